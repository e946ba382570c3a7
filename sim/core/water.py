"""The walkers: one pool of water particles, structure of arrays, each in one active area."""

from __future__ import annotations

import numpy as np

from .buffers import Growable


class Water:
    """x, y (px, float32) and area (int32) of every walker, in array order (oldest first)."""

    def __init__(self, capacity: int):
        self.x = Growable(np.float32, capacity=capacity)
        self.y = Growable(np.float32, capacity=capacity)
        self.area = Growable(np.int32, capacity=capacity)

    @property
    def n(self) -> int:
        return self.x.n

    def append(self, x: np.ndarray, y: np.ndarray, area: np.ndarray) -> None:
        self.x.append(x)
        self.y.append(y)
        self.area.append(area)

    def keep(self, keep: np.ndarray) -> None:
        """Keep the walkers where `keep` (their order stays)."""
        for buf in (self.x, self.y, self.area):
            buf.keep(keep)

    def drop(self, *idx: np.ndarray) -> None:
        """Remove the walkers at the indices of `idx`."""
        keep = np.empty(self.x.n, bool)
        keep.fill(True)
        for i in idx:
            keep[i] = False
        self.keep(keep)

    def drop_before(self, drop: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Remove walkers `drop`; returns the new indices of walkers `idx` (kept ones)."""
        keep = np.ones(self.x.n, bool)
        keep[drop] = False
        self.keep(keep)
        return np.searchsorted(np.flatnonzero(keep), idx)

    def set(self, xy: np.ndarray, area: np.ndarray) -> None:
        """Replace every walker by walkers at `xy` (n x 2) in `area` (n)."""
        self.keep(np.zeros(self.x.n, bool))
        self.append(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]),
                    np.ascontiguousarray(area))

    def at(self, idx: np.ndarray) -> np.ndarray:
        """len(idx) x 2 positions of walkers `idx`."""
        out = np.empty((len(idx), 2), np.float32)
        out[:, 0], out[:, 1] = self.x.raw()[idx], self.y.raw()[idx]
        return out

    def move(self, idx: np.ndarray, x: np.ndarray, y: np.ndarray) -> None:
        self.x.raw()[idx] = x
        self.y.raw()[idx] = y

    def buffers(self) -> tuple[Growable, ...]:
        return (self.x, self.y, self.area)
