"""Measures of a frost skeleton's shape, for the benchmark and the tests (docs/method.md, fern growth).

- mass-radius dimension: slope of log N(<r) on log r, r from 2 hc to 0.8 of the farthest
  crystal (off-lattice DLA: 1.71; a filled disc: 2);
- six-fold order S6 = |mean exp(6 i theta)| over link angles theta (0: no preferred axes);
- turns: each link's angle from its parent's link, as shares straight on (within 10
  degrees), at +-60 and at +-120 degrees.
"""

from __future__ import annotations

import numpy as np

TURN_TOLERANCE = 10.0  # degrees


def extent(crystals: np.ndarray, centre) -> float:
    """Distance of the farthest crystal from `centre`, px."""
    if len(crystals) == 0:
        return 0.0
    c = crystals.astype(np.float64)
    return float(np.hypot(c[:, 0] - centre[0], c[:, 1] - centre[1]).max())


def mass_radius_dimension(crystals: np.ndarray, centre, hc: float, samples: int = 20) -> float:
    """Slope of log N(<r) on log r for r log-spaced from 2 hc to 0.8 * extent (nan if
    the cluster is smaller than that range)."""
    c = crystals.astype(np.float64)
    d = np.sort(np.hypot(c[:, 0] - centre[0], c[:, 1] - centre[1]))
    top = 0.8 * d[-1] if len(d) else 0.0
    if top <= 2 * hc * 1.5:
        return float("nan")
    r = np.geomspace(2 * hc, top, samples)
    n = np.searchsorted(d, r, side="left")
    return float(np.polyfit(np.log(r), np.log(n), 1)[0])


def link_angles(crystals: np.ndarray, parents: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(child indices, angle of each child's link from its parent, radians)."""
    child = np.flatnonzero(parents >= 0)
    c = crystals.astype(np.float64)
    d = c[child] - c[parents[child]]
    return child, np.arctan2(d[:, 1], d[:, 0])


def six_fold_order(crystals: np.ndarray, parents: np.ndarray) -> float:
    """S6 = |mean exp(6 i theta)| over every link's angle theta."""
    _, theta = link_angles(crystals, parents)
    return float(np.abs(np.exp(6j * theta).mean())) if len(theta) else float("nan")


def turn_shares(crystals: np.ndarray, parents: np.ndarray) -> dict[str, float]:
    """Shares of links (whose parent has a link itself) turning 0, +-60, +-120 degrees
    from their parent's link, each within TURN_TOLERANCE."""
    child, theta = link_angles(crystals, parents)
    angle = np.full(len(parents), np.nan)
    angle[child] = theta
    before = angle[parents[child]]
    has = np.isfinite(before)
    turn = np.degrees(np.angle(np.exp(1j * (theta[has] - before[has]))))
    a = np.abs(turn)
    if len(a) == 0:
        return {"straight": float("nan"), "60": float("nan"), "120": float("nan")}
    return {"straight": float((a <= TURN_TOLERANCE).mean()),
            "60": float((np.abs(a - 60) <= TURN_TOLERANCE).mean()),
            "120": float((np.abs(a - 120) <= TURN_TOLERANCE).mean())}
