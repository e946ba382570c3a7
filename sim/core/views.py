"""What a FrostSim holds, as its users read it: views of the skeleton, the walkers and the
areas (no copies unless noted), exact water for tests and tools, and a few queries."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..index.freezing import FreezingIndex
from .areas import Areas
from .placement import Placer
from .skeleton import Skeleton
from .supply import Supply
from .water import Water


class Holdings:
    """The read side of `FrostSim` over its parts (set by FrostSim.__init__)."""

    ice: Skeleton
    index: FreezingIndex
    placer: Placer
    supply: Supply
    growth: Any
    _water: Water
    _areas: Areas

    def ice_state(self) -> tuple[int, int]:
        """What changes when the ice does (FrostSim's: crystals added, crystals melted)."""
        raise NotImplementedError

    def segments_near(self, box: tuple[float, float, float, float], reach: float) -> np.ndarray:
        """Indices of live segments whose points may lie within `reach` x their length
        beside them of the px box (x0, y0, x1, y1): those of the links of the crystals
        near the box. A superset; callers test the exact extent."""
        pad = self.ice.longest_link * (1.0 + reach) + 1.0
        x0, y0, x1, y1 = box
        return self.ice.live_segments(self.index.crystals_in_box(x0 - pad, y0 - pad,
                                                                 x1 + pad, y1 + pad))

    def set_water(self, xy, area=0) -> None:
        """Replace every walker by walkers at `xy` (n x 2 px) in active area(s) `area` (one
        index for all, or one each): exact water for a test or a tool to start a tick
        from. The areas must exist (a touch opens one)."""
        xy = np.asarray(xy, np.float32).reshape(-1, 2)
        area = np.broadcast_to(np.asarray(area, np.int32), (len(xy),))
        if len(area) and not (area.min() >= 0 and area.max() < self._areas.n):
            raise ValueError(f"set_water: area {int(area.max())} does not exist "
                             f"({self._areas.n} areas)")
        self._water.set(xy, area)

    def place(self, area: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, ok): spots for new walkers of areas `area` where a tick would place them
        (`ok` False: no free spot); nothing is added."""
        return self.placer.place(area, self.ice_state())

    # ---- what the simulation holds (views; copies where noted) ---------------------

    crystals = property(lambda self: self.ice.crystals.view(),
                        doc="n x 2 float32 positions of crystal particles, seeds included.")
    parents = property(lambda self: self.ice.parents.view(),
                       doc="n int32: each crystal's parent crystal, -1 for a seed.")
    crystal_alive = property(lambda self: self.ice.crystal_alive.view(),
                             doc="n bool: False for melted crystals (rows stay: stable indices).")
    crystal_area = property(lambda self: self.ice.area.view(),
                            doc="n int32: the active area whose water became each crystal.")
    upsampled = property(lambda self: self.ice.upsampled.view(),
                         doc="k x 2 float32 upsample particles (skeleton nodes, not crystals).")
    upsampled_link = property(lambda self: self.ice.upsampled_link.view(),
                              doc="k int32: the crystal whose parent link holds each particle.")
    upsampled_alive = property(lambda self: self.ice.upsampled_alive.view())
    segments = property(lambda self: self.ice.segments.view(),
                        doc="s x 4 float32 (x0, y0, x1, y1): consecutive nodes along each chain.")
    segments_link = property(lambda self: self.ice.segments_link.view(),
                             doc="s int32: the crystal whose parent link each segment belongs to.")
    segments_alive = property(lambda self: self.ice.segments_alive.view())
    water_area = property(lambda self: self._water.area.view())
    areas = property(lambda self: self._areas.rows.view(),
                     doc="a x 5 float32 active areas: centre x, centre y, outer radius, inner "
                         "radius (water lies between them), reach of the area's ice.")
    water_created = property(lambda self: self.supply.created)
    water_frozen = property(lambda self: self.supply.frozen)
    water_dropped = property(lambda self: self.supply.dropped)

    @property
    def water(self) -> np.ndarray:
        """m x 2 float32 water particle positions (a fresh copy)."""
        return np.column_stack((self._water.x.view(), self._water.y.view()))

    def nbytes(self) -> int:
        """Bytes held by the simulation's arrays (capacity, not just the filled rows)."""
        bufs = (*self.ice.buffers(), *self._water.buffers(), self._areas.rows, self._areas.ice,
                self.index, self.growth)
        return sum(b.nbytes() for b in bufs)
