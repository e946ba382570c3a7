"""Frost maps for game engines: height, normal and alpha, as numpy arrays (no PIL, no GL).

Everything is computed from the simulation's own geometry, not read back from GL, so
the maps are exact (no 8-bit feature heights, no half floats), need no context, and can
be computed on any thread that holds a copy of the arrays:
- the bumpy surface (Fig. 7): the geometry grid, bilinear at each pixel's centre, as
  the renderer samples its height texture;
- the sharp features: the renderer's own triangles (sim.look.geometry: Fig. 6's per segment,
  or the glass look's ridges), their height at each pixel centre, the highest winning
  where they overlap (the renderer's depth test); the glass look's edges anti-aliased
  as its feature pass does them (shaders/feature.frag, EDGE_AA);
- as in the renderer's ice pass, the two surfaces add: z = bumps + features;
- alpha is the renderer's thickness law (sim.look.material), opacity * (1 - exp(-density * z));
- normals come from the height gradient (central differences, px per px).
`encode` turns them into the integer images that app.images.export_maps writes as PNGs.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from ..core.frost import FrostSim
from ..params import Params
from ..screen import HEIGHT, WIDTH
from .geometry import feature_triangles, live_features
from .material import Material, film

MAP_NAMES = ("height", "normal", "alpha")
# Feature triangles are rasterized in batches of about this many pixel samples.
_BATCH_SAMPLES = 1 << 20
# normal_map works on bands of this many rows (bounded float64 temporaries).
NORMAL_ROWS = 256


@dataclass(frozen=True)
class FrostMaps:
    """The three maps as float arrays, H x W (normal H x W x 3), before encoding."""

    height: np.ndarray  # px above the glass
    normal: np.ndarray  # unit vectors, x right, y up (OpenGL convention), z out of the glass
    alpha: np.ndarray  # 0..1


def bump_field(grid: np.ndarray, spacing: float, width: int, height: int) -> np.ndarray:
    """The height grid (vertex (r, c) at px (c*spacing, r*spacing)) bilinear at every
    pixel centre, clamped at the edges: H x W float32."""
    def axis(n: int, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = np.clip((np.arange(n) + 0.5) / spacing, 0, size - 1)
        i0 = np.minimum(np.floor(t).astype(np.int64), size - 1)
        return i0, np.minimum(i0 + 1, size - 1), (t - i0).astype(np.float32)

    x0, x1, wx = axis(width, grid.shape[1])
    y0, y1, wy = axis(height, grid.shape[0])
    rows = grid[:, x0] * (1 - wx) + grid[:, x1] * wx
    return (rows[y0] * (1 - wy)[:, None] + rows[y1] * wy[:, None]).astype(np.float32)


def triangle_field(verts: np.ndarray, width: int, height: int,
                   edge_aa: bool = False, wrap: bool = False) -> np.ndarray:
    """Highest surface of feature triangles (3 rows of x, y, z, ... each) at every pixel
    centre, as the renderer's depth test keeps it: H x W float32 (0 off the ice); with
    `edge_aa`, each pixel's mean height within half a px of where a face meets the glass;
    with `wrap` (a tile), what leaves one edge comes in at the opposite one."""
    out = np.zeros(width * height, np.float32)
    tri = np.asarray(verts, np.float64)[:, :3].reshape(-1, 3, 3)
    lo = np.floor(tri[:, :, :2].min(axis=1) - 0.5).astype(np.int64)
    size = np.ceil(tri[:, :, :2].max(axis=1) + 0.5).astype(np.int64) - lo
    reach = size.max(axis=1)
    for r in np.unique(reach):  # one stencil size per batch
        pick = np.flatnonzero(reach == r)
        per = max(1, _BATCH_SAMPLES // int(r * r + 1))
        for start in range(0, len(pick), per):
            rows = pick[start:start + per]
            _raise_triangles(out, tri[rows], lo[rows], int(r), width, height, edge_aa, wrap)
    return out.reshape(height, width)


def _raise_triangles(out: np.ndarray, tri: np.ndarray, lo: np.ndarray, reach: int,
                     width: int, height: int, edge_aa: bool, wrap: bool = False) -> None:
    """Max the triangles' heights into `out` at the pixel centres of an r x r stencil."""
    idx, z = _triangle_pixels(tri, lo, reach, width, height, edge_aa, wrap)
    np.maximum.at(out, idx, z.astype(np.float32))


def _triangle_pixels(tri: np.ndarray, lo: np.ndarray, reach: int, width: int, height: int,
                     edge_aa: bool, wrap: bool) -> tuple[np.ndarray, np.ndarray]:
    """(flat pixel index, height) of every pixel centre of an r x r stencil inside a
    triangle; off the image it is dropped, or with `wrap` taken across the opposite edge
    (a tile's surface continues there)."""
    oy, ox = (a.ravel() for a in np.mgrid[0:reach, 0:reach])
    px, py = lo[:, 0:1] + ox, lo[:, 1:2] + oy
    x, y = px + 0.5, py + 0.5
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    ok = np.abs(area) > 1e-12
    area = np.where(ok, area, 1.0)[:, None]

    def edge(p, q):  # twice the signed area of (p, q, pixel), over the triangle's
        return ((q[:, 0:1] - p[:, 0:1]) * (y - p[:, 1:2])
                - (q[:, 1:2] - p[:, 1:2]) * (x - p[:, 0:1])) / area

    wa, wb, wc = edge(b, c), edge(c, a), edge(a, b)
    inside = ok[:, None] & (wa >= 0) & (wb >= 0) & (wc >= 0)
    z = wa * a[:, 2:3] + wb * b[:, 2:3] + wc * c[:, 2:3]
    if edge_aa:
        z = _edge_mean(z, tri, area)
    if wrap:
        hit = inside
        px, py = px % width, py % height
    else:
        hit = inside & (px >= 0) & (px < width) & (py >= 0) & (py < height)
    return py[hit] * width + px[hit], z[hit]


def triangle_hits(verts: np.ndarray, width: int, height: int, edge_aa: bool = False,
                  wrap: bool = False) -> np.ndarray:
    """Flat indices of the pixel centres that feature triangles (3 rows of x, y, z, ...
    each) raise above the glass, as triangle_field draws them, with repeats: the pixels
    a delta's features make ice."""
    tri = np.asarray(verts, np.float64)[:, :3].reshape(-1, 3, 3)
    if len(tri) == 0:
        return np.empty(0, np.int64)
    lo = np.floor(tri[:, :, :2].min(axis=1) - 0.5).astype(np.int64)
    reach = (np.ceil(tri[:, :, :2].max(axis=1) + 0.5).astype(np.int64) - lo).max(axis=1)
    found = []
    for r in np.unique(reach):
        pick = np.flatnonzero(reach == r)
        idx, z = _triangle_pixels(tri[pick], lo[pick], int(r), width, height, edge_aa, wrap)
        found.append(idx[z > 0])
    return np.concatenate(found)


def _edge_mean(z: np.ndarray, tri: np.ndarray, area: np.ndarray) -> np.ndarray:
    """The feature pass's EDGE_AA: where a face's height z at a pixel centre is within
    half the L1 slope of the glass, the pixel's coverage times its mean height."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    db, dc = b[:, 2:3] - a[:, 2:3], c[:, 2:3] - a[:, 2:3]
    gx = (db * (c[:, 1:2] - a[:, 1:2]) - dc * (b[:, 1:2] - a[:, 1:2])) / area
    gy = (dc * (b[:, 0:1] - a[:, 0:1]) - db * (c[:, 0:1] - a[:, 0:1])) / area
    ramp = np.maximum(np.abs(gx) + np.abs(gy), 1e-6)
    cover = np.clip(z / ramp + 0.5, 0.0, 1.0)
    return np.where(z < 0.5 * ramp, 0.5 * ramp * cover * cover, z)


def normal_map(height: np.ndarray, strength: float = 1.0, wrap: bool = False) -> np.ndarray:
    """Unit tangent-space normals of a height field (px, row 0 at the top): H x W x 3,
    x right, y UP the image (OpenGL / Unity / Blender convention), z out of the glass.
    n = normalize(-s dh/dx, +s dh/drow, 1): rows grow downward, so dh/dy_up = -dh/drow.
    With `wrap` (a tile) the differences at an edge reach across to the opposite one.
    Computed NORMAL_ROWS rows at a time (a 4096 px map's float64 temporaries were over a
    GB), each band with its neighbouring rows, so the result is the whole map's."""
    h = np.asarray(height)
    out = np.empty((*h.shape, 3), np.float32)
    for a in range(0, h.shape[0], NORMAL_ROWS):
        b = min(a + NORMAL_ROWS, h.shape[0])
        out[a:b] = _normal_band(h, a, b, strength, wrap)
    return out


def _normal_band(h: np.ndarray, a: int, b: int, strength: float, wrap: bool) -> np.ndarray:
    """normal_map's rows a..b-1, from rows a-1..b of `h` (over the wrap, or clipped)."""
    if wrap:
        band = np.asarray(h[np.arange(a - 1, b + 1) % h.shape[0]], np.float64)
        d_row = 0.5 * (band[2:] - band[:-2])
        d_col = 0.5 * (np.roll(band[1:-1], -1, axis=1) - np.roll(band[1:-1], 1, axis=1))
    elif min(h.shape) > 1:
        lo, hi = max(a - 1, 0), min(b + 1, h.shape[0])
        g_row, g_col = (np.asarray(g) for g in np.gradient(np.asarray(h[lo:hi], np.float64)))
        d_row, d_col = g_row[a - lo:b - lo], g_col[a - lo:b - lo]
    else:
        d_row = d_col = np.zeros((b - a, h.shape[1]))
    n = np.stack((-strength * d_col, strength * d_row, np.ones_like(d_row)), axis=-1)
    return (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)


def alpha_map(height: np.ndarray, material: Material | None = None) -> np.ndarray:
    """The renderer's opacity law: opacity * (1 - exp(-density * thickness))."""
    m = material or Material()
    return (m.opacity * (1.0 - np.exp(-m.density * np.maximum(height, 0.0)))).astype(np.float32)


def compute_maps(grid: np.ndarray, segments: np.ndarray, params: Params,
                 width: int = WIDTH, height: int = HEIGHT,
                 triangles: np.ndarray | None = None, wrap: bool = False) -> FrostMaps:
    """The three maps of a frost from its height grid and the renderer's feature
    triangles (sim.look.geometry.live_features, `map_triangles`); without them, the paper's
    triangles of the live skeleton `segments` (the glass look's ridges need the sim).
    `wrap`: a tile (its height grid periodic, its last row and column the first's), whose
    features and slopes continue across each edge."""
    z = bump_field(grid, params.grid_spacing, width, height)
    if params.look == "glass":
        z = film(z).astype(np.float32)
    if triangles is None:
        if params.look == "glass":
            raise ValueError("the glass look's maps need its ridges (sim.look.maps.map_triangles)")
        triangles = feature_triangles(segments, params.feature_width, params.feature_height)
    z += triangle_field(triangles, width, height, edge_aa=params.look == "glass", wrap=wrap)
    return FrostMaps(z, normal_map(z, wrap=wrap), alpha_map(z))


def encode(maps: FrostMaps) -> tuple[dict[str, np.ndarray], float]:
    """uint16 height (0..65535 = 0..height_max px), RGB8 normal (n*0.5+0.5), 8-bit alpha;
    and height_max, the px that 65535 stands for (at least 1 px)."""
    top = max(1.0, float(np.ceil(maps.height.max(initial=0.0))))
    images = {
        "height": np.round(np.clip(maps.height / top, 0, 1) * 65535).astype(np.uint16),
        "normal": np.round((maps.normal * 0.5 + 0.5) * 255).astype(np.uint8),
        "alpha": np.round(np.clip(maps.alpha, 0, 1) * 255).astype(np.uint8),
    }
    return images, top


MEANING = MappingProxyType({  # what each encoded image's values stand for
    "height": "16-bit grey: height above the glass = value / 65535 * height_max_px px",
    "normal": "RGB: tangent-space unit normal * 0.5 + 0.5; x right, y up (OpenGL), z out of the glass",
    "alpha": "8-bit grey: ice opacity, opacity * (1 - exp(-density * height_px))",
})


def live_segments(sim: FrostSim) -> np.ndarray:
    """The skeleton segments that have not melted (all of them in a sim without melting)."""
    alive = getattr(sim, "segments_alive", None)
    return sim.segments if alive is None else sim.segments[alive]


def map_triangles(sim: FrostSim, params: Params) -> np.ndarray:
    """The renderer's feature triangles of the live ice, in either look: what the maps
    rasterize, so that they hold what is drawn."""
    return live_features(sim, params)
