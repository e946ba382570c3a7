"""Frost geometry of Sec. 3.5: sharp features (Fig. 6) and the bumpy surface (Fig. 7).

Numpy only, no GL: `FrostGeometry.update` turns one tick's new particles into a
`GeometryDelta` (the dirty rows of the height grid and the new feature triangles)
that the renderer uploads. Nothing here ever walks the whole ice.

Convention: x right and y down in screen px (as the simulation), z is the height
above the glass toward the viewer, in px. Normals point to the viewer (nz > 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..index.periodic import wrap_triangles
from ..params import Params
from ..screen import HEIGHT, WIDTH
from .ridges import PipeRidges, top_height, widest

# Each segment gives 4 triangles of 3 vertices, each vertex x, y, z, nx, ny, nz.
VERTS_PER_SEGMENT = 12
# A raise sums only the vertices it touches when the dirty rows hold this many times more
# vertices than it raises (a unique pass over a few thousand beats five over the grid).
SPARSE_RAISE = 8
VERTEX_FLOATS = 6


@dataclass(frozen=True)
class GeometryDelta:
    """What changed in one tick: dirty height rows and new feature triangles."""

    tick: int
    rows: slice  # dirty row range of the height grid
    heights: np.ndarray  # float32 copy of heights[rows]
    features: np.ndarray  # float32 (12 k) x 6: x, y, z, nx, ny, nz, flat per face
    reset: bool = False
    # After a melt: the px box (x0, y0, x1, y1) whose features the renderer must wipe
    # before drawing `features`, which then hold the survivors in that box.
    clear_box: tuple[float, float, float, float] | None = None
    look: str = "paper"  # how the features are meant to be drawn (Params.look)
    height_scale: float = 16.0  # px that the feature texture's 8-bit height 1.0 stands for


@dataclass(frozen=True)
class IceCopy:
    """What drawing the live ice's features reads of a simulation (`live_features`),
    copied at one tick: taken between two ticks of a running simulation, it may be drawn
    on another thread while the simulation goes on."""

    tick: int
    width: int
    height: int
    wrap: bool
    crystals: np.ndarray
    crystal_alive: np.ndarray
    parents: np.ndarray
    segments: np.ndarray
    segments_alive: np.ndarray

    @classmethod
    def of(cls, sim) -> IceCopy:
        return cls(int(sim.tick), int(sim.width), int(sim.height), bool(getattr(sim, "wrap", False)),
                   sim.crystals.copy(), sim.crystal_alive.copy(), sim.parents.copy(),
                   sim.segments.copy(), sim.segments_alive.copy())


def _feature_points(seg: np.ndarray, width: float, height: float) -> np.ndarray:
    """s x 5 x 3 points (p, q, m, s1, s2) of the sharp features of segments s x 4."""
    p, q = seg[:, 0:2].astype(np.float64), seg[:, 2:4].astype(np.float64)
    d = q - p
    length = np.hypot(d[:, 0], d[:, 1])
    # (-dy, dx) is d turned by 90 degrees; its length is L, so m +/- width*that is
    # exactly m +/- width*L*n with no division (and no trouble at L = 0).
    perp = np.column_stack((-d[:, 1], d[:, 0]))
    m = 0.5 * (p + q)
    s1, s2 = m - width * perp, m + width * perp
    zeros = np.zeros((len(seg), 1))
    pts = np.stack([np.hstack((a, zeros)) for a in (p, q, m, s1, s2)], axis=1)
    pts[:, 2, 2] = height * length
    return pts


def feature_triangles(segments: np.ndarray, width: float, height: float) -> np.ndarray:
    """Non-indexed triangles (p,s1,m), (s1,q,m), (q,s2,m), (s2,p,m) of every segment,
    (12 s) x 6 float32 with each face's own normal, so ridges stay sharp."""
    if len(segments) == 0:
        return np.empty((0, VERTEX_FLOATS), np.float32)
    pts = _feature_points(segments, width, height)
    tri = pts[:, [0, 3, 2, 3, 1, 2, 1, 4, 2, 4, 0, 2]].reshape(-1, 3, 3)
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    # Winding differs from face to face (and the frame is y-down), so orient each
    # normal toward the viewer instead of trusting the cross product's sign.
    normal *= np.where(normal[:, 2:3] < 0, -1.0, 1.0)
    size = np.linalg.norm(normal, axis=1, keepdims=True)
    flat = size == 0  # a zero-length segment: lay it flat on the glass
    normal = np.where(flat, [0.0, 0.0, 1.0], normal / np.where(flat, 1.0, size))
    verts = np.concatenate((tri, np.repeat(normal[:, None, :], 3, axis=1)), axis=2)
    return verts.reshape(-1, VERTEX_FLOATS).astype(np.float32)


def falloff(d: np.ndarray, radius: float) -> np.ndarray:
    """Bump weight at distance d from a particle: (1 - (d/hc)^2)^2 inside hc, else 0.

    Chosen because it is 1 at the particle and reaches 0 at hc with zero slope, so
    the summed surface has no creases at the rim of a freezing area (a constant
    `bump` as printed in Fig. 7 would give a terraced look), and it needs no sqrt."""
    u = np.clip(1.0 - d * d / (radius * radius), 0.0, None)
    return u * u


class FrostGeometry:
    """The height grid (Fig. 7) and sharp features (Fig. 6) of a growing frost."""

    def __init__(self, params: Params, width: int = WIDTH, height: int = HEIGHT,
                 wrap: bool = False):
        self.params = params
        self.spacing = int(params.grid_spacing)
        self.rows = height // self.spacing + 1
        self.cols = width // self.spacing + 1
        # A tile (wrap): the grid is periodic, its last row and column repeat the first,
        # and a feature crossing an edge is sent again shifted across it.
        self.wrap, self.size = wrap, (width, height)
        if wrap and (width % self.spacing or height % self.spacing):
            raise ValueError(f"a tile's size ({width}x{height}) must be a multiple of "
                             f"grid_spacing ({self.spacing} px)")
        self.heights = np.zeros((self.rows, self.cols), np.float32)
        # Uncapped sum of the bumps, so that a melt can take a particle's share back
        # out exactly; heights = min(sum, max_height).
        self._sum = np.zeros((self.rows, self.cols), np.float64)
        # Offsets of the grid vertices that can lie within hc of a particle, relative
        # to the vertex nearest it: a fixed (2R+1)^2 stencil, so a tick costs
        # O(new particles) whatever the size of the ice.
        reach = math.ceil(params.hc / self.spacing) + 1
        oy, ox = np.mgrid[-reach:reach + 1, -reach:reach + 1]
        self._stencil = (oy.ravel(), ox.ravel())
        self.ridges = PipeRidges(params) if params.look == "glass" else None

    def reset(self) -> GeometryDelta:
        """Flat glass again; the delta tells the renderer to drop everything."""
        self.heights[:] = 0
        self._sum[:] = 0
        if self.ridges is not None:
            self.ridges = PipeRidges(self.params)
        empty = np.empty((0, VERTEX_FLOATS), np.float32)
        return self._delta(0, slice(0, self.rows), empty, reset=True)

    def redraw(self, sim) -> GeometryDelta:
        """The whole live ice drawn anew (after a change of look): a reset delta holding
        every height row and every live feature. Costs O(ice), once."""
        self.reset()
        pts = np.concatenate((sim.crystals[sim.crystal_alive],
                              sim.upsampled[sim.upsampled_alive]))
        self._raise(pts)
        if self.ridges is not None:
            feats = self.ridges.grow(sim, slice(0, len(sim.crystals)))
        else:
            feats = live_features(sim, self.params)
        return self._delta(sim.tick, slice(0, self.rows), feats, reset=True)

    def update(self, sim) -> GeometryDelta:
        """Raise the grid around the tick's new particles and build their features."""
        added = sim.added
        pts = np.concatenate((sim.crystals[added.crystals], sim.upsampled[added.upsampled]))
        rows = self._raise(pts)
        if self.ridges is not None:
            feats = self.ridges.grow(sim, added.crystals)
            return self._delta(added.tick, rows, feats)
        # A segment melted before this update never shows (its bumps are still added:
        # the melt took them back out already, and sums commute).
        segs = sim.segments[added.segments][sim.segments_alive[added.segments]]
        feats = feature_triangles(segs, self.params.feature_width, self.params.feature_height)
        return self._delta(added.tick, rows, feats)

    def melt(self, sim, melted) -> GeometryDelta:
        """Take a `sim.melt` result (`Melted`) out of the ice: its particles' bumps are
        subtracted and its segments' features wiped, the surviving features in the
        wiped box are sent again. Costs O(ice near the melt)."""
        pts = np.concatenate((sim.crystals[melted.crystals], sim.upsampled[melted.upsampled]))
        rows = self._raise(pts, -1.0)
        if self.ridges is not None:
            return self._melt_ridges(self.ridges, sim, melted, pts, rows)
        width, height = self.params.feature_width, self.params.feature_height
        dead = feature_triangles(sim.segments[melted.segments], width, height)
        box = _bounds(dead[:, :2], pts, self.params.hc)
        feats = np.empty((0, VERTEX_FLOATS), np.float32)
        if box is not None:
            feats = feature_triangles(_segments_in(sim, box, width), width, height)
        return self._delta(sim.tick, rows, feats, clear_box=box)

    def _delta(self, tick: int, rows: slice, feats: np.ndarray, **more) -> GeometryDelta:
        if self.wrap:
            feats = wrap_triangles(feats, *self.size)
        return GeometryDelta(tick, rows, self.heights[rows].copy(), feats, look=self.params.look,
                             height_scale=feature_scale(self.params), **more)

    def _melt_ridges(self, ridges: PipeRidges, sim, melted, pts: np.ndarray,
                     rows: slice) -> GeometryDelta:
        """The glass look's melt: the box holds the cut links (those of the melted
        crystals and of their children) and the links above them that thinned; every live
        ridge meeting it is sent again."""
        thinner = ridges.melt(sim, melted.crystals)
        c, parents = sim.crystals, sim.parents
        ends = [melted.orphans, thinner, parents[thinner]]
        dead = melted.crystals
        ends.append(parents[dead][parents[dead] >= 0])
        xy = c[np.concatenate(ends).astype(np.int64)]
        reach = 2.0 * widest(self.params.hc) + 1.0  # a ridge's cap reaches w past its end
        box = _bounds(np.vstack((xy - reach, xy + reach)), pts, self.params.hc)
        feats = np.empty((0, VERTEX_FLOATS), np.float32)
        if box is not None:
            links = np.unique(sim.segments_link[sim.segments_near(box, 1.0)])
            links = links[sim.crystal_alive[links] & (parents[links] >= 0)]
            feats = ridges.triangles(sim, links)
        return self._delta(sim.tick, rows, feats, clear_box=box)

    def _raise(self, pts: np.ndarray, sign: float = 1.0) -> slice:
        """Add (sign -1: take back) bump * falloff at every vertex within hc of each
        point, capped at max_height; returns the dirty row range (empty if none)."""
        if len(pts) == 0:
            return slice(0, 0)
        gs = self.spacing
        r = np.rint(pts[:, 1:2] / gs).astype(np.int64) + self._stencil[0]
        c = np.rint(pts[:, 0:1] / gs).astype(np.int64) + self._stencil[1]
        d = np.hypot(c * gs - pts[:, 0:1], r * gs - pts[:, 1:2])
        if self.wrap:
            return self._raise_wrapped(r, c, d, sign)
        hit = (d < self.params.hc) & (r >= 0) & (r < self.rows) & (c >= 0) & (c < self.cols)
        if not hit.any():
            return slice(0, 0)
        lo, hi = int(r[hit].min()), int(r[hit].max()) + 1
        # One bincount over the dirty rows (no sort): each vertex's bumps add up in input
        # order. The sum is kept as is (adds and melts commute, in any order); only the
        # shown height drops the round-off a melt leaves, so clear glass stays clear.
        flat = (r[hit] - lo) * self.cols + c[hit]
        bumps = self.params.bump * falloff(d[hit], self.params.hc)
        if len(flat) * SPARSE_RAISE < (hi - lo) * self.cols:
            # New ice far apart (the window's frame and pane grow all over at once): the
            # dirty rows are most of the grid, the vertices raised a few thousand. Sum
            # and cap only those, in the same order: the same heights, bit for bit.
            touched, inv = np.unique(flat, return_inverse=True)
            total = self._sum[lo:hi].reshape(-1)
            total[touched] += sign * np.bincount(inv, bumps)
            h = np.minimum(total[touched], self.params.max_height)
            self.heights[lo:hi].reshape(-1)[touched] = np.where(h < 1e-6, 0.0, h)
            return slice(lo, hi)
        add = np.bincount(flat, bumps, minlength=(hi - lo) * self.cols)
        total = self._sum[lo:hi]
        total += sign * add.reshape(hi - lo, self.cols)
        h = np.minimum(total, self.params.max_height)
        self.heights[lo:hi] = np.where(h < 1e-6, 0.0, h)
        return slice(lo, hi)


    def _raise_wrapped(self, r: np.ndarray, c: np.ndarray, d: np.ndarray, sign: float) -> slice:
        """A tile's raise: vertices past an edge are the opposite edge's, and the last row
        and column mirror the first. Only the vertices touched are summed and capped (new
        ice lands all over a tile, so the dirty rows are most of the grid every tick)."""
        hit = d < self.params.hc
        rows, cols = self.rows - 1, self.cols - 1
        rr, cc = r[hit] % rows, c[hit] % cols
        if len(rr) == 0:
            return slice(0, 0)
        touched, inv = np.unique(rr * self.cols + cc, return_inverse=True)
        add = np.bincount(inv.ravel(), self.params.bump * falloff(d[hit], self.params.hc))
        ty, tx = np.divmod(touched, self.cols)
        # The mirrors: a vertex in row 0 is also the last row, one in column 0 the last column.
        top, left = ty == 0, tx == 0
        corner = top & left
        ty = np.concatenate((ty, np.full(int(top.sum()), rows), ty[left], np.full(int(corner.sum()), rows)))
        tx = np.concatenate((tx, tx[top], np.full(int(left.sum()), cols), np.full(int(corner.sum()), cols)))
        add = np.concatenate((add, add[top], add[left], add[corner]))
        self._sum[ty, tx] += sign * add
        h = np.minimum(self._sum[ty, tx], self.params.max_height)
        self.heights[ty, tx] = np.where(h < 1e-6, 0.0, h)
        return slice(int(ty.min()), int(ty.max()) + 1)


def live_features(sim, params: Params) -> np.ndarray:
    """The feature triangles of all the live ice as `params.look` draws them (what the
    renderer holds after every delta; the glass look's widths counted afresh), for maps.
    Leaves every geometry as it is."""
    if params.look == "glass":
        return PipeRidges(params).grow(sim, slice(0, len(sim.crystals)))
    return feature_triangles(sim.segments[sim.segments_alive], params.feature_width,
                             params.feature_height)


def feature_height_bound(params: Params) -> float:
    """The highest a sharp feature can stand, px: a link is at most about hc + step long
    (the paper's features stand feature_height x its length), a glass ridge at most
    ridges.top_height."""
    if params.look == "glass":
        return top_height(params)
    return params.feature_height * (params.hc + params.step)


def feature_scale(params: Params) -> float:
    """The px the feature texture's 8-bit height stores as 1.0: 16 (steps of 0.06 px),
    more where features can stand higher, so none is clipped."""
    return max(16.0, float(np.ceil(feature_height_bound(params))))


def _bounds(xy: np.ndarray, pts: np.ndarray, reach: float):
    """The px box around points xy and discs of radius `reach` at pts (None if empty)."""
    if len(xy) == 0 and len(pts) == 0:
        return None
    lo = np.vstack((xy.reshape(-1, 2), pts - reach)).min(axis=0)
    hi = np.vstack((xy.reshape(-1, 2), pts + reach)).max(axis=0)
    return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))


def _segments_in(sim, box, width: float) -> np.ndarray:
    """Live segments whose feature (reaching width * L beside them) meets the box; only
    the segments of the ice near the box are looked at."""
    seg = sim.segments[sim.segments_near(box, width)]
    reach = width * np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1])
    x0 = np.minimum(seg[:, 0], seg[:, 2]) - reach
    x1 = np.maximum(seg[:, 0], seg[:, 2]) + reach
    y0 = np.minimum(seg[:, 1], seg[:, 3]) - reach
    y1 = np.maximum(seg[:, 1], seg[:, 3]) + reach
    meets = (x1 >= box[0]) & (x0 <= box[2]) & (y1 >= box[1]) & (y0 <= box[3])
    return seg[meets]
