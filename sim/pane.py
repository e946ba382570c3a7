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

from .fern import _nearest_d2
from .params import Params

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
TRIES = 8


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

    def start(self) -> None:
        pass

    def melted(self, dead: np.ndarray) -> None:
        pass

    def pool(self, humidity: int) -> int:
        return humidity

    def refill(self) -> None:
        pass


class Pane:
    """The pane's seeds and its one pool of water (see module doc)."""

    on = True

    def __init__(self, sim):
        self.sim = sim
        self._band = np.empty(0, np.int64)
        self._band_key = None
        # Crystals whose own cell each cell is (live ones among the first `_seen`).
        self._own = np.zeros(sim.grid.size, np.int32)
        self._seen = 0

    def start(self) -> None:
        """Open the pane-wide area, then plant the frame's and the glass's seeds."""
        sim = self.sim
        w, h = sim.width, sim.height
        row = np.array([[w / 2, h / 2, math.hypot(w, h) / 2 + 1.0, 0.0, 0.0]], np.float32)
        sim._areas.append(row)
        sim._area_ice.append(np.zeros(1, np.int32))
        sites = np.vstack((frame_sites(sim.rng, w, h, sim.params.frame_sites),
                           pane_sites(sim.rng, w, h, sim.params.pane_sites)))
        if len(sites):
            sim.plant(sites, water=False)  # the pane's own seeds: its pool is theirs

    def melted(self, dead: np.ndarray) -> None:
        """Melted crystals leave their cells' counts (those counted so far)."""
        seen = dead[dead < self._seen]
        c = self.sim._crystals.raw()[seen]
        np.subtract.at(self._own, self.sim.grid.keys(c[:, 0], c[:, 1]), 1)

    def pool(self, humidity: int) -> int:
        """The pool's size: `humidity`, or less where little glass lies near the ice."""
        return min(humidity, int(DENSITY * len(self.band())))

    def refill(self) -> None:
        """Keep the pool full: frozen water and water dropped for want of glass return."""
        self.sim._fill(np.zeros(1, np.int32))

    def place(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """n spots of glass in the band's cells (see `glass_spots`)."""
        return glass_spots(self.sim, self.band(), n)

    def band(self) -> np.ndarray:
        """Cells within BAND rings of a candidate cell that hold no crystal of their own;
        recomputed only when the ice changed (a crystal added or melted)."""
        sim = self.sim
        key = (sim._crystals.n, sim.water_melted)  # (what the band follows: the ice)
        if key != self._band_key:
            new = np.arange(self._seen, sim._crystals.n)
            c = sim._crystals.raw()[new[sim._calive.raw()[new]]]
            np.add.at(self._own, sim.grid.keys(c[:, 0], c[:, 1]), 1)
            self._seen = sim._crystals.n
            near = (sim.clearance.rings <= BAND) & (self._own == 0)
            self._band, self._band_key = np.flatnonzero(near), key
        return self._band


def glass_spots(sim, cells: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n uniform spots of glass (on screen, at least hc / 2 from every live crystal) in
    uniformly drawn `cells`; `ok` False where TRIES draws found none. hc / 2 is the fern
    rule's least crystal spacing: water placed only beyond hc (outside candidate cells)
    left a frosted pane with about 20 % of its cells holding no crystal, every point of
    them within hc of a neighbour's, and a wiped path half refrozen."""
    x, y, ok = np.zeros(n, np.float32), np.zeros(n, np.float32), np.zeros(n, bool)
    todo = np.arange(n)
    for _ in range(TRIES if len(cells) else 0):
        if len(todo) == 0:
            break
        px, py = _draw(sim, cells, len(todo))
        good = _glass(sim, px, py)
        x[todo[good]], y[todo[good]], ok[todo[good]] = px[good], py[good], True
        todo = todo[~good]
    return x, y, ok


def _draw(sim, cells: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """k uniform points of uniformly drawn `cells`."""
    u = sim.rng.random((3, k), dtype=np.float32)
    cell = cells[np.minimum((u[0] * len(cells)).astype(np.int64), len(cells) - 1)]
    s = np.float32(sim.grid.cell)
    return (cell % sim.grid.cols + u[1]) * s, (cell // sim.grid.cols + u[2]) * s


def _glass(sim, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """On the screen and at least hc / 2 from every live crystal."""
    good = (px < sim.width) & (py < sim.height)
    d2 = _nearest_d2(sim, np.column_stack((px[good], py[good])))
    good[good] = d2 >= np.float32(sim.params.hc / 2) ** 2
    return good


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


def make_pane(sim):
    if sim.params.water_far:  # (frond rules 2 and 3)
        from .openglass import OpenGlass
        return OpenGlass(sim)
    return Pane(sim) if sim.params.window_frost else NoPane()


def first_good(good: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For tries x k flags: which of the k have a good try, and the flat index (into the
    tries x k draws) of the first good try of each of those."""
    placed = np.any(good, axis=0)  # (an array for mypy, where good.any may be a scalar)
    pick = good.argmax(axis=0)[placed] * good.shape[1] + np.flatnonzero(placed)
    return placed, pick
