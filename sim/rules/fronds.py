"""Fronds (docs/method.md, section 8): how many hits a slot needs under frond rules 1 and 4.

- Branch order (rule 1): a crystal grown from a side slot of a non-seed crystal has its
  parent's order + 1, straight-on growth keeps it, a seed's stems are order 0 (the growth
  rule keeps the orders). A slot needs its hits x `order_hits`^order, and crystals of
  order `max_order` or more grow no side branches: a main stem outgrows its side branches,
  which outgrow theirs, the hierarchy of a feather.
- Colder frame (rule 4): hits divided by 1 + `frame_chill` x e^(-d / FRAME_PX), d the
  crystal's distance to the screen's edge: a denser, more granular band along the frame.

Either way the count is rounded and at least 1. Rules 2 and 3 (where water lands) are in
sim/rules/openglass.py.
"""

from __future__ import annotations

import numpy as np

from ..params import Params

# Decay length of the frame's chill, px: a prototype's 150.
FRAME_PX = 150.0


class NoFronds:
    """Every order and every spot alike: the hit counts as the parameters give them."""

    on = False

    def need(self, size, order, side, need: np.ndarray, at) -> np.ndarray:
        return need


class Fronds:
    """Rules 1 and 4 over the growth rule's per-crystal orders (see module doc)."""

    on = True

    def __init__(self, params: Params):
        self.order_hits = float(params.order_hits)
        self.max_order = params.max_order
        self.frame_chill = float(params.frame_chill)

    def need(self, size: tuple[int, int], order: np.ndarray, side: np.ndarray,
             need: np.ndarray, at: np.ndarray) -> np.ndarray:
        """Hits each slot needs: `need` (its kind's count, -1 closed) for slots of crystals
        of branch `order` at positions `at`; `side` marks side slots of non-seeds."""
        scale = np.ones(len(need))
        if self.order_hits != 1.0:
            scale *= self.order_hits ** order.astype(np.float64)
        if self.frame_chill:
            scale /= 1.0 + self.frame_chill * np.exp(-edge_distance(at, size) / FRAME_PX)
        out = np.maximum(1, np.rint(need * scale)).astype(need.dtype)
        closed = need <= 0
        if self.max_order:
            closed |= side & (order >= self.max_order)
        return np.where(closed, -1, out)


def edge_distance(pts: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Each point's distance to the nearest edge of a width x height screen, px."""
    p = pts.astype(np.float64)
    w, h = size
    return np.minimum(np.minimum(p[:, 0], w - p[:, 0]), np.minimum(p[:, 1], h - p[:, 1]))


def make_fronds(params: Params) -> NoFronds | Fronds:
    on = params.order_hits != 1.0 or params.max_order or params.frame_chill
    return Fronds(params) if on else NoFronds()
