"""Window mode: frost that nucleates on the frame and grows over the whole pane.

With `window_frost` on, the simulation starts with seeds along the screen's border (the
frame), spaced irregularly, plus `pane_sites` scratch and dust seeds on the glass; each is
an ordinary seed, so the growth rule gives it its own grain orientation. Water belongs to
the whole pane: one active area covering the screen holds one pool of `humidity` walkers,
kept full every tick, and placed on free glass within BAND cell rings of the ice (the
launch circle generalised), read off the clearance rings of the hash grid. Placing costs
O(grid cells), whatever the number of seeds.

`temperature` (degrees C below freezing) acts through the fern hit counters: a slot needs
round(hits x REFERENCE_C / temperature) hits (at least 1), so colder grows faster and
branches more densely; at REFERENCE_C the preset's counts apply as they are.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.placement import GLASS_TRIES, glass_spots
from ..params import Params

# Temperature at which the preset's hit counts apply unchanged, degrees C below freezing.
REFERENCE_C = 10.0
# Water is placed in free cells at most this many cell rings (of 2 hc) beyond the ice:
# 3 rings (42 px at hc 7) is the fern preset's 30 px launch circle rounded up to cells.
BAND = 3
# Most walkers per band cell: the pool is min(humidity, DENSITY x band cells), so the water
# over the glass keeps one density whether the front is the whole frame or a wiped path
# (3 000 walkers poured into a wipe closed it in a few ticks, as a haze). At the start the
# band holds about 1 300 cells: the full `humidity` of 3 000.
DENSITY = 2.5
# Draws per walker among the band's cells before it is dropped.
TRIES = GLASS_TRIES


def chill(params: Params) -> Params:
    """The parameters the growth rule uses: hit counts scaled by the temperature."""
    if not params.window_frost:
        return params
    scale = REFERENCE_C / params.temperature
    return params.replace(tip_hits=max(1, round(params.tip_hits * scale)),
                          side_hits=max(1, round(params.side_hits * scale)))


class NoPane:
    """Touch mode: water belongs to the touches' areas."""

    on = False

    def start(self) -> tuple[np.ndarray, np.ndarray] | None:
        return None

    def melted(self, dead: np.ndarray) -> None:
        pass

    def pool(self, humidity: int) -> int:
        return humidity

    def place(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        raise NotImplementedError  # (touch mode places water in its areas)

    def chilled(self, temperature: float, supply: float) -> None:
        pass  # (touch mode's water follows the touches, not the glass)


class Pane:
    """The pane's seeds and its one pool of water (see module doc). It reads the ice (the
    skeleton's positions and alive flags, the freezing index) and answers where water goes
    and how much; the simulation opens its area, plants its seeds and keeps its pool full."""

    on = True

    def __init__(self, params: Params, rng: np.random.Generator, index, ice):
        self.params, self.rng, self.index, self.ice = params, rng, index, ice
        self._band = np.empty(0, np.int64)
        self._band_key: tuple[int, int] | None = None
        # Crystals whose own cell each cell is (live ones among the first `_seen`).
        self._own = np.zeros(index.grid.size, np.int32)
        self._seen = 0
        self._melted = 0  # crystals melted so far (the ice's state, with its count)

    def start(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The pane-wide area's row, and the frame's and the glass's seeds."""
        w, h = self.index.width, self.index.height
        row = np.array([w / 2, h / 2, math.hypot(w, h) / 2 + 1.0, 0.0, 0.0], np.float32)
        sites = np.vstack((frame_sites(self.rng, w, h, self.params.frame_sites),
                           pane_sites(self.rng, w, h, self.params.pane_sites)))
        return row, sites

    def melted(self, dead: np.ndarray) -> None:
        """Melted crystals leave their cells' counts (those counted so far)."""
        self._melted += len(dead)
        seen = dead[dead < self._seen]
        c = self.ice.crystals.raw()[seen]
        np.subtract.at(self._own, self.index.grid.keys(c[:, 0], c[:, 1]), 1)

    def chilled(self, temperature: float, supply: float) -> None:
        pass  # (without the frond rules the pool keeps to the band's density)

    def ice_key(self) -> tuple[int, int]:
        """What the band follows: crystals added and melted."""
        return (self.ice.crystals.n, self._melted)

    def pool(self, humidity: int) -> int:
        """The pool's size: `humidity`, or less where little glass lies near the ice."""
        return min(humidity, int(DENSITY * len(self.band())))

    def place(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """n spots of glass in the band's cells (see `glass_spots`)."""
        return glass_spots(self.rng, self.index, self.band(), n, TRIES)

    def band(self) -> np.ndarray:
        """Cells within BAND rings of a candidate cell that hold no crystal of their own;
        recomputed only when the ice changed (a crystal added or melted)."""
        key = self.ice_key()
        if key != self._band_key:
            n = self.ice.crystals.n
            new = np.arange(self._seen, n)
            c = self.ice.crystals.raw()[new[self.ice.crystal_alive.raw()[new]]]
            np.add.at(self._own, self.index.grid.keys(c[:, 0], c[:, 1]), 1)
            self._seen = n
            near = (self.index.clearance.rings <= BAND) & (self._own == 0)
            self._band, self._band_key = np.flatnonzero(near), key
        return self._band


def frame_sites(rng: np.random.Generator, width: int, height: int, per_100: float) -> np.ndarray:
    """Sites along the border, per_100 per 100 px of it on average: the border is cut into
    equal stretches, one site uniform in each (irregular gaps, none much longer than two
    stretches). Each lies half a px inside the screen."""
    perimeter = 2.0 * (width + height)
    n = round(per_100 * perimeter / 100.0)
    if n == 0:
        return np.empty((0, 2), np.float64)
    t = (np.arange(n) + rng.random(n)) * (perimeter / n)
    return _on_border(t, width, height)


def _on_border(t: np.ndarray, width: int, height: int) -> np.ndarray:
    """The point at arc length t along the border, clockwise from the top-left corner."""
    w, h, e = width - 1.0, height - 1.0, 0.5
    t = t * (2 * (w + h)) / (2.0 * (width + height))
    top, right, bottom = t < w, (t >= w) & (t < w + h), (t >= w + h) & (t < 2 * w + h)
    x = np.select([top, right, bottom], [t, w, 2 * w + h - t], 0.0)
    y = np.select([top, right, bottom], [0.0, t - w, h], 2 * (w + h) - t)
    return np.column_stack((np.clip(x, e, w + 1 - e), np.clip(y, e, h + 1 - e)))


def pane_sites(rng: np.random.Generator, width: int, height: int, n: int) -> np.ndarray:
    """Scratch and dust: n sites uniform on the glass."""
    return rng.random((n, 2)) * np.array([width, height])

