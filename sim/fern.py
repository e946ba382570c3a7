"""Growth rules: where a walker that reached ice leaves its crystal (docs/method.md, fern rules 1-2).

`FrostSim` asks its growth rule, once per tick, which of the walkers within hc of ice
become crystals, where, and which go back to the pool. `PaperGrowth` is Sec. 3.4.3 as
written: every one freezes where it is. `FernGrowth` adds grains and hit counters:

- Each seed draws an orientation in [0, 60) degrees; a crystal has six slots, its axis
  plus k * 60 degrees. A hit counts for the slot nearest the walker's direction from the
  crystal. A seed's six slots are tips; any other crystal grows only straight on (slot 0,
  a tip) and at +-60 degrees (slots 1 and 5, side slots): ice dendrites branch along the
  a-axes, never backwards.
- A slot grows its child on its `tip_hits`-th (or `side_hits`-th) hit, one hc along the
  slot's axis; the child's axes turn from that link by a normal draw of `drift` degrees.
  A slot holds one child. A spot closer than hc / 2 to ice, off the screen, or (for a
  side slot) within `side_gap` - 1 links of a side branch on the same side of its stem is
  blocked; the hit still counts and the next one tries again.
- Walkers whose hit only counted are not frozen: the simulation places them again.
- (Session version 5 on, `pooled_first`.) Until a seed has its first child, its hits
  count together, whatever their slots: the hit that brings the seed's count to its
  tip need grows its own slot. A touch's ring of water spread its hits over six slots,
  and a seed near older ice, whose ring that ice cut, often never reached the need on
  any one of them (docs/method.md, 5.3).

Per-crystal state lives in arrays parallel to the simulation's crystals.
"""

from __future__ import annotations

import numpy as np

from .buffers import Growable
from .fronds import make_fronds
from .params import Params
from .periodic import nearest_image, wrap_points

SIXTH = np.pi / 3  # 60 degrees between a crystal's axes
SLOTS = 6
TIP, SIDE, CLOSED = 0, 1, 2
# A non-seed crystal's slots relative to its own axis: straight on, +60, +120, back, -120, -60.
SLOT_KIND = np.array([TIP, SIDE, CLOSED, CLOSED, CLOSED, SIDE])


class PaperGrowth:
    """Sec. 3.4.3: every walker within hc freezes where it is, linked to the nearest crystal."""

    def add_seeds(self, n: int) -> None:
        pass

    def settle(self, sim, hits: np.ndarray, parents: np.ndarray):
        """(growing walkers, their parents, new crystal positions, walkers to place again)."""
        pts = np.column_stack((sim._wx.raw()[hits], sim._wy.raw()[hits]))
        return hits, parents, pts, hits[:0]

    def melted(self, dead: np.ndarray, parents: np.ndarray, orphans: np.ndarray,
               edge: np.ndarray) -> None:
        pass

    def nbytes(self) -> int:
        return 0


class FernGrowth:
    """Grains and hit counters (see module doc) over per-crystal arrays."""

    def __init__(self, params: Params, rng: np.random.Generator, pooled_first: bool = True):
        self.rng = rng
        self.pooled_first = pooled_first
        self.L = float(params.hc)
        self.drift = np.deg2rad(params.drift)
        self.gap = params.side_gap
        # Hits a slot needs, by kind; a closed slot never grows.
        self.need = np.array([params.tip_hits, params.side_hits, -1])
        self.axis = Growable(np.float64)  # radians: direction of slot 0
        self.slot = Growable(np.int8)  # which slot of its parent holds each crystal (-1 none)
        self.seed = Growable(bool)  # a seed: six tip slots
        self.child = Growable(np.int32, (SLOTS,))  # each slot's child, -1 if empty
        self.hits = Growable(np.int32, (SLOTS,))
        self.order = Growable(np.int8)  # branch order (frond rule 1)
        self.fronds = make_fronds(params)

    # ---- hooks called by FrostSim ---------------------------------------------------

    def add_seeds(self, n: int) -> None:
        """New seeds: each draws its grain's orientation in [0, 60) degrees."""
        self._append(self.rng.random(n) * SIXTH, np.full(n, -1, np.int8), np.ones(n, bool))

    def settle(self, sim, hits: np.ndarray, parents: np.ndarray):
        """(growing walkers, their parents, new crystal positions, walkers to place again)."""
        if len(hits) == 0:
            return hits, parents, np.empty((0, 2), np.float32), hits
        k, need = self._slots(sim, hits, parents)
        cand = np.flatnonzero(self._count(parents, k, need))
        if len(cand) == 0:  # most ticks: every hit only counts
            return hits[:0], parents[:0], np.empty((0, 2), np.float32), hits
        angle = self.axis.raw()[parents[cand]] + k[cand] * SIXTH
        pts = self._spots(sim, parents[cand], angle)
        ok = self._free(sim, pts, parents[cand], k[cand])
        ok[ok] = _first_apart(pts[ok], self.L / 2)
        grow = cand[ok]
        self._adopt(sim._crystals.n, parents[grow], k[grow], angle[ok])
        counted = np.ones(len(hits), bool)
        counted[grow] = False
        return hits[grow], parents[grow], pts[ok], hits[counted]

    def melted(self, dead: np.ndarray, parents: np.ndarray, orphans: np.ndarray,
               edge: np.ndarray) -> None:
        """A melted crystal frees its parent's slot (whose count starts over); its own
        slots and counters go with it; its children become roots of no slot. The live
        crystals at the melt's `edge` open all six slots, as a seed's: their closed
        slots (+-120 degrees, back) often face the clearing, which then never refroze."""
        p = parents[dead]
        has = p >= 0
        slot = self.slot.raw()[dead[has]]
        self.child.raw()[p[has], slot] = -1
        self.hits.raw()[p[has], slot] = 0
        self.child.raw()[dead] = -1
        self.hits.raw()[dead] = 0
        self.slot.raw()[orphans] = -1
        if not self.fronds.on:
            self.seed.raw()[edge] = True
        # Fronds (docs/method.md, 8): the edge keeps its own slots, whose stems then grow on
        # across the clearing (six open slots each sprouted a stub: a band of stubs), and
        # goes back to branch order 0 (else a wipe regrew as a few high-order stubs).
        self.order.raw()[edge] = 0

    def nbytes(self) -> int:
        return sum(b.nbytes() for b in (self.axis, self.slot, self.seed, self.child, self.hits,
                                         self.order))

    # ---- steps of settle ------------------------------------------------------------

    def _slots(self, sim, hits, parents):
        """Each hit's slot (nearest axis to the walker's direction) and the hits it needs."""
        c = sim._crystals.raw()[parents].astype(np.float64)
        dx = sim._wx.raw()[hits] - c[:, 0]
        dy = sim._wy.raw()[hits] - c[:, 1]
        if sim.grid.period is not None:  # a tile: the walker may be across an edge
            dx, dy = nearest_image(dx, sim.width), nearest_image(dy, sim.height)
        turn = (np.arctan2(dy, dx) - self.axis.raw()[parents]) / SIXTH
        k = np.rint(turn).astype(np.int64) % SLOTS
        kind = np.where(self.seed.raw()[parents], TIP, SLOT_KIND[k])
        if not self.fronds.on:
            return k, self.need[kind]
        return k, self.fronds.need((sim.width, sim.height), self.order.raw()[parents],
                                   kind == SIDE, self.need[kind], c)

    def _count(self, parents, k, need) -> np.ndarray:
        """Count the hits on open, empty slots in walker order; True for the hit that
        reaches the slot's need (or the first, once an earlier attempt was blocked)."""
        child = self.child.raw()
        open_ = (need > 0) & (child[parents, k] < 0)
        slot = k
        if self.pooled_first:  # a seed's hits count together (in slot 0) until it grows
            slot = np.where(self._fresh(parents), 0, k)
        key = np.where(open_, parents * SLOTS + slot, -1)
        order = np.argsort(key, kind="stable")
        skey = key[order]
        start = np.concatenate(([0], np.flatnonzero(skey[1:] != skey[:-1]) + 1))
        rank = np.empty(len(key), np.int64)
        rank[order] = np.arange(len(key)) - np.repeat(start, np.diff(start, append=len(key)))
        flat = self.hits.raw().reshape(-1)
        before = flat[key.clip(0)]
        due = open_ & (rank == np.maximum(need - before - 1, 0))
        slots, hits = np.unique(key[open_], return_counts=True)
        # A blocked slot keeps counting: cap the count so it never overflows.
        flat[slots] = np.minimum(flat[slots] + hits, 1 << 20)
        return due

    def _spots(self, sim, parents, angle) -> np.ndarray:
        """One hc from each parent along `angle` (float64 arithmetic, stored float32)."""
        c = sim._crystals.raw()[parents].astype(np.float64)
        pts = np.column_stack((c[:, 0] + self.L * np.cos(angle),
                               c[:, 1] + self.L * np.sin(angle))).astype(np.float32)
        return wrap_points(pts, sim.grid.period and (sim.width, sim.height))

    def _free(self, sim, pts, parents, k) -> np.ndarray:
        """Spots on the screen, at least hc / 2 from the ice of the tick's start, and (side
        slots) clear of same-side branches along the stem."""
        x, y = pts[:, 0], pts[:, 1]
        ok = (x >= 0) & (x < sim.width) & (y >= 0) & (y < sim.height)
        ok[ok] = _nearest_d2(sim, pts[ok]) >= np.float32(self.L / 2) ** 2
        side = ok & (SLOT_KIND[k] == SIDE) & ~self.seed.raw()[parents]
        if self.gap > 1 and side.any():
            ok[side] = self._gap_clear(sim, parents[side], k[side])
        return ok

    def _gap_clear(self, sim, crystals, k) -> np.ndarray:
        """No side child in slot k within side_gap - 1 links up or down the stem."""
        clear = np.ones(len(crystals), bool)
        child, slot, parent = self.child.raw(), self.slot.raw(), sim._parents.raw()
        up, down = crystals.copy(), crystals.copy()
        for _ in range(self.gap - 1):
            stem = (up >= 0) & (slot[np.maximum(up, 0)] == 0)
            up = np.where(stem, parent[np.maximum(up, 0)], -1)
            down = np.where(down >= 0, child[np.maximum(down, 0), 0], -1)
            for ring in (up, down):
                clear &= ~((ring >= 0) & (child[np.maximum(ring, 0), k] >= 0))
        return clear

    def _fresh(self, crystals) -> np.ndarray:
        """Seeds with no child yet."""
        return self.seed.raw()[crystals] & (self.child.raw()[crystals] < 0).all(axis=1)

    def _adopt(self, first: int, parents, k, angle) -> None:
        """The growing slots take the new crystals first, first + 1, ...; each child's axis
        turns from its link by the drift draw. A seed's first child clears the count its
        hits kept together."""
        if self.pooled_first:
            self.hits.raw()[parents[self._fresh(parents)]] = 0
        self.child.raw()[parents, k] = np.arange(first, first + len(parents), dtype=np.int32)
        turn = self.rng.standard_normal(len(parents)) * self.drift
        side = (SLOT_KIND[k] == SIDE) & ~self.seed.raw()[parents]
        order = self.order.raw()[parents] + side
        self._append(angle + turn, k.astype(np.int8), np.zeros(len(parents), bool),
                     np.minimum(order, 127).astype(np.int8))

    def _append(self, axis, slot, seed, order=None) -> None:
        self.axis.append(axis)
        self.order.append(np.zeros(len(axis), np.int8) if order is None else order)
        self.slot.append(slot)
        self.seed.append(seed)
        self.child.append(np.full((len(axis), SLOTS), -1, np.int32))
        self.hits.append(np.zeros((len(axis), SLOTS), np.int32))


def _nearest_d2(sim, pts: np.ndarray) -> np.ndarray:
    """Squared distance from each point to the nearest live crystal listed in its cell
    (inf if none). Any crystal within hc of a point is listed in the point's cell."""
    d2 = np.full(len(pts), np.inf, np.float32)
    if len(pts) == 0:
        return d2
    counts, ids = sim.candidates.gather_flat(sim.grid.keys(pts[:, 0], pts[:, 1]))
    some = counts > 0
    if not some.any():
        return d2
    rows = np.repeat(np.arange(len(pts)), counts)
    c = sim._crystals.raw()[ids]
    dx, dy = c[:, 0] - pts[rows, 0], c[:, 1] - pts[rows, 1]
    if sim.grid.period is not None:  # a tile: over the wrap
        dx, dy = nearest_image(dx, sim.grid.period[0]), nearest_image(dy, sim.grid.period[1])
    e = dx ** 2 + dy ** 2
    starts = (np.cumsum(counts) - counts)[some]
    d2[some] = np.minimum.reduceat(e, starts)
    return d2


def _first_apart(pts: np.ndarray, gap: float) -> np.ndarray:
    """Greedy in order: keep each point unless it is closer than `gap` to a kept one."""
    keep = np.ones(len(pts), bool)
    if len(pts) < 2:
        return keep
    p = pts.astype(np.float64)
    near = np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1]) < gap
    np.fill_diagonal(near, False)
    for i in np.flatnonzero(near.any(axis=1)):
        if keep[i] and near[i, :i][keep[:i]].any():
            keep[i] = False
    return keep


def make_growth(params: Params, rng: np.random.Generator, pooled_first: bool = True):
    return FernGrowth(params, rng, pooled_first) if params.grains else PaperGrowth()
