"""The active areas (Sec. 3.4.2): where each pool's water lives and how far its ice reaches."""

from __future__ import annotations

import numpy as np

from .buffers import Growable, distinct


class Areas:
    """a rows of (centre x, centre y, outer radius, inner radius, reach of its ice) and
    each area's count of live crystals. Water lives in the annulus between the radii."""

    def __init__(self) -> None:
        self.rows = Growable(np.float32, (5,))
        self.ice = Growable(np.int32)  # live crystals of each area

    @property
    def n(self) -> int:
        return self.rows.n

    def open(self, row: np.ndarray) -> int:
        """A new area of one row (5 values); returns its index."""
        self.ice.append(np.zeros(1, np.int32))
        return self.rows.append(np.asarray(row, np.float32).reshape(1, 5)).start

    def areas_for(self, pts: np.ndarray, radius: float) -> np.ndarray:
        """The area of each touch in turn: the one whose disc holds it (nearest centre,
        lowest index among equals), else a new area of `radius` opened there."""
        out = np.empty(len(pts), np.int32)
        for k, (x, y) in enumerate(pts):
            a = self.rows.raw()
            d2 = (a[:, 0] - x) ** 2 + (a[:, 1] - y) ** 2
            inside = d2 <= a[:, 2] ** 2
            if inside.any():
                out[k] = np.argmin(np.where(inside, d2, np.inf))
                continue
            out[k] = self.open(np.array([x, y, radius, 0.0, 0.0], np.float32))
        return out

    def count_ice(self, area: np.ndarray, sign: int) -> None:
        """Crystals of `area` (one entry each) appear (sign 1) or melt (sign -1)."""
        ice = self.ice.raw()
        if len(ice) == 1:  # one area (a lone touch's)
            ice[0] += sign * len(area)
            return
        ice[:] += sign * np.bincount(area, minlength=len(ice)).astype(np.int32)

    def reach_to(self, area: np.ndarray, pts: np.ndarray) -> np.ndarray:
        """Widen each area's reach to the crystals `pts` of it; returns the areas touched."""
        rows = self.rows.raw()
        d = np.hypot(*(pts - rows[area, :2]).T)
        if len(rows) == 1:  # one area (a lone touch's)
            rows[0, 4] = max(rows[0, 4], d.max())
            return area[:1]
        np.maximum.at(rows[:, 4], area, d)
        return distinct(area)

    def ride(self, touched: np.ndarray, radius: float) -> None:
        """Growth mode: the annulus of `touched` rides on its ice front, half an active
        radius either side of the farthest crystal, so its water can still reach the ice."""
        rows = self.rows.raw()
        band = np.float32(radius / 2)
        reach = rows[touched, 4]
        rows[touched, 2] = np.maximum(radius, reach + band)
        rows[touched, 3] = np.maximum(0, reach - band)

    def columns(self, area: np.ndarray):
        """Centre x, centre y and outer radius of each walker's area (scalars for one area)."""
        rows = self.rows.raw()
        if len(rows) == 1:
            return rows[0, :3]
        # one column at a time: much cheaper than gathering rows
        return tuple(np.take(np.ascontiguousarray(rows[:, i]), area) for i in range(3))


def shell(a: np.ndarray, launch: float) -> tuple[np.ndarray, np.ndarray]:
    """Inner and outer radius water is placed between, for area rows `a`. With a launch
    circle (fern rule 4, `launch` > 0) both are `launch` px beyond the area's farthest
    ice, while that circle lies inside the area."""
    if not launch:
        return a[:, 3], a[:, 2]
    ring = a[:, 4] + np.float32(launch)
    on = ring < a[:, 2]
    return np.where(on, ring, a[:, 3]), np.where(on, ring, a[:, 2])
