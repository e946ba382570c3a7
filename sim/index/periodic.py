"""Wrap-around helpers for tiles (`frost maps --tile`): a `width` x `height` frost whose
left edge continues at its right and its top at its bottom, so its maps repeat seamlessly.

A point's place on the tile is taken modulo the size; the offset between two points is the
shortest one over the wrap (the minimum image), so a crystal near one edge is found from
across it; a triangle that crosses an edge is drawn again shifted by the size, so the part
that leaves one side shows on the other.
"""

from __future__ import annotations

import numpy as np


def wrap_into(v: np.ndarray, size: float) -> np.ndarray:
    """float32 coordinates taken into [0, size): -0.25 on a 64 px tile is 63.75 (the
    float32 rounding of a value just below 0 to `size` itself is taken down to 0)."""
    out = np.mod(np.asarray(v, np.float32), np.float32(size))
    return np.where(out >= np.float32(size), np.float32(0), out).astype(np.float32)


def nearest_image(d: np.ndarray, size) -> np.ndarray:
    """An offset (one axis) as the shortest over the wrap: in [-size/2, size/2]."""
    return d - size * np.round(d / size)


def image_near(p: np.ndarray, q: np.ndarray, size: tuple[int, int] | None) -> np.ndarray:
    """Points p (n x 2) moved to their image nearest q (n x 2), e.g. a parent beside its
    child across an edge, so the link between them is short; p itself without a size."""
    if size is None:
        return p
    period = np.array(size, np.float64)
    d = np.asarray(q, np.float64) - np.asarray(p, np.float64)
    return (np.asarray(q, np.float64) - nearest_image(d, period)).astype(p.dtype)


def wrap_points(pts: np.ndarray, size: tuple[int, int] | None) -> np.ndarray:
    """n x 2 float32 points taken onto the tile (unchanged without a size)."""
    if size is None:
        return pts
    return np.column_stack((wrap_into(pts[:, 0], size[0]), wrap_into(pts[:, 1], size[1])))


def wrap_triangles(verts: np.ndarray, width: int, height: int) -> np.ndarray:
    """Feature vertices (3 rows a triangle) with a copy of every triangle that reaches past
    an edge, shifted by the size across it (corners get both shifts): the renderer draws
    what its screen shows of each copy."""
    if len(verts) == 0:
        return verts
    tri = verts.reshape(-1, 3, verts.shape[1])
    lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
    copies = [tri]
    for sx in (-width, 0, width):
        for sy in (-height, 0, height):
            if sx == 0 and sy == 0:
                continue
            # The shifted copy shows only where it lands on the screen.
            meets = ((lo[:, 0] + sx < width) & (hi[:, 0] + sx > 0)
                     & (lo[:, 1] + sy < height) & (hi[:, 1] + sy > 0))
            if meets.any():
                moved = tri[meets].copy()
                moved[:, :, 0] += sx
                moved[:, :, 1] += sy
                copies.append(moved)
    return np.concatenate(copies).reshape(-1, verts.shape[1]).astype(verts.dtype)
