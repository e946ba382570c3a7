"""What a FrostSim does between ticks at a finger's word: touches plant seeds (each with
its area's water), warm fingers melt ice and give its water back."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..params import Params
from ..screen import touch_problem
from . import budget
from .melting import melt_discs, melt_tips
from .skeleton import Melted
from .versions import Rules
from .views import Holdings
from .walk import on_screen_f32


class Touches(Holdings):
    """The touch and melt side of `FrostSim` (its parts set by FrostSim.__init__)."""

    rules: Rules
    params: Params
    width: int
    height: int
    pane: Any
    water_melted: int

    def _add_crystals(self, pts: np.ndarray, parents: np.ndarray, area: np.ndarray) -> slice:
        """Crystals at `pts` (FrostSim's: into the skeleton, counted in their areas)."""
        raise NotImplementedError

    def _follow_ice(self, new: slice) -> None:
        """Each area's reach after crystals `new` (FrostSim's: growth mode, launch circle)."""
        raise NotImplementedError

    def touch(self, x: float, y: float) -> int:
        """Plant a seed crystal at (x, y); returns the index of its active area, or -1
        where the touch planted nothing (from version 9: its seed would overfill a cell).

        A touch inside an existing active area joins that area (the nearest, by its
        centre) and tops its pool up to `humidity`; elsewhere it opens a new area with
        its own pool. Either way the screen's walkers stay within `water_budget`, so a
        drag that plants a trail of touches costs what a few touches cost."""
        return int(self.plant([(x, y)])[0])

    def plant(self, points, water: bool = True) -> np.ndarray:
        """Touches at every (x, y) of `points` at once (a run's first touches, or those a
        rebuild replants together): the seeds, then one top-up of each area they touched,
        then (`water`, with `touch_water`) the ring of water each seed that joined an area
        brings (from version 8 each seed: `Supply.water_seed`). Returns each seed's area;
        -1 for a touch that planted nothing: from version 9 a touch obeys the cells' cap
        as a freeze does (`budget.within_cap`), so one spot touched again and again stops
        adding seeds (and water) once its cells are full."""
        pts = np.array(points, np.float64).reshape(-1, 2)
        for x, y in pts:
            problem = touch_problem(x, y, (self.width, self.height))
            if problem:
                raise ValueError(problem)
        pts32 = on_screen_f32(pts, self.width, self.height)
        room = self._room_for(pts32)
        out = np.full(len(pts), -1, np.int32)
        if room.any():
            out[room] = self._seed(pts32[room], water)
        return out

    def _room_for(self, pts32: np.ndarray) -> np.ndarray:
        """Which seeds at `pts32` (in order) the cells' cap takes (version 9; before, all)."""
        if not self.rules.capped_touches:
            return np.ones(len(pts32), bool)
        return budget.room_for(self.index.candidates, self.index.grid, pts32, self.params.hc)

    def _seed(self, pts32: np.ndarray, water: bool) -> np.ndarray:
        """Seeds at `pts32` (on the screen, within the cap), their areas topped up and
        ringed (see `plant`); each seed's area."""
        opened = self._areas.n
        area = self._areas.areas_for(pts32, self.params.active_radius)
        seeds = self._add_crystals(pts32, np.full(len(pts32), -1, np.int32), area)
        # The seeds that bring a ring of water (`touch_water`): those joining an area, and
        # from version 8 those opening one (whose pool starts on the launch circle, 30 px
        # out, else their first arm waits for it); their first hits count together.
        ringed = (area < opened) | self.rules.opening_rings
        ringed &= bool(water and self.params.touch_water)
        self.growth.add_seeds(len(pts32), ringed)
        self.index.register(seeds)
        self._follow_ice(seeds)  # a seed joining an area may lie beyond its ice
        self.supply.fill(np.unique(area), self.ice_state())
        for seed in np.flatnonzero(ringed):
            sx, sy = self.ice.crystals.raw()[seeds.start + int(seed)]
            self.supply.water_seed((float(sx), float(sy)), int(area[seed]))
        return area

    def melt(self, x: float, y: float, radius: float) -> Melted:
        """A warm finger at (x, y): crystals within `radius` px melt and their water returns
        to its area's pool (never above `humidity`; an area left with no ice loses its
        water); their links (and those of their children, which become roots) leave the
        skeleton; the cleared cells stop being candidate cells. Costs O(local ice)."""
        return self.melt_many([(x, y, radius)])

    def melt_many(self, discs) -> Melted:
        """One melt of the crystals within any of `discs` ((x, y, radius) each): as `melt`,
        in one pass over the ice they cover, one return of their water."""
        return self._returned(melt_discs(discs, self.ice, self.index, self.growth, self.pane))

    def melt_tips(self) -> Melted:
        """The weather's thaw, one layer: the ice's thin edges (`Skeleton.tips`) melt and
        their water returns, as a warm finger's does."""
        return self._returned(melt_tips(self.ice, self.index, self.growth, self.pane))

    def _returned(self, melted: Melted) -> Melted:
        """The water of the crystals `melted` back in its areas' pools."""
        self.water_melted += len(melted.crystals)
        dead_area = self.ice.area.raw()[melted.crystals]
        self._areas.count_ice(dead_area, -1)
        self.supply.returned(dead_area, self.ice_state())
        return melted
