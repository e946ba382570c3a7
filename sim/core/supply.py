"""The water supply: walkers placed, topped up within the budget, returned by melts, spent
by freezes, and the water a touch brings (Sec. 3.4.2; docs/method.md 5)."""

from __future__ import annotations

import numpy as np

from ..index.periodic import wrap_into
from . import budget
from .placement import CELL_TRIES, first_good_by_rounds, ring_spots

# Draws for each walker a touch brings to its ring (`Supply.water_seed`): a seed tucked in
# beside older ice is the nearest crystal to a sliver of its ring, where 8 draws placed 4
# of 48 walkers.
TOUCH_TRIES = 32
_NONE = np.empty(0, np.int64)


class Supply:
    """Keeps the walkers (`water`) of the areas (`areas`) supplied through `placer`; counts
    the water created, frozen and dropped."""

    def __init__(self, params, rng: np.random.Generator, water, areas, placer, pane,
                 index, touch_creates: bool, kept: bool = False):
        self.params, self.rng, self.water, self.areas = params, rng, water, areas
        self.placer, self.pane, self.index = placer, pane, index
        self.touch_creates, self.kept = touch_creates, kept
        self.created = self.frozen = self.dropped = 0
        # Version 14: walkers of each area that the tick's cell work cut (`Placer.take_cut`),
        # placed first in the next tick (`repay`): owed, never dropped.
        self.owed = np.zeros(0, np.int64)
        self._unplaced_owed = 0  # of the walkers relocate returned since `spent`, those owed

    @property
    def waiting(self) -> int:
        """Walkers owed to their areas, to be placed in a later tick."""
        return int(self.owed.sum())

    def _owed_of(self, n: int) -> np.ndarray:
        """The owed walkers of each of n areas (the owed list grows as areas open)."""
        if len(self.owed) < n:
            self.owed = np.concatenate((self.owed, np.zeros(n - len(self.owed), np.int64)))
        return self.owed

    def _owe(self, cut: np.ndarray) -> int:
        """Counts the walkers of areas `cut` (the placer's cut) as owed; returns how many."""
        if len(cut) == 0:
            return 0
        np.add.at(self._owed_of(self.areas.n), cut, 1)
        return len(cut)

    def repay(self, ice: tuple[int, int]) -> None:
        """Version 14, at a tick's start: the owed walkers are placed again, within the
        water budget (what the budget has no room for stays owed); those the cell work
        cuts again stay owed. An area whose ice all melted is owed nothing."""
        if not self.owed.any():
            return
        gone = self.areas.ice.raw()[:len(self.owed)] == 0  # (owed grows with the areas)
        gone |= self.placer.bare(len(self.owed), ice)
        self.dropped += int(self.owed[gone].sum())  # no glass left for them: the frost is done
        self.owed[gone] = 0
        areas = np.flatnonzero(self.owed)
        give = budget.given(self.owed[areas], max(0, self.params.water_budget - self.water.n))
        self.owed[areas] -= give
        self.spawn(np.repeat(areas.astype(np.int32), give), ice, repaid=True)

    def top_up(self, ice: tuple[int, int]) -> None:
        """Version 14, at a tick's end: a kept pool (replenish, growth mode) short of
        `humidity` (owed walkers counted in it) is topped up within the water budget,
        wherever its area still has ice: water a full cell or a failed placement took
        comes back while free glass remains. Nothing is trimmed from other pools."""
        n = self.areas.n
        if n == 0:
            return
        owed = self._owed_of(n)
        counts = np.bincount(self.water.area.raw(), minlength=n) + owed
        want = np.maximum(0, self.pane.pool(self.params.humidity) - counts)
        want[(self.areas.ice.raw() == 0) | self.placer.bare(n, ice)] = 0
        room = self.params.water_budget - self.water.n - int(owed.sum())
        if room <= 0 or not want.any():
            return
        areas = np.flatnonzero(want)
        self.spawn(np.repeat(areas.astype(np.int32), budget.given(want[areas], room)), ice)

    def spawn(self, area: np.ndarray, ice: tuple[int, int], repaid: bool = False) -> None:
        """Create water for `area[i]`; those with no free spot are dropped. From version
        14 (`kept`) the water the cell work cut is owed (created, waiting), water with no
        spot is not created, and `repaid` walkers (owed ones) were created already: those
        with no spot are dropped."""
        if len(area) == 0:
            return
        x, y, ok = self.placer.place(area, ice)
        self._born(area, x, y, ok, self._owe(self.placer.take_cut()), repaid)

    def relocate(self, idx: np.ndarray, ice: tuple[int, int]) -> np.ndarray:
        """Place walkers `idx` again in their areas; returns those with no free spot."""
        if len(idx) == 0:
            return idx
        x, y, ok = self.placer.place(self.water.area.raw()[idx], ice)
        return self._moved(idx, x, y, ok, self._owe(self.placer.take_cut()))

    def relocate_then_spawn(self, idx: np.ndarray, area: np.ndarray,
                            ice: tuple[int, int]) -> np.ndarray:
        """`relocate(idx)`, then `spawn(area)`: the same water in the same places, their
        placements made in one pass (`Placer.place_both`). Returns what relocate does."""
        if len(idx) == 0 or len(area) == 0:
            lost = self.relocate(idx, ice)
            self.spawn(area, ice)
            return lost
        (mx, my, mok), (bx, by, bok) = self.placer.place_both(self.water.area.raw()[idx], area, ice)
        born_cut = self._owe(self.placer.take_cut())
        lost = self._moved(idx, mx, my, mok, self._owe(self.placer.first_cut))
        self._born(area, bx, by, bok, born_cut)
        return lost

    def _born(self, area: np.ndarray, x: np.ndarray, y: np.ndarray, ok: np.ndarray, cut: int,
              repaid: bool = False) -> None:
        self.water.append(x[ok], y[ok], area[ok])
        placed = int(np.count_nonzero(ok))
        if not self.kept:
            self.created += placed
            self.dropped += len(ok) - placed
            return
        if repaid:
            self.dropped += len(ok) - placed - cut
        else:
            self.created += placed + cut

    def _moved(self, idx: np.ndarray, nx: np.ndarray, ny: np.ndarray, ok: np.ndarray,
               cut: int) -> np.ndarray:
        """Moves the placed walkers; returns those with no spot, for `spent` (those the
        cell work cut among them are owed, not dropped)."""
        if ok.all():
            self.water.move(idx, nx, ny)
            return idx[:0]
        self.water.move(idx[ok], nx[ok], ny[ok])
        self._unplaced_owed += cut
        return idx[~ok]

    def fill(self, areas: np.ndarray, ice: tuple[int, int]) -> None:
        """Top the pools of `areas` up to `humidity` within `water_budget`; when the budget
        is spent, the areas holding more than a fair share give theirs up first."""
        counts = np.bincount(self.water.area.raw(), minlength=self.areas.n)
        room = self.params.water_budget - self.water.n
        if self.kept:  # owed walkers are the pool's too
            owed = self._owed_of(self.areas.n)
            want_counts, room = counts + owed, room - int(owed.sum())
        else:
            want_counts = counts
        pool = self.pane.pool(self.params.humidity)
        want, share = budget.wanted(want_counts, areas, pool, self.params.water_budget, room)
        if share is not None:
            keep = budget.trim(counts, areas, int(want.sum()) - room, share,
                               self.water.area.raw())
            if keep is not None:
                self.water.keep(keep)
                room += int((~keep).sum())
                if self.kept:
                    self.dropped += int((~keep).sum())
        self.spawn(np.repeat(areas.astype(np.int32), budget.given(want, room)), ice)

    def returned(self, area: np.ndarray, ice: tuple[int, int]) -> None:
        """Melted crystals' water goes back to their areas, never above `humidity` nor
        the budget; an area with no ice left has nothing to grow on and loses its pool.
        A kept pool (replenish, growth, the pane) is topped up: in a frosted area it had
        drained for want of glass, and the melt made glass."""
        empty = self.areas.ice.raw() == 0
        if empty.any():
            kept = ~empty[self.water.area.raw()]
            self.water.keep(kept)
            if self.kept:  # version 14 counts them
                self.dropped += int((~kept).sum())
        if self.params.replenish or self.params.grow or self.pane.on:
            self.fill(np.unique(area[~empty[area]]), ice)
            return
        counts = np.bincount(self.water.area.raw(), minlength=self.areas.n)
        back = np.bincount(area[~empty[area]], minlength=self.areas.n)
        back = np.minimum(back, np.maximum(0, self.pane.pool(self.params.humidity) - counts))
        room = max(0, self.params.water_budget - self.water.n)
        self.spawn(np.repeat(np.arange(len(back), dtype=np.int32), back)[:room], ice)

    def spent(self, frozen: np.ndarray, dropped: np.ndarray = _NONE) -> None:
        """Frozen water is spent (the pool shrinks as ice grows); `dropped` water found no
        free spot to be placed again."""
        if len(frozen) == 0 and len(dropped) == 0:
            return
        self.frozen += len(frozen)
        self.dropped += len(dropped) - self._unplaced_owed
        self._unplaced_owed = 0
        self.water.drop(frozen, dropped)

    def water_seed(self, seed: tuple[float, float], area: int) -> None:
        """A touch into an area brings `touch_water` walkers to glass around its seed (at
        `seed`): uniform in the ring from hc to 2 hc, on the screen, at least hc / 2 from
        every live crystal, and where no crystal within hc (one it could freeze to) is
        nearer than the seed; those with no such spot in TOUCH_TRIES draws (CELL_TRIES
        before version 5) are not brought. Up to version 4 they were all the area's own
        walkers (drawn at random), so nothing was created; but a drained pool (an area
        whose launch circle lies on ice or off the screen finds no spot for its water) had
        nothing to bring, and a drag's next touch took back the last one's ring. From
        version 5, while the area's pool is short of `humidity` and `water_budget` has
        room, the touch brings new walkers of the area, and moves the area's own for the
        rest (docs/method.md, 5.3)."""
        want = self.params.touch_water
        mine = np.flatnonzero(self.water.area.raw() == area)
        new = 0
        if self.touch_creates:  # a pool short of `humidity` brings new ones, in the budget
            short = self.pane.pool(self.params.humidity) - len(mine)
            room = self.params.water_budget - self.water.n
            if self.kept:  # (version 14) owed walkers are the pool's and the budget's too
                owed = self._owed_of(self.areas.n)
                short, room = short - int(owed[area]), room - int(owed.sum())
            new = max(0, min(want, short, room))
        if len(mine) > want - new:
            mine = np.sort(self.rng.choice(mine, want - new, replace=False))
        k = len(mine) + new
        if k == 0:
            return
        tries = TOUCH_TRIES if self.touch_creates else CELL_TRIES
        px, py = ring_spots(self.rng, seed, self.params.hc, tries * k)  # every try drawn at once
        if self.index.grid.period is not None:  # a tile: onto it
            px, py = wrap_into(px, self.index.width), wrap_into(py, self.index.height)
        placed, pick = first_good_by_rounds(lambda flat: self._beside(seed, px[flat], py[flat]),
                                            tries, k)
        which = np.flatnonzero(placed)
        moved = which < len(mine)  # the pool's walkers first, then the new ones
        self.water.move(mine[which[moved]], px[pick[moved]], py[pick[moved]])
        born = pick[~moved]
        if len(born):
            self.water.append(px[born], py[born], np.full(len(born), area, np.int32))
            self.created += len(born)

    def _beside(self, seed: tuple[float, float], px: np.ndarray, py: np.ndarray) -> np.ndarray:
        """Spots on the screen, at least hc / 2 from every live crystal and no nearer to
        any crystal than to the seed at `seed`."""
        index = self.index
        good = (px >= 0) & (px < index.width) & (py >= 0) & (py < index.height)
        pts = np.column_stack((px[good], py[good]))
        d2 = index.nearest_d2(pts)
        own = (pts[:, 0] - seed[0]) ** 2 + (pts[:, 1] - seed[1]) ** 2
        good[good] = (d2 >= np.float32(self.params.hc / 2) ** 2) & (own <= d2)  # the seed's water
        return good
