"""The frost simulation of Sec. 3.3-3.4: water walks, freezes near crystals, and grows a skeleton.

`FrostSim` runs a tick over its parts (sim/core, sim/index): the ice skeleton, the freezing
index over it, the walkers, the active areas, their placement and supply. A tick
(`FrostSim.step`) is: walk -> drop water in full cells -> crystallize and admit (within
the tick's geometry budget and the cells' cap) -> settle (the growth rule: Table 1's keeps
every freeze, the fern rule's slots and hits) -> link and upsample -> register the new
crystals in the index -> follow the ice (growth mode, launch circle) -> place again the
walkers whose hits only counted -> refill the pools (replenish, growth mode, the pane).
Touches and melts (`Touches`, sim/core/touches.py) come between ticks.
Everything is plain numpy data; rendering reads the arrays and the per-tick `added` slices.
"""

from __future__ import annotations

import numpy as np

from ..index.freezing import FreezingIndex
from ..index.periodic import image_near
from ..params import Params
from ..rules.fern import make_growth
from ..rules.pane_choice import make_pane
from ..rules.window_mode import chill
from ..screen import HEIGHT, WIDTH
from . import budget, placement
from .areas import Areas
from .budget import CELL_CAP, FREEZE_WORK
from .freezes import admitted, drop_in_full_cells, nearest_crystals
from .placement import CELL_TRIES, CELL_WORK, Placer
from .skeleton import Added, Melted, Skeleton, upsample
from .supply import TOUCH_TRIES, Supply
from .touches import Touches
from .versions import NEWEST, random_streams, rules_of
from .walk import clearance_jumps, walk_displacements, walk_water
from .water import Water

__all__ = ["Added", "CELL_CAP", "CELL_TRIES", "CELL_WORK", "FREEZE_WORK", "FrostSim", "Melted",
           "TOUCH_TRIES", "VERSION", "upsample", "walk_displacements"]

# The newest rules (what a session file's "version" names; sim/core/versions.py lists what
# each changed). Older versions replay as frost grew them then.
VERSION = NEWEST
_NONE = np.empty(0, np.int64)
_PANE = np.zeros(1, np.int32)  # the pane's one area


def _check(name: str, v, low: int, high: int, what: str) -> None:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not low <= v <= high:
        raise ValueError(f"{name}={v!r} must be a whole number{what} in [{low}, {high}]")


class FrostSim(Touches):
    """Window frost on a `width` x `height` px screen (docs/method.md). `version` (1 ..
    VERSION) picks the rules a session file of that version replays with (`self.rules`,
    sim/core/versions.py); each part draws from its stream of `self.streams`. `wrap`: a
    tile (sim.index.periodic), whose walkers, search, clearance and placement see across edges."""

    def __init__(self, params: Params | None = None, width: int = WIDTH, height: int = HEIGHT,
                 seed: int = 0, version: int = VERSION, wrap: bool = False):
        _check("width", width, 1, 16384, " of px")
        _check("height", height, 1, 16384, " of px")
        self.rules = rules_of(version)
        p = self.params = params if params is not None else Params()
        self.width, self.height, self.wrap = int(width), int(height), bool(wrap)
        self.seed, self.version = seed, self.rules.version
        self.streams = random_streams(seed, self.rules)
        self.tick, self.water_melted, self._rows_at_tick_end = 0, 0, (0, 0, 0)
        self.ice, self._water, self._areas = Skeleton(), Water(p.humidity), Areas()
        self.index = FreezingIndex(self.ice.crystals, self.width, self.height, p.hc,
                                   p.neighbor_search, self.wrap, p.long_jumps or p.window_frost)
        self.grid, self.candidates = self.index.grid, self.index.candidates
        self.search, self.clearance = self.index.search, self.index.clearance
        self.work_per_crystal = budget.work_per_crystal(p.hc, p.grid_spacing, p.D)
        # Beyond the paper (fern rules; window mode chills them by its temperature).
        rules, streams = self.rules, self.streams
        self.growth = make_growth(chill(p), streams.growth, rules.pooled_first_hits,
                                  rules.capped_touches)
        self.pane = make_pane(p, streams.pane, self.index, self.ice, rules.tries_at_once)
        self.placer = Placer(streams.placement, self.index, self._areas, self.pane, p,
                             rules.batched_placement, rules.kept_water)
        self.supply = Supply(p, streams.supply, self._water, self._areas, self.placer, self.pane,
                             self.index, rules.touch_creates, rules.kept_water)
        self.added = Added(0, slice(0, 0), slice(0, 0), slice(0, 0), 0)
        self.thawing = False  # the weather's thaw (`set_weather`): no step grows
        self._start_pane()

    def set_weather(self, temperature: float | None, supply: float = 1.0) -> None:
        """The weather's glass from the next step on (sim/weather): window mode grows as
        if its `temperature` were `temperature` and its pane's water were `supply` times
        as much; None: a thaw, whose steps grow nothing (the walkers wait where they are;
        `melt_tips` takes the ice back). Touch mode has no temperature: a thaw alone acts."""
        self.thawing = temperature is None
        if temperature is not None and self.params.window_frost:
            self.growth.chilled(chill(self.params.replace(temperature=temperature)))
            self.pane.chilled(temperature, supply)

    def _start_pane(self) -> None:
        """Window mode: the pane-wide area, then the frame's and the glass's own seeds."""
        start = self.pane.start()
        if start is not None:
            self._areas.open(start[0])
            if len(start[1]):
                self.plant(start[1], water=False)  # the pane's own seeds: its pool is theirs

    # ---- a tick -------------------------------------------------------------------

    def step(self) -> Added:
        """One tick: the phases of the module doc, in order (none in a thaw)."""
        if self.thawing:
            self.tick += 1
            return self._close_tick(0)
        self.placer.cell_work = placement.CELL_WORK
        if self.rules.kept_water:  # the water last tick's cell work cut comes first
            self.supply.repay(self.ice_state())
        self.walk()
        keys, dropped = drop_in_full_cells(self._water, self.index)
        self.supply.dropped += dropped
        hits, parents = self._admit(*self.crystallize(keys))
        frozen, parents, pts, bounced = self.growth.settle(self._water.at(hits), hits, parents,
                                                           self.ice, self.index)
        new = self._link(frozen, parents, pts)
        self.index.register(new)
        self._follow_ice(new)
        # Hits that only counted are placed again; a kept pool (not the pane's: it refills)
        # gets the frozen water back.
        if (self.params.replenish or self.params.grow) and not self.pane.on:
            lost = self.supply.relocate_then_spawn(bounced, self._water.area.raw()[frozen],
                                                   self.ice_state())
        else:
            lost = self.supply.relocate(bounced, self.ice_state())
        self.supply.spent(frozen, lost)
        if self.pane.on:  # the pane keeps its pool full
            self.supply.fill(_PANE, self.ice_state())
        elif self.rules.kept_water and (self.params.replenish or self.params.grow):
            self.supply.top_up(self.ice_state())  # a kept pool gets back what was lost
        self.tick += 1
        return self._close_tick(len(frozen))

    # ---- phases ---------------------------------------------------------------------

    def ice_state(self) -> tuple[int, int]:
        """What changes when the ice does: crystals added, crystals melted."""
        return (self.ice.crystals.n, self.water_melted)

    def walk(self) -> None:
        """Eq. 2 for every walker; leavers are recreated inside their area (Sec. 3.4.2)."""
        if self._water.n == 0:
            return
        x, y = self._water.x.raw(), self._water.y.raw()
        columns = self._areas.columns(self._water.area.raw())
        left = walk_water(self.streams.walk, x, y, columns, self.params.step, self.jumps(x, y, columns),
                          (self.width, self.height), self.wrap)
        self.supply.spent(_NONE, self.supply.relocate(left, self.ice_state()))

    def jumps(self, x: np.ndarray, y: np.ndarray, columns=None) -> np.ndarray | None:
        """Long jumps: the clearance of walkers at (x, y), each in its own area (None
        without long jumps); `columns`: `Areas.columns` of the walkers, where known."""
        if not self.params.long_jumps:
            return None
        columns = self._areas.columns(self._water.area.raw()) if columns is None else columns
        return clearance_jumps(self.index.clearance, x, y, columns)

    def crystallize(self, keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Sec. 3.4.3: the walkers within hc of a crystal, and their nearest crystal
        (`keys`: the walkers' cells, where known)."""
        return nearest_crystals(self._water, self.index, keys)

    def _admit(self, hits: np.ndarray, parents: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The freezes this tick takes (`freezes.admitted`); the rest wait or drop."""
        frozen, parents, dropped = admitted(self._water, self.index, hits, parents,
                                            self.params.hc, self.work_per_crystal)
        self.supply.dropped += dropped
        return frozen, parents

    def _link(self, frozen: np.ndarray, parents: np.ndarray, pts: np.ndarray) -> slice:
        """Frozen walkers become crystals at `pts` linked to their parents; links are
        upsampled. With a launch circle a crystal belongs to the area of the ice it grew
        on (so each area's reach follows its own frost), else to its water's."""
        area = (self.ice.area.raw()[parents] if self.params.launch
                else self._water.area.raw()[frozen])
        new = self._add_crystals(pts, parents, area)
        # On a tile the link runs to the parent's image beside its child (across an edge
        # its segments and upsample particles lie off the tile; the geometry wraps them).
        size = (self.width, self.height) if self.wrap else None
        tail = image_near(self.ice.crystals.raw()[parents], pts, size)
        self.ice.link(new.start, tail, pts, self.params.D)
        return new

    def _add_crystals(self, pts: np.ndarray, parents: np.ndarray, area: np.ndarray) -> slice:
        new = self.ice.add(pts, parents, area)
        self._areas.count_ice(area, 1)
        return new

    def _follow_ice(self, new: slice) -> None:
        """Growth mode: each area's annulus rides on its ice front (`Areas.ride`); a launch
        circle needs the reach too. Costs O(new crystals). Without growth mode the areas
        keep their size, and the pane's one area (window mode) always covers the screen."""
        area = self.ice.area.raw()[new]
        if len(area) == 0 or self.pane.on or not (self.params.grow or self.params.launch):
            return
        touched = self._areas.reach_to(area, self.ice.crystals.raw()[new])
        if self.params.grow:
            self._areas.ride(touched, self.params.active_radius)

    def _close_tick(self, frozen: int) -> Added:
        """The rows this tick added (touches since the last tick's end included)."""
        now = self.ice.counts()
        crystals, upsampled, segments = (slice(a, b) for a, b in zip(self._rows_at_tick_end, now,
                                                                      strict=True))
        self._rows_at_tick_end = now
        self.added = Added(self.tick, crystals, upsampled, segments, frozen)
        return self.added
