"""Slow, obvious versions of what the production code does fast, for tests to compare with."""

from __future__ import annotations

import numpy as np

from sim.look.geometry import falloff


def bump_heights(points: np.ndarray, rows: int, cols: int, spacing: int,
                 radius: float, bump: float, cap: float) -> np.ndarray:
    """The capped height grid (Fig. 7) from all particles at once, vertex by vertex."""
    vy, vx = np.mgrid[0:rows, 0:cols].astype(np.float64) * spacing
    h = np.zeros((rows, cols))
    for x, y in points:
        h += bump * falloff(np.hypot(vx - x, vy - y), radius)
    return np.minimum(h, cap).astype(np.float32)


def feature_vertices(p, q, width: float = 1.5,
                     height: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Fig. 6 for one segment p -> q, as the figure draws it: the 5 points (p, q, m, s1, s2)
    as 5 x 3 and the 4 faces as index triples into them. m is the midpoint raised to
    height*L; s1, s2 = m -/+ width*L*n on the glass, n the unit perpendicular (-dy, dx)/L."""
    p, q = np.asarray(p, np.float64), np.asarray(q, np.float64)
    d = q - p
    length = float(np.hypot(d[0], d[1]))
    n = np.array([-d[1], d[0]]) / length if length > 0 else np.zeros(2)  # L = 0: s1 = s2 = m
    m = 0.5 * (p + q)
    s1, s2 = m - width * length * n, m + width * length * n
    xyz = np.array([[*p, 0.0], [*q, 0.0], [*m, height * length], [*s1, 0.0], [*s2, 0.0]])
    faces = np.array([[0, 3, 2], [3, 1, 2], [1, 4, 2], [4, 0, 2]])  # (p,s1,m) (s1,q,m) (q,s2,m) (s2,p,m)
    return xyz, faces
