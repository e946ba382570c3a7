"""The frost simulation of Sec. 3.3-3.4: water walks, freezes near crystals, and grows a skeleton.

A tick is a short list of phases (see `FrostSim.step`): walk -> drop water in full cells ->
crystallize (within the tick's geometry budget) -> settle (the growth rule: Table 1's keeps
every freeze, the fern rule's slots and hits) -> link and upsample -> register the new
crystals (candidate cells, search) -> follow the ice (growth mode) -> place again the
walkers whose hits only counted -> refill the pools (replenish, growth mode, the pane).
Everything is plain numpy data; rendering reads the arrays and the per-tick `added` slices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .buffers import CellLists, Growable
from .clearance import make_clearance
from .fern import _nearest_d2, make_growth
from .grid import HashGrid
from .pane import chill, glass_spots, make_pane
from .pane import first_good as _first_good
from .params import Params
from .periodic import image_near, nearest_image, wrap_into
from .screen import HEIGHT, WIDTH, touch_problem
from .search import make_search

TWO_PI = np.float32(2.0 * np.pi)
# The newest rules (what a session file's "version" names; sim/session.py lists what each
# changed). Older versions replay as frost grew them then.
VERSION = 5
# A water particle that found no spot in its area's free cells after this many draws is
# dropped: an area filled with ice has no free spot left (its frost is complete).
CELL_TRIES = 8
# Draws for each walker a touch brings to its ring (`_water_seed`): a seed tucked in
# beside older ice is the nearest crystal to a sliver of its ring, where 8 draws placed 4
# of 48 walkers.
TOUCH_TRIES = 32
_NONE = np.empty(0, np.int64)
# Most crystals one hash cell may list. The paper's rule lets ice pile up without end
# where water keeps arriving (replenish, growth mode, touch after touch on one spot), and
# a walker's search costs the length of its cell's list; a full cell is finished ice, and
# water that would freeze into it is dropped instead. Table 1's single touches never
# list more than 58 (measured over seeds 0-2), so the paper's frost is unchanged.
CELL_CAP = 128
# Geometry work one tick's freezes may make, in grid-vertex raises (each new crystal brings
# its link's upsample particles, and each particle raises a stencil of grid vertices).
# Freezes beyond it wait a tick as water (in walker order). Table 1's single touches peak at
# 166 050 (a-1, seeds 0-2) and two a-1 touches at about 332 000, so the paper's frost is
# unchanged; a fast chain reaction at a large hc no longer makes one tick do seconds of work.
FREEZE_WORK = 400_000
# Walkers one tick may place from cells (`_cell_spots_all`, where an area's disc draws
# failed); the rest find no spot and are dropped, as in an area with no glass left. In an
# area all ice (a fern look's pane after a storm of touches) nearly every walker hits ice
# and is placed again each tick: ~3 700 cell placements a tick took the tick past 50 ms
# (1 000 still ~30). One touch's growth needs at most 173 a tick (fern, seed 0), Table 1's
# at most 13.
CELL_WORK = 400


@dataclass(frozen=True)
class Added:
    """Index ranges appended since the previous tick (touches included)."""

    tick: int
    crystals: slice
    upsampled: slice
    segments: slice
    frozen: int  # water particles that froze in this tick


@dataclass(frozen=True)
class Melted:
    """What one `melt` removed (indices into crystals, upsampled, segments) and the
    crystals that lost their parent and became roots of their own trees."""

    crystals: np.ndarray
    upsampled: np.ndarray
    segments: np.ndarray
    orphans: np.ndarray


def walk_displacements(rng: np.random.Generator, m: int, step: float,
                       jump: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 2: each walker moves a*(cos t, sin t), a ~ U[0, step], t ~ U[0, 2 pi).
    A walker whose clearance `jump[i]` exceeds the step jumps that far instead (long jumps)."""
    u = rng.random((2, m), dtype=np.float32)
    a = u[0] * np.float32(step)
    if jump is not None:
        a = np.where(jump > step, jump, a)
    theta = u[1] * TWO_PI
    return a * np.cos(theta), a * np.sin(theta)


def upsample(p: np.ndarray, q: np.ndarray, spacing: float) -> tuple[np.ndarray, ...]:
    """Eq. 3-4 for links p[i] -> q[i]: Nu = floor(|q - p| / D); if Nu >= 2 the Nu - 1
    points p + (k / Nu)(q - p), k = 1..Nu-1, split the link into a chain of Nu segments.

    Returns (points, point_link, segments, segment_link): points k x 2, segments
    s x 4 (x0, y0, x1, y1) in chain order, and the link index of each."""
    p64, d = p.astype(np.float64), q.astype(np.float64) - p.astype(np.float64)
    nu = np.floor(np.hypot(d[:, 0], d[:, 1]) / spacing).astype(np.int64)
    if not (nu >= 2).any():  # no link long enough: each is one segment (the common case at c-2)
        links = np.arange(len(p))
        return np.empty((0, 2), np.float32), links[:0], np.hstack([p, q]).astype(np.float32), links
    nseg = np.where(nu >= 2, nu, 1)
    seg_link = np.repeat(np.arange(len(p)), nseg)
    j = np.arange(len(seg_link)) - np.repeat(np.cumsum(nseg) - nseg, nseg)
    t0 = (j / nseg[seg_link])[:, None]
    t1 = ((j + 1) / nseg[seg_link])[:, None]
    a = p64[seg_link] + t0 * d[seg_link]
    b = p64[seg_link] + t1 * d[seg_link]
    segments = np.hstack([a, b]).astype(np.float32)
    inner = j > 0  # a chain's inner nodes are the upsample particles
    return a[inner].astype(np.float32), seg_link[inner], segments, seg_link


def _on_screen_f32(pts: np.ndarray, width: int, height: int) -> np.ndarray:
    """On-screen float64 points as float32, still on the screen: x = 759.99999999 would
    round up to 760.0, off a 760 px screen, so it becomes the largest float32 below 760."""
    edge = np.nextafter(np.array([width, height], np.float32), np.float32(0))
    return np.minimum(pts.astype(np.float32), edge)


class FrostSim:
    """Window frost on a `width` x `height` px screen (docs/method.md)."""

    def __init__(self, params: Params | None = None, width: int = WIDTH, height: int = HEIGHT,
                 seed: int = 0, version: int = VERSION, wrap: bool = False):
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 < v <= 16384:
                raise ValueError(f"{name}={v!r} must be a whole number of px in [1, 16384]")
        self.params = params if params is not None else Params()
        self.width, self.height = int(width), int(height)
        # A tile (sim.periodic): walkers wrap, and the search, clearance and placement see
        # across the edges; window mode has no frame there (pane sites only).
        self.wrap = bool(wrap)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        # The rules of `version` (a session file's replays as frost grew it when written):
        if isinstance(version, bool) or not isinstance(version, (int, np.integer)) \
                or not 1 <= version <= VERSION:
            raise ValueError(f"version={version!r} must be a whole number in [1, {VERSION}]")
        self.version = int(version)
        # 3: where placement falls back to cells, one pass for all areas (before: one
        # area at a time).
        self.batched = version >= 3
        # 4: window water's later tries drawn in one batch (docs/method.md 8): the same
        # spots in law, fewer passes over the ice.
        self.tries_at_once = version >= 4
        # 5: a touch whose area's pool is short brings new walkers (`_water_seed`), and a
        # seed's hits count together until its first child (sim/fern.py).
        self.touch_creates = version >= 5
        self._plans: dict[int, tuple[np.ndarray, float, bool, bool]] = {}
        self._plans_key: tuple[int, int] | None = None
        self._cell_work = CELL_WORK  # cell placements left in this tick
        self._full: dict[int, bool] = {}  # areas whose annulus was last seen with no free cell
        self.grid = HashGrid(self.width, self.height, self.params.hc, self.wrap)
        self.tick = 0
        # The ice skeleton: crystals with parent links (-1 for a seed), upsample
        # particles and the chain segments between consecutive skeleton nodes.
        self._crystals = Growable(np.float32, (2,))
        self._parents = Growable(np.int32)
        self._calive = Growable(bool)  # False once melted (indices stay stable)
        self._ualive = Growable(bool)
        self._salive = Growable(bool)
        self._ups = Growable(np.float32, (2,))
        self._ups_link = Growable(np.int32)
        self._segs = Growable(np.float32, (4,))
        self._segs_link = Growable(np.int32)
        # Each crystal's own link as row ranges (first, count) of the segments and upsample
        # particles, so a melt finds what it cuts without scanning the whole skeleton.
        self._seg_range = Growable(np.int32, (2,))
        self._ups_range = Growable(np.int32, (2,))
        self._longest_link = 0.0  # a crystal's children lie within this of it
        # Grid vertices one new crystal may raise: its link's particles times the stencil.
        reach = math.ceil(self.params.hc / self.params.grid_spacing) + 1
        per_link = 1 + max(0, math.floor(self.params.hc / self.params.D) - 1)
        self._work_per_crystal = per_link * (2 * reach + 1) ** 2
        # Water, structure of arrays; each particle belongs to one active area.
        self._wx = Growable(np.float32, capacity=self.params.humidity)
        self._wy = Growable(np.float32, capacity=self.params.humidity)
        self._warea = Growable(np.int32, capacity=self.params.humidity)
        # centre x, centre y, outer and inner radius (water lives in the annulus), reach of its ice
        self._areas = Growable(np.float32, (5,))
        self._area_ice = Growable(np.int32)  # live crystals of each area
        self._carea = Growable(np.int32)  # the area whose water became each crystal
        self.candidates = CellLists(self.grid.size)  # Fig. 3d: state = count > 0
        self.search = make_search(self.params.neighbor_search, self.grid, self.candidates, self.params.hc)
        # Beyond the paper (fern rules): where hits grow, and how far walkers may jump.
        # (window mode: chilled by temperature)
        self.growth = make_growth(chill(self.params), self.rng, pooled_first=version >= 5)
        self.clearance = make_clearance(self.grid, self.width, self.height,
                                        self.params.long_jumps or self.params.window_frost)
        self.water_created = 0
        self.water_frozen = 0
        self.water_dropped = 0
        self.water_melted = 0
        self._mark = (0, 0, 0)
        self.added = Added(0, slice(0, 0), slice(0, 0), slice(0, 0), 0)
        self.pane = make_pane(self)  # window mode: the frame's seeds and the pane's pool
        self.pane.start()

    # ---- public API -------------------------------------------------------------

    def touch(self, x: float, y: float) -> int:
        """Plant a seed crystal at (x, y); returns the index of its active area.

        A touch inside an existing active area joins that area (the nearest, by its
        centre) and tops its pool up to `humidity`; elsewhere it opens a new area with
        its own pool. Either way the screen's walkers stay within `water_budget`, so a
        drag that plants a trail of touches costs what a few touches cost."""
        return int(self.plant([(x, y)])[0])

    def plant(self, points, water: bool = True) -> np.ndarray:
        """Touches at every (x, y) of `points` at once (a run's first touches, or those a
        rebuild replants together): the seeds, then one top-up of each area they touched,
        then (`water`, with `touch_water`) the water each seed that joined an area brings
        (`_water_seed`). Returns each seed's area."""
        pts = np.array(points, np.float64).reshape(-1, 2)
        for x, y in pts:
            problem = touch_problem(x, y, (self.width, self.height))
            if problem:
                raise ValueError(problem)
        pts32 = _on_screen_f32(pts, self.width, self.height)
        opened = self._areas.n
        area = self._areas_for(pts32)
        seeds = self._add_crystals(pts32, np.full(len(pts), -1, np.int32), area)
        self.growth.add_seeds(len(pts))
        for ranges, buf in ((self._seg_range, self._segs), (self._ups_range, self._ups)):
            ranges.append(np.column_stack((np.full(len(pts), buf.n), np.zeros(len(pts)))))
        self._register(seeds)
        self._follow_ice(seeds)  # a seed joining an area may lie beyond its ice
        self._fill(np.unique(area))
        if water and self.params.touch_water:
            for seed in np.flatnonzero(area < opened):
                self._water_seed(seeds.start + int(seed), int(area[seed]))
        return area

    def _water_seed(self, seed: int, area: int) -> None:
        """A touch into an area brings `touch_water` walkers to glass around its seed:
        uniform in the ring from hc to 2 hc, on the screen, at least hc / 2 from every
        live crystal, and where no crystal within hc (one it could freeze to) is nearer
        than the seed; those with no such spot in TOUCH_TRIES draws (CELL_TRIES before
        version 5) are not brought. Up to version 4 they were all the area's own walkers
        (drawn at random), so nothing was created; but a drained pool (an area whose
        launch circle lies on ice or off the screen finds no spot for its water) had
        nothing to bring, and a drag's next touch took back the last one's ring. From
        version 5, while the area's pool is short of `humidity` and `water_budget` has
        room, the touch brings new walkers of the area, and moves the area's own for the
        rest (docs/method.md, 5.3)."""
        want = self.params.touch_water
        mine = np.flatnonzero(self._warea.raw() == area)
        new = 0
        if self.touch_creates:  # a pool short of `humidity` brings new ones, in the budget
            short = self.pane.pool(self.params.humidity) - len(mine)
            new = max(0, min(want, short, self.params.water_budget - self._wx.n))
        if len(mine) > want - new:
            mine = np.sort(self.rng.choice(mine, want - new, replace=False))
        sx, sy = (float(v) for v in self._crystals.raw()[seed])
        hc, k = self.params.hc, len(mine) + new
        if k == 0:
            return
        tries = TOUCH_TRIES if self.touch_creates else CELL_TRIES
        u = self.rng.random((2, tries * k))  # every try at once: one nearest search
        r = hc * np.sqrt(1.0 + 3.0 * u[0])  # uniform in the ring's area: hc .. 2 hc
        px = (sx + r * np.cos(TWO_PI * u[1])).astype(np.float32)
        py = (sy + r * np.sin(TWO_PI * u[1])).astype(np.float32)
        if self.wrap:
            px, py = wrap_into(px, self.width), wrap_into(py, self.height)
        good = (px >= 0) & (px < self.width) & (py >= 0) & (py < self.height)
        pts = np.column_stack((px[good], py[good]))
        d2, own = _nearest_d2(self, pts), (pts[:, 0] - sx) ** 2 + (pts[:, 1] - sy) ** 2
        good[good] = (d2 >= np.float32(hc / 2) ** 2) & (own <= d2)  # the seed's water
        placed, pick = _first_good(good.reshape(tries, k))
        which = np.flatnonzero(placed)
        moved = which < len(mine)  # the pool's walkers first, then the new ones
        self._wx.raw()[mine[which[moved]]] = px[pick[moved]]
        self._wy.raw()[mine[which[moved]]] = py[pick[moved]]
        born = pick[~moved]
        if len(born):
            self._wx.append(px[born])
            self._wy.append(py[born])
            self._warea.append(np.full(len(born), area, np.int32))
            self.water_created += len(born)

    def step(self) -> Added:
        """One tick: walk -> crystallize -> settle (the growth rule) -> link and upsample ->
        update candidate cells -> follow the ice -> refill the pool (window mode)."""
        self._cell_work = CELL_WORK
        self._walk()
        self._drop_in_full_cells()
        hits, parents = self._admit(*self._crystallize())
        frozen, parents, pts, bounced = self.growth.settle(self, hits, parents)
        new = self._link(frozen, parents, pts)
        self._register(new)
        self._follow_ice(new)
        lost = self._relocate(bounced)  # hits that only counted go back to the pool
        if (self.params.replenish or self.params.grow) and not self.pane.on:  # (pane: refill)
            self._spawn(self._warea.raw()[frozen])
        self._forget_water(frozen, lost)
        self.pane.refill()
        self.tick += 1
        return self._close_tick(len(frozen))

    def melt(self, x: float, y: float, radius: float) -> Melted:
        """A warm finger at (x, y): crystals within `radius` px melt and their water returns
        to its area's pool (never above `humidity`; an area left with no ice loses its
        water); their links (and those of their children, which become roots) leave the
        skeleton; the cleared cells stop being candidate cells. Costs O(local ice)."""
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(radius) and radius > 0):
            raise ValueError(f"melt at ({x!r}, {y!r}) with radius {radius!r}: need finite values, "
                             "radius > 0")
        dead = self._crystals_near(x, y, radius)
        self._calive.raw()[dead] = False
        self.pane.melted(dead)
        pts = self._crystals.raw()[dead]
        cells, _ = self.grid.disc_cells(pts, self.params.hc)
        self.candidates.remove(cells, dead)
        self.search.remove(pts, dead)
        # A child lies within one link of its parent: look no further than that.
        near = self._crystals_near(x, y, radius + self._longest_link + 1.0)
        parents = self._parents.raw()
        orphans = near[np.isin(parents[near], dead)]
        self.growth.melted(dead, parents, orphans, near if len(dead) else dead)
        parents[orphans] = -1
        cut = np.concatenate([dead, orphans])
        segs = _rows(self._seg_range.raw()[cut])
        ups = _rows(self._ups_range.raw()[cut])
        segs, ups = segs[self._salive.raw()[segs]], ups[self._ualive.raw()[ups]]
        self._salive.raw()[segs] = False
        self._ualive.raw()[ups] = False
        self.water_melted += len(dead)
        dead_area = self._carea.raw()[dead]
        self._area_ice.raw()[:] -= np.bincount(dead_area, minlength=self._area_ice.n).astype(np.int32)
        self._return_water(dead_area)
        return Melted(dead, ups, segs, orphans)

    def segments_near(self, box: tuple[float, float, float, float], reach: float) -> np.ndarray:
        """Indices of live segments whose points may lie within `reach` x their length
        beside them of the px box (x0, y0, x1, y1): those of the links of the crystals
        near the box. A superset; callers test the exact extent."""
        pad = self._longest_link * (1.0 + reach) + 1.0
        x0, y0, x1, y1 = box
        ids = self._crystals_in_box(x0 - pad, y0 - pad, x1 + pad, y1 + pad)
        segs = _rows(self._seg_range.raw()[ids])
        return segs[self._salive.raw()[segs]]

    @property
    def crystal_alive(self) -> np.ndarray:
        """n bool: False for melted crystals (their rows stay so indices are stable)."""
        return self._calive.view()

    @property
    def upsampled_alive(self) -> np.ndarray:
        return self._ualive.view()

    @property
    def segments_alive(self) -> np.ndarray:
        return self._salive.view()

    @property
    def crystals(self) -> np.ndarray:
        """n x 2 float32 positions of crystal particles, seeds included."""
        return self._crystals.view()

    @property
    def parents(self) -> np.ndarray:
        """n int32: each crystal's parent crystal, -1 for a seed."""
        return self._parents.view()

    @property
    def upsampled(self) -> np.ndarray:
        """k x 2 float32 upsample particles (skeleton nodes that are not crystals)."""
        return self._ups.view()

    @property
    def upsampled_link(self) -> np.ndarray:
        """k int32: the crystal whose parent link holds each upsample particle."""
        return self._ups_link.view()

    @property
    def segments(self) -> np.ndarray:
        """s x 4 float32 (x0, y0, x1, y1): consecutive skeleton nodes along each chain."""
        return self._segs.view()

    @property
    def segments_link(self) -> np.ndarray:
        """s int32: the crystal whose parent link each segment belongs to."""
        return self._segs_link.view()

    @property
    def water(self) -> np.ndarray:
        """m x 2 float32 water particle positions (a fresh copy)."""
        return np.column_stack((self._wx.view(), self._wy.view()))

    @property
    def water_area(self) -> np.ndarray:
        return self._warea.view()

    def set_water(self, xy, area=0) -> None:
        """Replace every walker by walkers at `xy` (n x 2 px) in active area(s) `area` (one
        index for all, or one each): exact water for a test or a tool to start a tick
        from. The areas must exist (a touch opens one)."""
        xy = np.asarray(xy, np.float32).reshape(-1, 2)
        area = np.broadcast_to(np.asarray(area, np.int32), (len(xy),))
        if len(area) and not (area.min() >= 0 and area.max() < self._areas.n):
            raise ValueError(f"set_water: area {int(area.max())} does not exist "
                             f"({self._areas.n} areas)")
        self._keep_water(np.zeros(self._wx.n, bool))
        self._wx.append(np.ascontiguousarray(xy[:, 0]))
        self._wy.append(np.ascontiguousarray(xy[:, 1]))
        self._warea.append(np.ascontiguousarray(area))

    @property
    def areas(self) -> np.ndarray:
        """a x 5 float32 active areas: centre x, centre y, outer radius, inner radius
        (water is placed in the annulus between them), reach of the area's ice."""
        return self._areas.view()

    def nbytes(self) -> int:
        """Bytes held by the simulation's arrays (capacity, not just the filled rows)."""
        bufs = (self._crystals, self._parents, self._ups, self._ups_link, self._segs,
                self._segs_link, self._wx, self._wy, self._warea, self._areas, self._carea,
                self._calive, self._ualive, self._salive, self._seg_range, self._ups_range,
                self._area_ice, self.candidates, self.search, self.growth, self.clearance)
        return sum(b.nbytes() for b in bufs)

    # ---- phases ---------------------------------------------------------------------

    def _walk(self) -> None:
        """Eq. 2 for every walker; leavers are recreated inside their area (Sec. 3.4.2)."""
        m = self._wx.n
        if m == 0:
            return
        x, y = self._wx.raw(), self._wy.raw()
        dx, dy = walk_displacements(self.rng, m, self.params.step, self._clearance(x, y))
        x += dx
        y += dy
        if self.wrap:  # a tile: a walker leaving one edge comes in at the opposite one
            x[:], y[:] = wrap_into(x, self.width), wrap_into(y, self.height)
        lost = self._relocate(np.flatnonzero(self._outside(x, y)))
        self._forget_water(_NONE, lost)

    def _clearance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray | None:
        """Long jumps: each walker's clearance (None without them)."""
        if not self.params.long_jumps:
            return None
        cx, cy, r = self._area_columns()
        rim = r - np.hypot(x - cx, y - cy)
        return self.clearance.radii(x, y, rim)

    def _crystallize(self) -> tuple[np.ndarray, np.ndarray]:
        """Sec. 3.4.3: the walkers within hc of a crystal, and their nearest crystal."""
        if self._wx.n == 0:
            return np.empty(0, np.int64), np.empty(0, np.int32)
        return self.search.nearest(self._crystals.raw(), self._wx.raw(), self._wy.raw())

    def _drop_in_full_cells(self) -> None:
        """Water in a cell that lists CELL_CAP crystals has arrived at finished ice."""
        keys = self.grid.keys(self._wx.raw(), self._wy.raw())
        full = self.candidates.count[keys] >= CELL_CAP
        if full.any():
            self.water_dropped += int(full.sum())
            self._keep_water(~full)

    def _admit(self, frozen: np.ndarray, parents: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The freezes this tick takes: within FREEZE_WORK (the rest wait a tick), then
        those whose cells all stay within CELL_CAP (the rest of the water is dropped). In
        walker order, so both neighbour searches admit the same."""
        most = max(1, FREEZE_WORK // self._work_per_crystal)
        frozen, parents = frozen[:most], parents[:most]
        if self.candidates.count.max(initial=0) + len(frozen) <= CELL_CAP:
            return frozen, parents  # no cell can fill up this tick (cheap: one pass, no cells)
        pts = np.column_stack((self._wx.raw()[frozen], self._wy.raw()[frozen]))
        cells, owner = self.grid.disc_cells(pts, self.params.hc)
        if len(cells) == 0 or self.candidates.count[cells].max() + len(frozen) <= CELL_CAP:
            return frozen, parents
        order = np.argsort(cells, kind="stable")
        c = cells[order]
        first = np.concatenate(([0], np.flatnonzero(c[1:] != c[:-1]) + 1))
        rank = np.empty(len(c), np.int64)
        rank[order] = np.arange(len(c)) - np.repeat(first, np.diff(first, append=len(c)))
        over = self.candidates.count[cells] + rank >= CELL_CAP
        ok = np.bincount(owner[over], minlength=len(frozen)) == 0
        if not ok.all():
            self.water_dropped += int((~ok).sum())
            keep = np.ones(self._wx.n, bool)
            keep[frozen[~ok]] = False
            self._keep_water(keep)
            # The kept walkers move down; frozen ones keep their order.
            frozen, parents = np.searchsorted(np.flatnonzero(keep), frozen[ok]), parents[ok]
        return frozen, parents

    def _link(self, frozen: np.ndarray, parents: np.ndarray, pts: np.ndarray) -> slice:
        """Frozen walkers become crystals at `pts` linked to their parents; links are upsampled."""
        new = self._add_crystals(pts, parents, self._ice_area(frozen, parents))
        # On a tile the link runs to the parent's image beside its child (across an edge
        # its segments and upsample particles lie off the tile; the geometry wraps them).
        size = (self.width, self.height) if self.wrap else None
        tail = image_near(self._crystals.raw()[parents], pts, size)
        ups, ups_link, segs, segs_link = upsample(tail, pts, self.params.D)
        self._seg_range.append(_ranges(segs_link, len(frozen), self._segs.n))
        self._ups_range.append(_ranges(ups_link, len(frozen), self._ups.n))
        self._ups.append(ups)
        self._ualive.append(np.ones(len(ups), bool))
        self._salive.append(np.ones(len(segs), bool))
        self._ups_link.append(ups_link.astype(np.int32) + new.start)
        self._segs.append(segs)
        self._segs_link.append(segs_link.astype(np.int32) + new.start)
        if len(frozen):
            d = pts - tail
            self._longest_link = max(self._longest_link, float(np.hypot(d[:, 0], d[:, 1]).max()))
        return new

    def _ice_area(self, frozen: np.ndarray, parents: np.ndarray) -> np.ndarray:
        """The area each new crystal belongs to: its water's (the paper's pools). With a
        launch circle, the area of the ice it grew on, so each area's reach (and circle)
        follows its own frost, not water that strayed onto a neighbour's."""
        if self.params.launch:
            return self._carea.raw()[parents]
        return self._warea.raw()[frozen]

    def _add_crystals(self, pts: np.ndarray, parents: np.ndarray, area: np.ndarray) -> slice:
        """Append crystals (live) with their parents and areas; count them in their areas."""
        new = self._crystals.append(pts)
        self._parents.append(parents)
        self._carea.append(area)
        self._calive.append(np.ones(len(pts), bool))
        self._area_ice.raw()[:] += np.bincount(area, minlength=self._area_ice.n).astype(np.int32)
        return new

    def _register(self, new: slice) -> None:
        """Sec. 3.4.1: mark the cells the new crystals' freezing areas reach."""
        if new.stop == new.start:
            return
        pts = self._crystals.raw()[new]
        ids = np.arange(new.start, new.stop, dtype=np.int32)
        cells, owner = self.grid.disc_cells(pts, self.params.hc)
        self.clearance.lower(cells[self.candidates.count[cells] == 0])
        self.candidates.insert(cells, ids[owner])
        self.search.insert(pts, ids)

    # ---- helpers --------------------------------------------------------------------

    def _crystals_near(self, x: float, y: float, radius: float) -> np.ndarray:
        """Ascending indices of live crystals within `radius` of (x, y)."""
        ids = self._crystals_in_box(x - radius, y - radius, x + radius, y + radius)
        c = self._crystals.raw()[ids].astype(np.float64)
        return ids[np.hypot(c[:, 0] - x, c[:, 1] - y) < radius]

    def _crystals_in_box(self, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
        """Ascending indices of the live crystals listed in the cells under a px box (a
        superset of those inside it: every crystal is listed in its own cell)."""
        cols, rows = self.grid.span(x0, y0, x1, y1)
        cells = (rows[:, None] * self.grid.cols + cols[None, :]).ravel()
        ids, valid = self.candidates.gather(cells)
        return np.unique(ids[valid])

    def _area_columns(self):
        """Centre x, centre y and outer radius of each walker's area (scalars for one area)."""
        areas = self._areas.raw()
        if len(areas) == 1:
            return areas[0, :3]
        w = self._warea.raw()  # one column at a time: much cheaper than gathering rows
        return tuple(np.take(np.ascontiguousarray(areas[:, i]), w) for i in range(3))

    def _outside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Walkers off the screen or outside their own active area."""
        cx, cy, r = self._area_columns()
        ox, oy = x - cx, y - cy
        if self.wrap:  # a tile: an area reaches across the edges
            ox, oy = nearest_image(ox, self.width), nearest_image(oy, self.height)
        off = (x < 0) | (x >= self.width) | (y < 0) | (y >= self.height)
        return off | (ox * ox + oy * oy > r * r)

    def _place(self, area: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Uniform spots in each walker's area (its annulus), on screen and outside
        candidate cells; `ok` is False where there is no free spot. Sampling the disc
        places almost every walker in a round or two while an area is mostly glass; the
        few left (an area nearly full of ice) are placed from its free cells directly,
        so a full area costs one look at its cells, never a long rejection loop."""
        if self.pane.on:
            return self.pane.place(len(area))
        n = len(area)
        x, y = np.zeros(n, np.float32), np.zeros(n, np.float32)
        ok = np.zeros(n, bool)
        # An area whose annulus has no free cell cannot place by disc draws: to its cells.
        direct = self._annulus_full(area) if self.batched else np.zeros(n, bool)
        todo = np.flatnonzero(~direct)
        # A launch circle may cross other areas' ice: give it more tries before the cells.
        for tries in ((1, 2) if n > 1024 else (4,)) + ((16,) if self.params.launch else ()):
            if len(todo) == 0:
                break
            px, py = self._disc_spots(np.tile(area[todo], tries))
            placed, pick = _first_good(self._free(px, py).reshape(tries, len(todo)))
            x[todo[placed]], y[todo[placed]] = px[pick], py[pick]
            ok[todo[placed]] = True
            todo = todo[~placed]
        if len(todo) and not self.batched:  # session files before version 3
            for a in np.unique(area[todo]):
                mine = todo[area[todo] == a]
                x[mine], y[mine], ok[mine] = self._cell_spots(int(a), len(mine))
        elif self.batched and (len(todo) or direct.any()):
            todo = np.union1d(todo, np.flatnonzero(direct))[:self._cell_work]
            self._cell_work -= len(todo)
            x[todo], y[todo], ok[todo] = self._cell_spots_all(area[todo])
        return x, y, ok

    def _disc_spots(self, area: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A uniform point of each area's annulus (which may reach off the screen)."""
        a = self._areas.raw()[area]
        u = self.rng.random((2, len(a)), dtype=np.float32)
        inner, outer = self._shell(a)
        r = np.sqrt(inner ** 2 + u[0] * (outer ** 2 - inner ** 2))
        th = u[1] * TWO_PI
        x, y = a[:, 0] + r * np.cos(th), a[:, 1] + r * np.sin(th)
        if self.wrap:
            return wrap_into(x, self.width), wrap_into(y, self.height)
        return x, y

    def _shell(self, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Inner and outer radius water is placed between, for area rows `a`. With a
        launch circle (fern rule 4) both are `launch` px beyond the area's farthest ice,
        while that circle lies inside the area."""
        if not self.params.launch:
            return a[:, 3], a[:, 2]
        ring = a[:, 4] + np.float32(self.params.launch)
        on = ring < a[:, 2]
        return np.where(on, ring, a[:, 3]), np.where(on, ring, a[:, 2])

    def _relocate(self, idx: np.ndarray) -> np.ndarray:
        """Place walkers `idx` again in their areas; returns those with no free spot."""
        if len(idx) == 0:
            return idx
        nx, ny, ok = self._place(self._warea.raw()[idx])
        self._wx.raw()[idx[ok]] = nx[ok]
        self._wy.raw()[idx[ok]] = ny[ok]
        return idx[~ok]

    def _free(self, px: np.ndarray, py: np.ndarray) -> np.ndarray:
        """On the screen and in no candidate cell."""
        good = (px >= 0) & (px < self.width) & (py >= 0) & (py < self.height)
        good[good] = self.candidates.count[self.grid.keys(px[good], py[good])] == 0
        return good

    def _cell_spots(self, area: int, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """k uniform spots of `area`'s annulus outside candidate cells: a free cell that
        meets the annulus at random (cells are equal), a uniform point in it, kept if it
        lies in the annulus and on the screen; CELL_TRIES such draws each at most."""
        cx, cy, r_out, r_in = (float(v) for v in self._areas.raw()[area, :4])
        cells = self._free_cells(cx, cy, r_out, r_in)
        if len(cells) == 0 and self.params.grow:
            # Growth mode: a front ring all ice may enclose a melt's clearing, and an area
            # all ice may still hold glass between fronds; the water goes there, so a
            # wiped path refreezes.
            r_in, cells = 0.0, self._free_cells(cx, cy, r_out, 0.0)
            if len(cells) == 0:
                return glass_spots(self, self._free_cells(cx, cy, r_out, 0.0, free=False), k)
        if len(cells) == 0:
            return np.zeros(k, np.float32), np.zeros(k, np.float32), np.zeros(k, bool)
        u = self.rng.random((3, CELL_TRIES * k), dtype=np.float32)
        cell = cells[np.minimum((u[0] * len(cells)).astype(np.int64), len(cells) - 1)]
        s = np.float32(self.grid.cell)
        px = (cell % self.grid.cols + u[1]) * s
        py = (cell // self.grid.cols + u[2]) * s
        d2 = (px - cx) ** 2 + (py - cy) ** 2
        good = (d2 <= r_out * r_out) & (d2 >= r_in * r_in) & (px < self.width) & (py < self.height)
        placed, pick = _first_good(good.reshape(CELL_TRIES, k))
        x, y = np.zeros(k, np.float32), np.zeros(k, np.float32)
        x[placed], y[placed] = px[pick], py[pick]
        return x, y, placed

    def _cell_spots_all(self, area: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`_cell_spots` for walkers of any areas at once: each walker draws from its own
        area's cells (`_area_cells`), CELL_TRIES rounds in all. The work is a few numpy
        passes over the walkers whatever the number of areas: one call per area cost
        ~1.5 ms, and a storm of touches made tens of areas (docs/method.md, 4.3)."""
        ua, inv = np.unique(area, return_inverse=True)
        plans = [self._area_cells(int(a)) for a in ua]
        cells = np.concatenate([p[0] for p in plans]) if plans else _NONE
        lens = np.array([len(p[0]) for p in plans], np.int64)
        off = np.cumsum(lens) - lens
        r_in = np.array([p[1] for p in plans], np.float32)
        glass = np.array([p[2] for p in plans], bool)
        cx, cy, r_out = (np.ascontiguousarray(self._areas.raw()[ua, i]) for i in range(3))
        k = len(area)
        x, y, ok = np.zeros(k, np.float32), np.zeros(k, np.float32), np.zeros(k, bool)
        todo = np.flatnonzero(lens[inv] > 0)
        if len(todo) == 0:
            return x, y, ok
        # CELL_TRIES draws each, drawn at once as `_cell_spots` draws them (one area's
        # walkers land where they did, area by area); a glass check on the first draws,
        # then on the later ones of the walkers still without a spot.
        g = np.tile(inv[todo], CELL_TRIES)
        u = self.rng.random((3, len(g)), dtype=np.float32)
        cell = cells[off[g] + np.minimum((u[0] * lens[g]).astype(np.int64), lens[g] - 1)]
        s = np.float32(self.grid.cell)
        px, py = (cell % self.grid.cols + u[1]) * s, (cell // self.grid.cols + u[2]) * s
        d2 = (px - cx[g]) ** 2 + (py - cy[g]) ** 2
        good = (d2 <= r_out[g] ** 2) & (glass[g] | (d2 >= r_in[g] ** 2))
        good &= (px < self.width) & (py < self.height)
        check = good & glass[g]  # glass between fronds: clear of every crystal
        first = np.arange(len(g)) < len(todo)
        self._on_glass(px, py, good, check & first)
        self._on_glass(px, py, good, check & ~first & ~np.tile(good[:len(todo)], CELL_TRIES))
        placed, pick = _first_good(good.reshape(CELL_TRIES, len(todo)))
        x[todo[placed]], y[todo[placed]], ok[todo[placed]] = px[pick], py[pick], True
        return x, y, ok

    def _on_glass(self, px: np.ndarray, py: np.ndarray, good: np.ndarray, check: np.ndarray) -> None:
        """`good` stays True where `check` only if the point is at least hc / 2 from every
        live crystal."""
        d2 = _nearest_d2(self, np.column_stack((px[check], py[check])))
        good[check] = d2 >= np.float32(self.params.hc / 2) ** 2

    def _area_cells(self, area: int) -> tuple[np.ndarray, float, bool, bool]:
        """(cells, inner radius, glass, full) an area's water is drawn from when its disc
        draws failed: its annulus's free cells; in growth mode, else its whole disc's free
        cells, else any cell of its disc, where a spot must be glass (`glass` True).
        `full`: its annulus has no free cell. Kept until the ice changes (a tick's
        growth, a touch, a melt)."""
        key = (self._crystals.n, self.water_melted)
        if key != self._plans_key:
            self._plans, self._plans_key = {}, key
        if area not in self._plans:
            cx, cy, r_out, r_in = (float(v) for v in self._areas.raw()[area, :4])
            flat, near2, far2 = self._box_cells(cx, cy, r_out)
            disc = near2 <= r_out ** 2
            free = disc & (self.candidates.count[flat] == 0)
            cells, glass = flat[free & (far2 >= r_in ** 2)], False
            full = len(cells) == 0
            if full and self.params.grow:
                r_in, cells = 0.0, flat[free]
                if len(cells) == 0:
                    cells, glass = flat[disc], True
            self._plans[area] = (cells, r_in, glass, full)
            self._full[area] = full
        return self._plans[area]

    def _annulus_full(self, area: np.ndarray) -> np.ndarray:
        """Per walker: its area's annulus held no free cell when its cells were last
        listed (`_area_cells`; at most a tick old). Listing every area's cells for every
        placement cost ~0.1 ms an area, though few areas ever fill; a stale answer only
        sends a walker the other way to a valid spot."""
        if not any(self._full.values()):  # (the usual case: no area has filled)
            return np.zeros(len(area), bool)
        ua, inv = np.unique(area, return_inverse=True)
        return np.array([self._full.get(int(a), False) for a in ua], bool)[inv]

    def _box_cells(self, cx: float, cy: float, r: float):
        """The flat indices of the cells under the disc's bounding box, with the squared
        distance from (cx, cy) to each cell's nearest and farthest point."""
        g = self.grid
        cols, rows = g.span(cx - r, cy - r, cx + r, cy + r)
        x0, y0 = cols[None, :] * g.cell, rows[:, None] * g.cell
        near_x, near_y = np.clip(cx, x0, x0 + g.cell) - cx, np.clip(cy, y0, y0 + g.cell) - cy
        far_x = np.maximum(np.abs(x0 - cx), np.abs(x0 + g.cell - cx))
        far_y = np.maximum(np.abs(y0 - cy), np.abs(y0 + g.cell - cy))
        flat = rows[:, None] * g.cols + cols[None, :]
        return flat.ravel(), (near_x ** 2 + near_y ** 2).ravel(), (far_x ** 2 + far_y ** 2).ravel()

    def _free_cells(self, cx: float, cy: float, r_out: float, r_in: float,
                    free: bool = True) -> np.ndarray:
        """Flat indices of the cells with no crystal listed (any cell if not `free`) that
        meet the annulus."""
        g = self.grid
        cols, rows = g.span(cx - r_out, cy - r_out, cx + r_out, cy + r_out)
        x0, y0 = cols[None, :] * g.cell, rows[:, None] * g.cell
        near_x = np.clip(cx, x0, x0 + g.cell) - cx
        near_y = np.clip(cy, y0, y0 + g.cell) - cy
        far_x = np.maximum(np.abs(x0 - cx), np.abs(x0 + g.cell - cx))
        far_y = np.maximum(np.abs(y0 - cy), np.abs(y0 + g.cell - cy))
        meets = (near_x ** 2 + near_y ** 2 <= r_out ** 2) & (far_x ** 2 + far_y ** 2 >= r_in ** 2)
        flat = (rows[:, None] * g.cols + cols[None, :])
        return flat[meets & ((self.candidates.count[flat] == 0) | (not free))]

    def _spawn(self, area: np.ndarray) -> None:
        """Create water for `area[i]`; those with no free spot are dropped."""
        x, y, ok = self._place(area)
        self._wx.append(x[ok])
        self._wy.append(y[ok])
        self._warea.append(area[ok])
        self.water_created += int(ok.sum())
        self.water_dropped += int((~ok).sum())

    def _areas_for(self, pts: np.ndarray) -> np.ndarray:
        """The area of each touch in turn: the one whose disc holds it (nearest centre,
        lowest index among equals), else a new area opened there."""
        out = np.empty(len(pts), np.int32)
        for k, (x, y) in enumerate(pts):
            a = self._areas.raw()
            d2 = (a[:, 0] - x) ** 2 + (a[:, 1] - y) ** 2
            inside = d2 <= a[:, 2] ** 2
            if inside.any():
                out[k] = np.argmin(np.where(inside, d2, np.inf))
                continue
            row = np.array([[x, y, self.params.active_radius, 0.0, 0.0]], np.float32)
            out[k] = self._areas.append(row).start
            self._area_ice.append(np.zeros(1, np.int32))
        return out

    def _fill(self, areas: np.ndarray) -> None:
        """Top the pools of `areas` up to `humidity` within `water_budget`; when the budget
        is spent, the areas holding more than a fair share give theirs up first."""
        counts = np.bincount(self._warea.raw(), minlength=self._areas.n)
        want = np.maximum(0, self.pane.pool(self.params.humidity) - counts[areas])
        room = self.params.water_budget - self._wx.n
        if want.sum() > room:
            holding = counts > 0
            holding[areas] = True
            share = self.params.water_budget // int(holding.sum())
            want = np.minimum(want, np.maximum(0, share - counts[areas]))
            room += self._trim(counts, areas, int(want.sum()) - room, share)
        give = np.minimum(want, np.maximum(0, room - (np.cumsum(want) - want)))
        self._spawn(np.repeat(areas.astype(np.int32), give))

    def _trim(self, counts: np.ndarray, areas: np.ndarray, need: int, share: int) -> int:
        """Drop up to `need` walkers of the areas other than `areas`, taking the largest
        pools down to a common level no lower than `share`; returns how many went.
        Each area keeps its oldest walkers (the first in array order)."""
        if need <= 0:
            return 0
        others = counts.copy()
        others[areas] = 0  # (an area being topped up holds less than `share`: never cut)
        limit = np.minimum(counts, _level(others, need, share))
        wa = self._warea.raw()
        order = np.argsort(wa, kind="stable")
        rank = np.empty(len(wa), np.int64)
        rank[order] = np.arange(len(wa)) - np.repeat(np.cumsum(counts) - counts, counts)
        keep = rank < limit[wa]
        self._keep_water(keep)
        return int((~keep).sum())

    def _return_water(self, area: np.ndarray) -> None:
        """Melted crystals' water goes back to their areas, never above `humidity` nor
        the budget; an area with no ice left has nothing to grow on and loses its pool.
        A kept pool (replenish, growth, the pane) is topped up: in a frosted area it had
        drained for want of glass, and the melt made glass."""
        empty = self._area_ice.raw() == 0
        if empty.any():
            self._keep_water(~empty[self._warea.raw()])
        if self.params.replenish or self.params.grow or self.pane.on:
            self._fill(np.unique(area[~empty[area]]))
            return
        counts = np.bincount(self._warea.raw(), minlength=self._areas.n)
        back = np.bincount(area[~empty[area]], minlength=self._areas.n)
        back = np.minimum(back, np.maximum(0, self.pane.pool(self.params.humidity) - counts))
        room = max(0, self.params.water_budget - self._wx.n)
        spawn = np.repeat(np.arange(len(back), dtype=np.int32), back)[:room]
        self._spawn(spawn)

    def _forget_water(self, frozen: np.ndarray, dropped: np.ndarray = _NONE) -> None:
        """Frozen water is spent (the pool shrinks as ice grows); `dropped` water found no
        free spot to be placed again."""
        if len(frozen) == 0 and len(dropped) == 0:
            return
        self.water_frozen += len(frozen)
        self.water_dropped += len(dropped)
        keep = np.ones(self._wx.n, bool)
        keep[frozen] = False
        keep[dropped] = False
        self._keep_water(keep)

    def _keep_water(self, keep: np.ndarray) -> None:
        for buf in (self._wx, self._wy, self._warea):
            buf.keep(keep)

    def _follow_ice(self, new: slice) -> None:
        """Growth mode: each area's annulus rides on its ice front, half an active radius
        either side of the farthest crystal, so its water can still reach the ice.
        Costs O(new crystals): only the areas of this tick's crystals change. A launch
        circle needs the reach too; without growth mode the areas keep their size, and the
        pane's one area (window mode) always covers the screen."""
        area = self._carea.raw()[new]
        if len(area) == 0 or self.pane.on or not (self.params.grow or self.params.launch):
            return
        areas = self._areas.raw()
        d = np.hypot(*(self._crystals.raw()[new] - areas[area, :2]).T)
        np.maximum.at(areas[:, 4], area, d)
        if not self.params.grow:
            return
        band = np.float32(self.params.active_radius / 2)
        touched = np.unique(area)
        reach = areas[touched, 4]
        areas[touched, 2] = np.maximum(self.params.active_radius, reach + band)
        areas[touched, 3] = np.maximum(0, reach - band)

    def _close_tick(self, frozen: int) -> Added:
        now = (self._crystals.n, self._ups.n, self._segs.n)
        c, u, s = (slice(a, b) for a, b in zip(self._mark, now, strict=True))
        self._mark = now
        self.added = Added(self.tick, c, u, s, frozen)
        return self.added


def _ranges(link: np.ndarray, n: int, offset: int) -> np.ndarray:
    """n x 2 (first row, count) of each link's rows, given the ascending link index of
    rows appended at `offset`."""
    count = np.bincount(link, minlength=n).astype(np.int32)
    first = offset + np.cumsum(count) - count
    return np.column_stack((first, count)).astype(np.int32)


def _rows(ranges: np.ndarray) -> np.ndarray:
    """The row indices of (first, count) ranges, back to back."""
    first, count = ranges[:, 0].astype(np.int64), ranges[:, 1].astype(np.int64)
    total = int(count.sum())
    if total == 0:
        return np.empty(0, np.int64)
    starts = np.repeat(first - (np.cumsum(count) - count), count)
    return starts + np.arange(total)


def _level(counts: np.ndarray, need: int, floor: int) -> int:
    """The highest level >= floor such that cutting every count down to it frees at least
    `need` (or `floor` itself if even that frees less): a water-filling cut."""
    lo, hi = floor, int(counts.max(initial=0))
    if np.maximum(counts - lo, 0).sum() < need:
        return lo
    while lo < hi:  # invariant: cutting to lo frees enough
        mid = (lo + hi + 1) // 2
        if np.maximum(counts - mid, 0).sum() >= need:
            lo = mid
        else:
            hi = mid - 1
    return lo
