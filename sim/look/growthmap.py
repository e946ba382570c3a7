"""When each pixel's ice appeared: the growth-time map that lets an engine replay the freeze.

`GrowthClock` reads the same GeometryDelta stream the renderer does and keeps, per pixel,
the tick at which it last went from clear to ice:
- the sharp features: a pixel takes the tick of the first triangle that covered it (the
  renderer's feature texture only ever rises, so a pixel once covered stays ice); a melt's
  `clear_box` clears the box, and the survivors the delta re-sends keep the time they had;
- the bumps: where grid vertices changed, the pixels interpolated from them are sampled
  again as the maps sample them; a pixel takes the tick its bump height first rose above
  the ice threshold (0, or the film's cut in the glass look) and loses it when a melt
  takes it back below.
A pixel's time is the earlier of the two; a melted-and-refrozen pixel takes the later time
because the melt cleared the earlier one. Pixels that are not ice in the final maps carry
NEVER, whatever the clock saw.
"""

from __future__ import annotations

import numpy as np

from ..params import Params
from .geometry import GeometryDelta
from .maps import triangle_hits
from .material import FILM_CUT

NEVER = np.iinfo(np.int32).max  # no ice (yet)
GROWTH_TOP = 65534  # the run's last tick; 65535 is kept for pixels with no ice
GROWTH_NONE = 65535


class GrowthClock:
    """Per-pixel ice times of a `width` x `height` frost, fed every GeometryDelta in order."""

    def __init__(self, params: Params, width: int, height: int, wrap: bool = False):
        self.width, self.height, self.wrap = width, height, wrap
        self.spacing = int(params.grid_spacing)
        self.threshold = FILM_CUT if params.look == "glass" else 0.0
        self.edge_aa = params.look == "glass"  # the maps' features, as sim.look.maps draws them
        self.features = np.full(width * height, NEVER, np.int32)
        self.bumps = np.full(width * height, NEVER, np.int32)
        # The heights as the deltas left them (sim.look.geometry's grid: a vertex every spacing px).
        self.grid = np.zeros((height // self.spacing + 1, width // self.spacing + 1), np.float32)

    def apply(self, delta: GeometryDelta) -> None:
        if delta.reset:
            self.features[:] = NEVER
            self.bumps[:] = NEVER
            self.grid[:] = 0
        if delta.clear_box is not None:
            self._clear(delta.clear_box, delta)
        else:
            self._cover(delta.features, delta.tick)
        self._bumps(delta)

    def _cover(self, verts: np.ndarray, tick: int) -> None:
        """Pixels under `verts`' triangles that had no ice take `tick`."""
        idx = triangle_hits(verts, self.width, self.height, self.edge_aa, self.wrap)
        np.minimum.at(self.features, idx, np.int32(tick))

    def _clear(self, box, delta: GeometryDelta) -> None:
        """A melt: the box is wiped; the survivors re-sent keep their times."""
        img = self.features.reshape(self.height, self.width)
        x0, y0 = max(int(np.floor(box[0])), 0), max(int(np.floor(box[1])), 0)
        x1, y1 = min(int(np.ceil(box[2])) + 1, self.width), min(int(np.ceil(box[3])) + 1, self.height)
        # A pixel a survivor still covers was ice before the melt (under this feature or
        # by the bumps alone, before the ridge was cut shorter): it keeps its time.
        bumps = self.bumps.reshape(self.height, self.width)[y0:y1, x0:x1]
        old = np.minimum(img[y0:y1, x0:x1], bumps)
        idx = triangle_hits(delta.features, self.width, self.height, self.edge_aa, self.wrap)
        keep = np.full(self.width * self.height, NEVER, np.int32)
        np.minimum.at(keep, idx, np.int32(delta.tick))
        keep = keep.reshape(self.height, self.width)[y0:y1, x0:x1]
        img[y0:y1, x0:x1] = np.where(keep < NEVER, np.minimum(old, keep), NEVER)

    def _bumps(self, delta: GeometryDelta) -> None:
        """Pixels in the grid cells around the vertices that changed: ice from the bumps
        (bilinear, as sim.look.maps.bump_field samples them) takes the tick, clear loses it."""
        rows = delta.rows
        if rows.stop <= rows.start:
            return
        changed = np.argwhere(delta.heights != self.grid[rows])
        self.grid[rows] = delta.heights
        if len(changed) == 0:
            return
        changed[:, 0] += rows.start
        ys, xs = self._cell_pixels(changed)
        z = self._bilinear(xs, ys)
        idx = ys * self.width + xs
        was = self.bumps[idx]
        self.bumps[idx] = np.where(z > self.threshold, np.minimum(was, delta.tick), NEVER)

    def _cell_pixels(self, vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ys, xs) of every pixel interpolated from any of `vertices` (r, c)."""
        s = self.spacing
        cells = np.unique(np.concatenate([vertices - [dy, dx] for dy in (0, 1) for dx in (0, 1)]),
                          axis=0)
        cells = cells[(cells >= 0).all(axis=1)]
        oy, ox = (a.ravel() for a in np.mgrid[-1:s + 1, -1:s + 1])
        ys, xs = cells[:, 0:1] * s + oy, cells[:, 1:2] * s + ox
        keep = (ys >= 0) & (ys < self.height) & (xs >= 0) & (xs < self.width)
        flat = np.unique(ys[keep] * self.width + xs[keep])
        return flat // self.width, flat % self.width

    def _bilinear(self, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
        """The bump height at pixel centres, float32 as sim.look.maps.bump_field computes it."""
        x0, x1, wx = _axis(xs, self.spacing, self.grid.shape[1])
        y0, y1, wy = _axis(ys, self.spacing, self.grid.shape[0])
        g = self.grid
        a = g[y0, x0] * (1 - wx) + g[y0, x1] * wx
        b = g[y1, x0] * (1 - wx) + g[y1, x1] * wx
        return (a * (1 - wy) + b * wy).astype(np.float32)

    def ticks(self, ice: np.ndarray) -> np.ndarray:
        """H x W int32 tick at which each pixel of the final `ice` mask froze (NEVER where
        it is not ice)."""
        t = np.minimum(self.features, self.bumps).reshape(self.height, self.width)
        return np.where(ice, t, NEVER)


def _axis(i: np.ndarray, spacing: int, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """sim.look.maps.bump_field's sampling of pixel index `i` on one axis: vertices and weight."""
    t = np.clip((i + 0.5) / spacing, 0, size - 1)
    i0 = np.minimum(np.floor(t).astype(np.int64), size - 1)
    return i0, np.minimum(i0 + 1, size - 1), (t - i0).astype(np.float32)


def encode_growth(ticks: np.ndarray, total: int) -> np.ndarray:
    """uint16 growth map: tick t of a `total`-tick run as floor(t x 65534 / total), so
    `growth <= progress x 65534` is the ice at that share of the run; 65535 where no ice."""
    total = max(int(total), 1)
    table = (np.arange(total + 1, dtype=np.int64) * GROWTH_TOP // total).astype(np.uint16)
    return np.where(ticks == NEVER, np.uint16(GROWTH_NONE), table[np.minimum(ticks, total)])
