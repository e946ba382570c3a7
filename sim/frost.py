"""The frost simulation of Sec. 3.3-3.4: water walks, freezes near crystals, and grows a skeleton.

A tick is a short list of phases (see `FrostSim.step`):
walk -> crystallize -> link and upsample -> update candidate cells.
Everything is plain numpy data; rendering reads the arrays and the per-tick `added` slices.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .buffers import CellLists, Growable
from .grid import HashGrid
from .params import Params

TWO_PI = np.float32(2.0 * np.pi)
# Rejection sampling of a water particle's spot gives up after about this many tries:
# an active area filled with ice has no free spot left and its water is dropped.
MAX_PLACE_TRIES = 32
# grid9 queries walkers in chunks of this many to bound the gather matrix.
_GRID9_CHUNK = 4096


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


def walk_displacements(rng: np.random.Generator, m: int, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 2: each walker moves a*(cos t, sin t), a ~ U[0, step], t ~ U[0, 2 pi)."""
    u = rng.random((2, m), dtype=np.float32)
    a = u[0] * np.float32(step)
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


def _on_screen_f32(v: float, size: int) -> np.float32:
    """`v` (0 <= v < size) as float32, still below `size`: 759.99999999 would round up
    to 760.0, off a 760 px screen, so it becomes the largest float32 below 760."""
    return min(np.float32(v), np.nextafter(np.float32(size), np.float32(0)))


class FrostSim:
    """Window frost on a `width` x `height` px screen (SPEC.md)."""

    def __init__(self, params: Params | None = None, width: int = 760, height: int = 1280,
                 seed: int = 0):
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 < v <= 16384:
                raise ValueError(f"{name}={v!r} must be a whole number of px in [1, 16384]")
        self.params = params if params is not None else Params()
        self.width, self.height = int(width), int(height)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.grid = HashGrid(self.width, self.height, self.params.hc)
        self.tick = 0
        self._hc2 = np.float32(self.params.hc) ** 2
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
        # Water, structure of arrays; each particle belongs to one active area.
        self._wx = Growable(np.float32, capacity=self.params.humidity)
        self._wy = Growable(np.float32, capacity=self.params.humidity)
        self._warea = Growable(np.int32, capacity=self.params.humidity)
        # centre x, centre y, outer and inner radius (water lives in the annulus), reach of its ice
        self._areas = Growable(np.float32, (5,))
        self._carea = Growable(np.int32)  # the area whose water became each crystal
        self.candidates = CellLists(self.grid.size)  # Fig. 3d: state = count > 0
        self._own = CellLists(self.grid.size + 1) if self.params.neighbor_search == "grid9" else None
        self.water_created = 0
        self.water_frozen = 0
        self.water_dropped = 0
        self.water_melted = 0
        self._mark = (0, 0, 0)
        self.added = Added(0, slice(0, 0), slice(0, 0), slice(0, 0), 0)

    # ---- public API -------------------------------------------------------------

    def touch(self, x: float, y: float) -> int:
        """Plant a seed crystal at (x, y) and its active area; returns the area's index."""
        if not (np.isfinite(x) and np.isfinite(y) and 0 <= x < self.width and 0 <= y < self.height):
            raise ValueError(f"touch ({x!r}, {y!r}) is off the {self.width}x{self.height} screen")
        x, y = _on_screen_f32(x, self.width), _on_screen_f32(y, self.height)
        row = [[x, y, self.params.active_radius, 0.0, 0.0]]
        area = self._areas.append(np.array(row, np.float32)).start
        seed = self._crystals.append(np.array([[x, y]], np.float32))
        self._parents.append(np.array([-1], np.int32))
        self._carea.append(np.array([area], np.int32))
        self._calive.append(np.ones(1, bool))
        self._register(seed)
        self._spawn(np.full(self.params.humidity, area, np.int32))
        return area

    def step(self) -> Added:
        """One tick: walk -> crystallize -> link and upsample -> update candidate cells."""
        self._walk()
        frozen, parents = self._crystallize()
        new = self._link(frozen, parents)
        self._register(new)
        if self.params.grow:
            self._follow_ice(new)
        if self.params.replenish or self.params.grow:
            self._spawn(self._warea.raw()[frozen])
        self._forget_water(frozen)
        self.tick += 1
        return self._close_tick(len(frozen))

    def melt(self, x: float, y: float, radius: float) -> Melted:
        """A warm finger at (x, y): crystals within `radius` px melt and their water returns
        to its area's pool; their links (and those of their children, which become roots)
        leave the skeleton; the cleared cells stop being candidate cells. Costs O(local ice)
        but for one scan of the parent and link arrays."""
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(radius) and radius > 0):
            raise ValueError(f"melt at ({x!r}, {y!r}) with radius {radius!r}: need finite values, "
                             "radius > 0")
        dead = self._crystals_near(x, y, radius)
        self._calive.raw()[dead] = False
        pts = self._crystals.raw()[dead]
        cells, _ = self.grid.disc_cells(pts, self.params.hc)
        self.candidates.remove(cells, dead)
        if self._own is not None:
            self._own.remove(self.grid.keys(pts[:, 0], pts[:, 1]), dead)
        parents = self._parents.raw()
        orphans = np.flatnonzero(np.isin(parents, dead) & self._calive.raw())
        parents[orphans] = -1
        cut = np.concatenate([dead, orphans])
        segs = np.flatnonzero(np.isin(self._segs_link.raw(), cut) & self._salive.raw())
        ups = np.flatnonzero(np.isin(self._ups_link.raw(), cut) & self._ualive.raw())
        self._salive.raw()[segs] = False
        self._ualive.raw()[ups] = False
        self.water_melted += len(dead)
        self._spawn(self._carea.raw()[dead])
        return Melted(dead, ups, segs, orphans)

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

    @property
    def areas(self) -> np.ndarray:
        """a x 5 float32 active areas: centre x, centre y, outer radius, inner radius
        (water is placed in the annulus between them), reach of the area's ice."""
        return self._areas.view()

    def nbytes(self) -> int:
        """Bytes held by the simulation's arrays (capacity, not just the filled rows)."""
        bufs = (self._crystals, self._parents, self._ups, self._ups_link, self._segs,
                self._segs_link, self._wx, self._wy, self._warea, self._areas, self._carea,
                self._calive, self._ualive, self._salive, self.candidates)
        own = self._own.nbytes() if self._own is not None else 0
        return sum(b.nbytes() for b in bufs) + own

    # ---- phases ---------------------------------------------------------------------

    def _walk(self) -> None:
        """Eq. 2 for every walker; leavers are recreated inside their area (Sec. 3.4.2)."""
        m = self._wx.n
        if m == 0:
            return
        dx, dy = walk_displacements(self.rng, m, self.params.step)
        x, y = self._wx.raw(), self._wy.raw()
        x += dx
        y += dy
        left = np.flatnonzero(self._outside(x, y))
        if len(left) == 0:
            return
        nx, ny, ok = self._place(self._warea.raw()[left])
        x[left[ok]] = nx[ok]
        y[left[ok]] = ny[ok]
        if not ok.all():
            keep = np.ones(m, bool)
            keep[left[~ok]] = False
            self.water_dropped += int((~ok).sum())
            self._keep_water(keep)

    def _crystallize(self) -> tuple[np.ndarray, np.ndarray]:
        """Sec. 3.4.3: the walkers within hc of a crystal, and their nearest crystal."""
        if self._wx.n == 0:
            return np.empty(0, np.int64), np.empty(0, np.int32)
        x, y = self._wx.raw(), self._wy.raw()
        keys = self.grid.keys(x, y)
        if self._own is not None:
            return self._nearest_grid9(x, y, keys)
        w = np.flatnonzero(self.candidates.count[keys] > 0)
        counts, ids = self.candidates.gather_flat(keys[w])
        return self._nearest(w, counts, ids, x, y)

    def _link(self, frozen: np.ndarray, parents: np.ndarray) -> slice:
        """Frozen walkers become crystals linked to their parents; links are upsampled."""
        pts = np.column_stack((self._wx.raw()[frozen], self._wy.raw()[frozen]))
        new = self._crystals.append(pts)
        self._parents.append(parents)
        self._carea.append(self._warea.raw()[frozen])
        self._calive.append(np.ones(len(frozen), bool))
        if len(frozen):
            ups, ups_link, segs, segs_link = upsample(self.crystals[parents], pts, self.params.D)
            self._ups.append(ups)
            self._ualive.append(np.ones(len(ups), bool))
            self._salive.append(np.ones(len(segs), bool))
            self._ups_link.append(ups_link.astype(np.int32) + new.start)
            self._segs.append(segs)
            self._segs_link.append(segs_link.astype(np.int32) + new.start)
        return new

    def _register(self, new: slice) -> None:
        """Sec. 3.4.1: mark the cells the new crystals' freezing areas reach."""
        if new.stop == new.start:
            return
        pts = self._crystals.raw()[new]
        ids = np.arange(new.start, new.stop, dtype=np.int32)
        cells, owner = self.grid.disc_cells(pts, self.params.hc)
        self.candidates.insert(cells, ids[owner])
        if self._own is not None:
            self._own.insert(self.grid.keys(pts[:, 0], pts[:, 1]), ids)

    # ---- helpers --------------------------------------------------------------------

    def _crystals_near(self, x: float, y: float, radius: float) -> np.ndarray:
        """Ascending indices of live crystals within `radius` of (x, y). Every crystal is
        listed in its own cell, so the cells under the disc's bounding box hold them all."""
        g = self.grid
        cx = np.arange(max(int((x - radius) // g.cell), 0), min(int((x + radius) // g.cell), g.cols - 1) + 1)
        cy = np.arange(max(int((y - radius) // g.cell), 0), min(int((y + radius) // g.cell), g.rows - 1) + 1)
        cells = (cy[:, None] * g.cols + cx[None, :]).ravel()
        ids, valid = self.candidates.gather(cells)
        ids = np.unique(ids[valid])
        c = self._crystals.raw()[ids].astype(np.float64)
        return ids[np.hypot(c[:, 0] - x, c[:, 1] - y) < radius]

    def _nearest(self, w: np.ndarray, counts: np.ndarray, ids: np.ndarray,
                 x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Of walkers `w`, each with `counts[i] > 0` crystal ids listed back to back in `ids`,
        those within hc of one, and the nearest (lowest index among equals). Both neighbour
        searches share this, so their distances are the same floats."""
        if len(w) == 0:
            return w, np.empty(0, np.int32)
        starts = np.cumsum(counts) - counts
        rows = np.repeat(np.arange(len(w)), counts)
        c = self._crystals.raw()
        dx = c[ids, 0] - x[w][rows]
        dy = c[ids, 1] - y[w][rows]
        d2 = dx * dx + dy * dy
        dmin = np.minimum.reduceat(d2, starts)
        tied = np.where(d2 == dmin[rows], ids, np.iinfo(np.int32).max)
        parent = np.minimum.reduceat(tied, starts)
        hit = dmin < self._hc2
        return w[hit], parent[hit].astype(np.int32)

    def _nearest_grid9(self, x: np.ndarray, y: np.ndarray, keys: np.ndarray):
        """Fig. 9's baseline: every walker against the crystals of its 9 surrounding cells."""
        cols, rows = self.grid.cols, self.grid.rows
        kx, ky = keys % cols, keys // cols
        hits, parents = [], []
        for lo in range(0, len(keys), _GRID9_CHUNK):
            sl = slice(lo, lo + _GRID9_CHUNK)
            nx = kx[sl, None] + np.array([-1, 0, 1, -1, 0, 1, -1, 0, 1])
            ny = ky[sl, None] + np.array([-1, -1, -1, 0, 0, 0, 1, 1, 1])
            inside = (nx >= 0) & (nx < cols) & (ny >= 0) & (ny < rows)
            cells = np.where(inside, ny * cols + nx, self.grid.size)  # last cell stays empty
            width = int(self._own.count[cells].max(initial=0))
            ids = self._own.items[cells, :width].reshape(len(cells), -1)
            valid = (np.arange(width) < self._own.count[cells][..., None]).reshape(len(cells), -1)
            counts = valid.sum(axis=1)
            some = counts > 0
            w = np.arange(sl.start, sl.start + len(cells))[some]
            h, p = self._nearest(w, counts[some], ids[some][valid[some]], x, y)
            hits.append(h)
            parents.append(p)
        return np.concatenate(hits), np.concatenate(parents)

    def _outside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Walkers off the screen or outside their own active area."""
        areas = self._areas.raw()
        if len(areas) == 1:
            cx, cy, r = areas[0, :3]
        else:
            a = areas[self._warea.raw()]
            cx, cy, r = a[:, 0], a[:, 1], a[:, 2]
        ox, oy = x - cx, y - cy
        off = (x < 0) | (x >= self.width) | (y < 0) | (y >= self.height)
        return off | (ox * ox + oy * oy > r * r)

    def _place(self, area: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Uniform spots in each walker's area, on screen and outside candidate cells.
        Bounded rejection sampling: rounds of 1, 2, 4, 8, 16 tries per particle still
        unplaced (31 in all; 4, 8, 16 for a small batch), so a nearly full area costs a
        few rounds, not 31. `ok` is False where no free spot was found."""
        n = len(area)
        x, y = np.zeros(n, np.float32), np.zeros(n, np.float32)
        ok = np.zeros(n, bool)
        todo = np.arange(n)
        areas = self._areas.raw()
        tries = 1 if n > 1024 else 4  # a few respawns: spend tries, not rounds
        while len(todo) and tries <= MAX_PLACE_TRIES // 2:
            a = areas[np.tile(area[todo], tries)]
            u = self.rng.random((2, len(a)), dtype=np.float32)
            r = np.sqrt(a[:, 3] ** 2 + u[0] * (a[:, 2] ** 2 - a[:, 3] ** 2))  # uniform on the annulus
            th = u[1] * TWO_PI
            px, py = a[:, 0] + r * np.cos(th), a[:, 1] + r * np.sin(th)
            good = (px >= 0) & (px < self.width) & (py >= 0) & (py < self.height)
            good[good] = self.candidates.count[self.grid.keys(px[good], py[good])] == 0
            good = good.reshape(tries, len(todo))
            placed = good.any(axis=0)
            pick = good.argmax(axis=0)[placed] * len(todo) + np.flatnonzero(placed)  # first good try
            x[todo[placed]], y[todo[placed]] = px[pick], py[pick]
            ok[todo[placed]] = True
            todo = todo[~placed]
            tries *= 2
        return x, y, ok

    def _spawn(self, area: np.ndarray) -> None:
        """Create water for `area[i]`; those with no free spot are dropped."""
        x, y, ok = self._place(area)
        self._wx.append(x[ok])
        self._wy.append(y[ok])
        self._warea.append(area[ok])
        self.water_created += int(ok.sum())
        self.water_dropped += int((~ok).sum())

    def _forget_water(self, frozen: np.ndarray) -> None:
        """Frozen water is spent (the pool shrinks as ice grows)."""
        if len(frozen) == 0:
            return
        self.water_frozen += len(frozen)
        keep = np.ones(self._wx.n, bool)
        keep[frozen] = False
        self._keep_water(keep)

    def _keep_water(self, keep: np.ndarray) -> None:
        for buf in (self._wx, self._wy, self._warea):
            buf.keep(keep)

    def _follow_ice(self, new: slice) -> None:
        """Growth mode: each area's annulus rides on its ice front, half an active radius
        either side of the farthest crystal, so its water can still reach the ice.
        Costs O(new crystals): only the areas of this tick's crystals change."""
        area = self._carea.raw()[new]
        if len(area) == 0:
            return
        areas = self._areas.raw()
        d = np.hypot(*(self._crystals.raw()[new] - areas[area, :2]).T)
        np.maximum.at(areas[:, 4], area, d)
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
