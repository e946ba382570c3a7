"""Growth rules: where a walker that reached ice leaves its crystal (docs/method.md, fern rules 1-2).

`FrostSim` asks its growth rule, once per tick, which of the walkers within hc of ice
become crystals, where, and which go back to the pool; it hands the rule the walkers'
positions, the ice skeleton (read only) and the freezing index, nothing else. `PaperGrowth` is Sec. 3.4.3 as
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
  blocked, and from session version 9 so is one whose crystal would list a cell past
  CELL_CAP (sim/core/budget.py); the hit still counts and the next one tries again.
- Walkers whose hit only counted are not frozen: the simulation places them again.
- (Session version 5 on, `pooled_first`.) Until a seed that a touch brought a ring of
  water has its first child, its hits count together, whatever their slots: the hit that
  brings the seed's count to its tip need grows its own slot. The ring's hits spread over
  six slots, and a seed near older ice, whose ring that ice cut, often never reached the
  need on any one of them (docs/method.md, 5.3). Up to version 7 only a touch joining an
  area brings a ring; one opening an area, pooled without a ring, had its first arm early
  and alone (a lone touch's six-fold order S6 0.53 -> 0.33). From version 8 it brings one
  too (its arms come early and together). The pane's seeds count slot by slot: pooled,
  the window's stems grew shorter (stem_lw 76.8 -> 72.8 px).

Per-crystal state lives in arrays parallel to the simulation's crystals.
"""

from __future__ import annotations

import numpy as np

from ..core.budget import room_for
from ..core.buffers import Growable, runs
from ..index.periodic import nearest_image, wrap_points
from ..params import Params
from .fronds import make_fronds

SIXTH = np.pi / 3  # 60 degrees between a crystal's axes
SLOTS = 6
TIP, SIDE, CLOSED = 0, 1, 2
# A non-seed crystal's slots relative to its own axis: straight on, +60, +120, back, -120, -60.
SLOT_KIND = np.array([TIP, SIDE, CLOSED, CLOSED, CLOSED, SIDE])
# A blocked slot keeps counting its hits: capped, so the count never overflows.
HITS_CAP = 1 << 20


class PaperGrowth:
    """Sec. 3.4.3: every walker within hc freezes where it is, linked to the nearest crystal."""

    def add_seeds(self, n: int, ringed=None) -> None:
        pass

    def settle(self, walkers: np.ndarray, hits: np.ndarray, parents: np.ndarray, ice, index):
        """(growing walkers, their parents, new crystal positions, walkers to place again)
        for walkers `hits` at `walkers` (len(hits) x 2) within hc of crystals `parents`."""
        return hits, parents, walkers, hits[:0]

    def melted(self, dead: np.ndarray, parents: np.ndarray, orphans: np.ndarray,
               edge: np.ndarray) -> None:
        pass

    def nbytes(self) -> int:
        return 0

    def chilled(self, params: Params) -> None:
        """The paper's rule counts no hits: the temperature changes nothing."""


class FernGrowth:
    """Grains and hit counters (see module doc) over per-crystal arrays."""

    def __init__(self, params: Params, rng: np.random.Generator, pooled_first: bool = True,
                 capped: bool = False):
        self.rng = rng
        self.pooled_first = pooled_first
        self.capped = capped  # version 9: a spot that would overfill a cell is blocked
        self.L = float(params.hc)
        self._apart_squared = np.float32(self.L / 2) ** 2  # (a new crystal's least gap to ice, squared)
        self.drift = np.deg2rad(params.drift)
        self.gap = params.side_gap
        # Hits a slot needs, by kind; a closed slot never grows.
        self.need = np.array([params.tip_hits, params.side_hits, -1])
        self.axis = Growable(np.float64)  # radians: direction of slot 0
        self.slot = Growable(np.int8)  # which slot of its parent holds each crystal (-1 none)
        self.seed = Growable(bool)  # a seed: six tip slots
        self.ringed = Growable(bool)  # a touch's seed with a ring of water: first hits pooled
        self.child = Growable(np.int32, (SLOTS,))  # each slot's child, -1 if empty
        self.hits = Growable(np.int32, (SLOTS,))
        self.order = Growable(np.int8)  # branch order (frond rule 1)
        self._any_ringed = False  # a ringed seed was ever added (else none is fresh)
        self.fronds = make_fronds(params)

    # ---- hooks called by FrostSim ---------------------------------------------------

    def add_seeds(self, n: int, ringed=None) -> None:
        """New seeds: each draws its grain's orientation in [0, 60) degrees. `ringed` (one
        flag each; default none) marks the seeds a touch brought a ring of water, whose
        first hits count together (with `pooled_first`)."""
        ringed = np.zeros(n, bool) if ringed is None else np.asarray(ringed, bool)
        self._any_ringed |= bool(ringed.any())
        self._append(self.rng.random(n) * SIXTH, np.full(n, -1, np.int8), np.ones(n, bool),
                     ringed=ringed)

    def settle(self, walkers: np.ndarray, hits: np.ndarray, parents: np.ndarray, ice, index):
        """(growing walkers, their parents, new crystal positions, walkers to place again)
        for walkers `hits` at `walkers` within hc of crystals `parents` of the skeleton
        `ice` (read only); `index` answers where the ice is."""
        if len(hits) == 0:
            return hits, parents, np.empty((0, 2), np.float32), hits
        at = ice.crystals.raw()[parents]
        k, need = self._slots(walkers, at, parents, index)
        cand = self._count(parents, k, need).nonzero()[0]
        if len(cand) == 0:  # most ticks: every hit only counts
            return hits[:0], parents[:0], np.empty((0, 2), np.float32), hits
        pc, kc = parents[cand], k[cand]
        side = (SLOT_KIND[kc] == SIDE) & ~self.seed.raw()[pc]  # side slots (a seed has none)
        angle = self.axis.raw()[pc] + kc * SIXTH
        pts = self._spots(at[cand], angle, index)
        ok = self._free(pts, pc, kc, side, ice.parents.raw(), index)
        if np.count_nonzero(ok) > 1:
            ok[ok] = _first_apart(pts[ok], self.L / 2)
        if self.capped and ok.any():  # (the cap was checked at the walker, not the spot)
            ok[ok] = room_for(index.candidates, index.grid, pts[ok], index.hc)
        grow = cand[ok]
        self._adopt(ice.crystals.n, pc[ok], kc[ok], side[ok], angle[ok])
        counted = np.empty(len(hits), bool)
        counted.fill(True)
        counted[grow] = False
        return hits[grow], pc[ok], pts[ok], hits[counted]

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

    def chilled(self, params: Params) -> None:
        """The hits a slot needs from now on: `params`' (the weather's, `window_mode.chill`);
        the hits counted so far are kept."""
        self.need = np.array([params.tip_hits, params.side_hits, -1])

    def nbytes(self) -> int:
        return sum(b.nbytes() for b in (self.axis, self.slot, self.seed, self.ringed, self.child,
                                         self.hits, self.order))

    # ---- steps of settle ------------------------------------------------------------

    def _slots(self, walkers, at, parents, index):
        """Each hit's slot (nearest axis to the walker's direction from its crystal, at
        `at`) and the hits it needs."""
        c = at.astype(np.float64)
        d = walkers - c
        dx, dy = d[:, 0], d[:, 1]
        if index.grid.period is not None:  # a tile: the walker may be across an edge
            dx, dy = nearest_image(dx, index.width), nearest_image(dy, index.height)
        turn = (np.arctan2(dy, dx) - self.axis.raw()[parents]) / SIXTH
        k = np.rint(turn).astype(np.int64) % SLOTS
        kind = np.where(self.seed.raw()[parents], TIP, SLOT_KIND[k])
        if not self.fronds.on:
            return k, self.need[kind]
        return k, self.fronds.need((index.width, index.height), self.order.raw()[parents],
                                   kind == SIDE, self.need[kind], c)

    def _count(self, parents, k, need) -> np.ndarray:
        """Count the hits on open, empty slots in walker order; True for the hit that
        reaches the slot's need (or the first, once an earlier attempt was blocked)."""
        child = self.child.raw()
        open_ = (need > 0) & (child[parents, k] < 0)
        slot = k
        if self.pooled_first and self._any_ringed:  # a seed's hits count together until it grows
            slot = np.where(self._fresh(parents), 0, k)
        key = np.where(open_, parents * SLOTS + slot, -1)
        flat = self.hits.raw().reshape(-1)
        order = key.argsort(kind="stable")
        skey = key[order]
        _, last, in_run = runs(skey)
        rank = np.empty(len(key), np.int64)
        rank[order] = in_run
        before = flat[np.maximum(key, 0)]
        due = open_ & (rank == np.maximum(need - before - 1, 0))
        last &= skey >= 0  # each open slot hit: its key (ascending) and its hits
        slots, hits = skey[last], in_run[last] + 1
        flat[slots] = np.minimum(flat[slots] + hits, HITS_CAP)
        return due

    def _spots(self, at, angle, index) -> np.ndarray:
        """One hc from each parent (at `at`) along `angle` (float64 arithmetic, stored
        float32)."""
        c = at.astype(np.float64)
        pts = np.empty((len(c), 2), np.float32)
        pts[:, 0], pts[:, 1] = c[:, 0] + self.L * np.cos(angle), c[:, 1] + self.L * np.sin(angle)
        return wrap_points(pts, index.grid.period and (index.width, index.height))

    def _free(self, pts, parents, k, side, parent, index) -> np.ndarray:
        """Spots on the screen, at least hc / 2 from the ice of the tick's start, and (side
        slots, where `side`) clear of same-side branches along the stem (`parent`: every
        crystal's)."""
        x, y = pts[:, 0], pts[:, 1]
        ok = (x >= 0) & (x < index.width) & (y >= 0) & (y < index.height)
        if ok.all():  # (the usual case)
            ok = index.nearest_d2(pts) >= self._apart_squared
        else:
            ok[ok] = index.nearest_d2(pts[ok]) >= self._apart_squared
        side = ok & side
        if self.gap > 1 and side.any():
            ok[side] = self.gap_clear(parents[side], k[side], parent)
        return ok

    def gap_clear(self, crystals, k, parent) -> np.ndarray:
        """No side child in slot k within side_gap - 1 links up or down the stem of each
        of `crystals` (`parent`: every crystal's parent)."""
        return gap_clear(self.child.raw(), self.slot.raw(), self.gap, crystals, k, parent)

    def _fresh(self, crystals) -> np.ndarray:
        """Ringed seeds with no child yet."""
        return self.ringed.raw()[crystals] & (self.child.raw()[crystals] < 0).all(axis=1)

    def _adopt(self, first: int, parents, k, side, angle) -> None:
        """The growing slots take the new crystals first, first + 1, ...; each child's axis
        turns from its link by the drift draw; a side slot's child (`side`) is one branch
        order up. A seed's first child clears the count its hits kept together."""
        if self.pooled_first and self._any_ringed:
            self.hits.raw()[parents[self._fresh(parents)]] = 0
        self.child.raw()[parents, k] = np.arange(first, first + len(parents), dtype=np.int32)
        turn = self.rng.standard_normal(len(parents)) * self.drift
        order = self.order.raw()[parents] + side
        self._append(angle + turn, k.astype(np.int8), np.zeros(len(parents), bool),
                     np.minimum(order, 127).astype(np.int8))

    def _append(self, axis, slot, seed, order=None, ringed=None) -> None:
        n = len(axis)
        self.axis.append(axis)
        if ringed is None:
            self.ringed.append_fill(n, False)
        else:
            self.ringed.append(ringed)
        if order is None:
            self.order.append_fill(n, 0)
        else:
            self.order.append(order)
        self.slot.append(slot)
        self.seed.append(seed)
        self.child.append_fill(n, -1)
        self.hits.append_fill(n, 0)


def _first_apart(pts: np.ndarray, gap: float) -> np.ndarray:
    """Greedy in order: keep each point unless it is closer than `gap` to a kept one."""
    keep = np.ones(len(pts), bool)
    if len(pts) < 2:
        return keep
    p = pts.astype(np.float64)
    near = np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1]) < gap
    at = np.arange(len(p))
    near &= at[None, :] < at[:, None]  # only an earlier point can take a later one's place
    if not near.any():
        return keep
    for i in near.any(axis=1).nonzero()[0]:
        if keep[i] and near[i, :i][keep[:i]].any():
            keep[i] = False
    return keep


def make_growth(params: Params, rng: np.random.Generator, pooled_first: bool = True,
                capped: bool = False):
    return FernGrowth(params, rng, pooled_first, capped) if params.grains else PaperGrowth()


def gap_clear(child: np.ndarray, slot: np.ndarray, gap: int, crystals, k, parent) -> np.ndarray:
    """FernGrowth.gap_clear over its arrays: `child` (a crystal's child in each slot, -1
    none), `slot` (the slot each crystal fills) and `gap` (side_gap)."""
    clear = np.empty(len(crystals), bool)
    clear.fill(True)
    up, down = crystals, crystals
    for step in range(gap - 1):
        if step == 0:  # (the crystals themselves: all real)
            up = np.where(slot[up] == 0, parent[up], -1)
            down = child[down, 0]
        else:
            stem = (up >= 0) & (slot[np.maximum(up, 0)] == 0)
            up = np.where(stem, parent[np.maximum(up, 0)], -1)
            down = np.where(down >= 0, child[np.maximum(down, 0), 0], -1)
        for ring in (up, down):
            clear &= ~((ring >= 0) & (child[np.maximum(ring, 0), k] >= 0))
    return clear
