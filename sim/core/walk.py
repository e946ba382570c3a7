"""The walk (Eq. 2, Sec. 3.4.2): displacements, long jumps, and who left its area."""

from __future__ import annotations

import numpy as np

from ..index.periodic import nearest_image, wrap_into
from .placement import TWO_PI


def walk_displacements(rng: np.random.Generator, m: int, step: float,
                       jump: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 2: each walker moves a*(cos t, sin t), a ~ U[0, step], t ~ U[0, 2 pi).
    A walker whose clearance `jump[i]` exceeds the step jumps that far instead (long jumps)."""
    u = rng.random((2, m), dtype=np.float32)
    a = u[0] * np.float32(step)
    if jump is not None:
        a = np.where(jump > step, jump, a)
    theta = u[1] * TWO_PI
    return a * np.cos(theta), a * np.sin(theta)


def walk_water(rng: np.random.Generator, x: np.ndarray, y: np.ndarray, columns, step: float,
               jump: np.ndarray | None, size: tuple[int, int], wrap: bool) -> np.ndarray:
    """One walk (Eq. 2) of the walkers at (x, y), moved in place, each in its own area
    (`columns`: centre x, centre y, outer radius); on a tile (`wrap`) a walker leaving one
    edge comes in at the opposite one. Returns the indices of those that left their area."""
    dx, dy = walk_displacements(rng, len(x), step, jump)
    x += dx
    y += dy
    if wrap:
        x[:], y[:] = wrap_into(x, size[0]), wrap_into(y, size[1])
    return outside(x, y, columns, size, wrap).nonzero()[0]


def clearance_jumps(clearance, x: np.ndarray, y: np.ndarray, columns) -> np.ndarray:
    """Long jumps: the clearance of walkers at (x, y) within their own areas (`columns`)."""
    cx, cy, r = columns
    return clearance.radii(x, y, r - np.hypot(x - cx, y - cy))


def outside(x: np.ndarray, y: np.ndarray, centre_r, size: tuple[int, int],
            wrap: bool) -> np.ndarray:
    """Walkers at (x, y) off a `size` screen or outside their own active area (centre x,
    centre y, outer radius: `centre_r`); on a tile (`wrap`) an area reaches across edges."""
    cx, cy, r = centre_r
    ox, oy = x - cx, y - cy
    if wrap:
        ox, oy = nearest_image(ox, size[0]), nearest_image(oy, size[1])
    out = ox * ox + oy * oy > r * r
    if not wrap and np.ndim(r) == 0 and min(cx - r, cy - r, size[0] - cx - r, size[1] - cy - r) >= 1:
        return out  # one area whose disc lies a pixel inside the screen: off it is outside the disc
    return out | (x < 0) | (x >= size[0]) | (y < 0) | (y >= size[1])


def on_screen_f32(pts: np.ndarray, width: int, height: int) -> np.ndarray:
    """On-screen float64 points as float32, still on the screen: x = 759.99999999 would
    round up to 760.0, off a 760 px screen, so it becomes the largest float32 below 760."""
    edge = np.nextafter(np.array([width, height], np.float32), np.float32(0))
    return np.minimum(pts.astype(np.float32), edge)
