"""The frost renderer: background, bumpy ice and sharp features, alpha-blended and Phong-shaded.

Design (frame cost independent of the amount of ice):
- the height grid lives in a half-float RGB texture, one texel per vertex holding the
  height and its slope (central differences, done here on the CPU for the dirty rows
  only), sampled bilinearly: one fetch per pixel instead of five; `apply` rewrites only
  a delta's dirty rows (plus one on each side, whose slope they change);
- feature triangles are rasterized ONCE, when they arrive, into a persistent screen-sized
  "ice" texture (normal xy, height, coverage) with a depth test so the higher surface wins;
- each frame is then a background pass (one texel per pixel) and, blended over it, an
  ice pass drawn only on the screen tiles that hold ice (instanced quads), so clear
  glass costs no more than the background.
Only the main thread may call this (GL).
"""

from __future__ import annotations

import logging
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from app.backdrops import DEFAULT_BACKDROP, LIVE, load_backdrop, read_backdrop
from app.gl.shaders import load_program
from app.lockscreen import CLOCK_BOX, DEFAULT_MINUTE, clock_patch
from app.resources import ASSET_DIR
from sim.look.geometry import VERTEX_FLOATS, GeometryDelta
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES, MAX_DEPTH, TILE, Material, default_light
from sim.params import Params
from sim.screen import HEIGHT, WIDTH

log = logging.getLogger(__name__)

BACKGROUND = ASSET_DIR / "background.png"
# Feature heights are stored in 8 bits as z / height scale: 16 px (steps of 0.06 px)
# unless features can stand higher (sim.look.geometry.feature_scale; each delta says).
FEATURE_HEIGHT_SCALE = 16.0
VERTEX_BYTES = VERTEX_FLOATS * 4


def load_background(path: Path = BACKGROUND) -> np.ndarray:
    """The view through the window, H x W x 3 uint8 top-down."""
    if not path.is_file():
        raise FileNotFoundError(f"background image {path} is missing; "
                                "make it with: python3 assets/make_background.py")
    return np.asarray(Image.open(path).convert("RGB"))


class Renderer:
    """Draws the frost frame into a given framebuffer."""

    def __init__(self, ctx: moderngl.Context, params: Params, width: int = WIDTH,
                 height: int = HEIGHT, background: np.ndarray | None = None):
        self.ctx, self.params = ctx, params
        self.size = (width, height)
        self.light: np.ndarray | tuple[float, ...] = default_light()
        self.material = Material()
        self.show_features = True
        self.show_bumps = True
        self.look, self.height_scale = params.look, FEATURE_HEIGHT_SCALE
        self.backdrop = DEFAULT_BACKDROP  # the background's name (or file), for the view
        self.minute = DEFAULT_MINUTE  # the lock screen's clock (app/lockscreen.py)
        self.outside = ""  # the line under it: the temperature outside ("" none)
        self.photos: Path | None = None  # the folder photos are found in by name (app/photos.py)
        self._static: np.ndarray | None = None  # the lock screen's static parts, once read
        spacing = params.grid_spacing
        self.grid_size = (width // spacing + 1, height // spacing + 1)
        self._background = self._background_texture(background)
        self._grid = np.zeros(self.grid_size[::-1], np.float32)  # mirror of the heights
        self._heights = ctx.texture(self.grid_size, 3, dtype="f2")
        self.features = FeatureLayer(ctx, self.size)
        self._background_prog = load_program(ctx, "fullscreen.vert", "background.frag")
        self._background_pass = ctx.vertex_array(self._background_prog, [])
        self._ice_progs: dict[str, moderngl.Program] = {}
        self.tiles = TileSet(ctx, self.size, spacing)
        self.reset()

    # ---- view state: what, besides the frost, decides the picture --------------------

    def view(self) -> dict:
        """The light and the toggles as JSON (session files and PNGs carry it, so a
        replay draws the same picture; see sim.io.session.check_view)."""
        return {"light": [float(v) for v in self.light], "features": bool(self.show_features),
                "bumps": bool(self.show_bumps), "background": self.backdrop}

    def set_view(self, view: dict | None) -> None:
        """Show as `view` (from `view()`, or some of its keys) says; None keeps the
        defaults. A background that cannot be read raises ValueError."""
        view = view or {}
        if "light" in view:
            self.light = tuple(float(v) for v in view["light"])
        self.show_features = view.get("features", self.show_features)
        self.show_bumps = view.get("bumps", self.show_bumps)
        if view.get("background", self.backdrop) != self.backdrop:
            self.set_backdrop(view["background"])

    def set_backdrop(self, name: str) -> None:
        """The view behind the glass: a built-in backdrop's name or an image file (the
        lock screen with its clock at `minute`)."""
        self.set_background_image(
            load_backdrop(name, self.size, self.minute, self.photos, self.outside), name)

    def set_minute(self, minute: str, patch: np.ndarray | None = None,
                   outside: str | None = None) -> None:
        """The lock screen's clock shows `minute` ("YYYY-MM-DDTHH:MM") and `outside` under
        it (None: the line it has): over the lock screen, its clock box alone is drawn
        (unless `patch` is it, drawn already: see `clock_box`) and uploaded (texture rows
        are the image's, top row first); any other backdrop keeps them for when the lock
        screen is shown."""
        outside = self.outside if outside is None else outside
        if (minute, outside) == (self.minute, self.outside):
            return
        self.minute, self.outside = minute, outside
        if self.backdrop != LIVE:
            return
        if not self.patches_clock():  # scaled: the whole backdrop again
            self.set_backdrop(LIVE)
            return
        x0, y0, x1, y1 = CLOCK_BOX
        patch = self.clock_box(minute, outside) if patch is None else patch
        self._background.write(np.ascontiguousarray(patch).tobytes(),
                               viewport=(x0, y0, x1 - x0, y1 - y0))

    def patches_clock(self) -> bool:
        """Whether a new minute is drawn as the clock box alone (the lock screen shown at
        its own size)."""
        return self.backdrop == LIVE and self.size == (WIDTH, HEIGHT)

    def clock_box(self, minute: str, outside: str = "") -> np.ndarray:
        """The lock screen's clock box at `minute`, `outside` under it (any thread: it
        draws no GL; the static lock screen is read at the first call)."""
        if self._static is None:
            self._static = np.asarray(read_backdrop(LIVE))
        return clock_patch(self._static, minute, outside)

    def set_background_image(self, image: np.ndarray, name: str) -> None:
        """The view behind the glass from an H x W x 3 uint8 image (top row first)."""
        self._background.write(np.ascontiguousarray(image, np.uint8).tobytes())
        self.backdrop = name

    def heights_grid(self) -> np.ndarray:
        """A copy of the height grid the renderer holds (vertex (r, c) at px (c, r) x spacing)."""
        return self._grid.copy()

    # ---- uploads ----------------------------------------------------------------

    def apply(self, delta: GeometryDelta) -> None:
        """Upload a tick's changes: its dirty height rows and its new feature vertices."""
        if delta.reset:
            self.reset()
        self.look, self.height_scale = delta.look, delta.height_scale
        self.features.height_scale, self.features.look = delta.height_scale, delta.look
        if delta.clear_box is not None:
            self.features.wipe(delta.clear_box)
        if delta.rows.stop > delta.rows.start:
            fresh = (delta.heights > 0) & (self._grid[delta.rows] == 0)  # newly iced
            self._grid[delta.rows] = delta.heights
            self._upload_rows(delta.rows.start - 1, delta.rows.stop + 1)
            self.tiles.mark_heights(fresh, delta.rows.start)
        self.tiles.mark_triangles(delta.features[:, :2])
        self.features.append(delta.features)

    def _upload_rows(self, lo: int, hi: int) -> None:
        """Write height and slope (per px) of grid rows lo..hi-1 to the texture."""
        rows = len(self._grid)
        lo, hi = max(lo, 0), min(hi, rows)
        a, b = max(lo - 1, 0), min(hi + 1, rows)  # neighbours for central differences
        slab = self._grid[a:b]  # at least 2 rows: the grid spans the screen's height
        gy, gx = np.gradient(slab, float(self.params.grid_spacing))
        texels = np.stack((slab, gx, gy), axis=-1)[lo - a:hi - a].astype(np.float16)
        self._heights.write(texels.tobytes(), viewport=(0, lo, self.grid_size[0], hi - lo))

    def reset(self) -> None:
        """Clear glass: no heights, no features."""
        self._grid[:] = 0
        self._upload_rows(0, len(self._grid))
        self.features.clear()
        self.tiles.clear()

    def _background_texture(self, image: np.ndarray | None) -> moderngl.Texture:
        image = load_background() if image is None else image
        if image.shape != (self.size[1], self.size[0], 3) or image.dtype != np.uint8:
            raise ValueError(f"background must be {self.size[1]}x{self.size[0]}x3 uint8, "
                             f"got {image.shape} {image.dtype}")
        tex = self.ctx.texture(self.size, 3, np.ascontiguousarray(image).tobytes())
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return tex

    # ---- drawing ----------------------------------------------------------------

    def render(self, fbo: moderngl.Framebuffer) -> None:
        """Draw one full frame into `fbo` (which must be the screen's size)."""
        self.features.draw_queued()
        fbo.use()
        self.ctx.viewport = (0, 0, *self.size)
        self.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._background.use(0)
        self._set(self._background_prog, {"u_background": 0, "u_screen": self.size})
        self._background_pass.render(moderngl.TRIANGLES, vertices=3)
        if not (self.show_bumps or self.show_features):
            return
        self._heights.use(1)
        self.features.texture.use(2)
        prog = self.ice_program(self.look)
        self._set(prog, self._ice_uniforms())
        # Premultiplied "over": frame = ice + (1 - alpha) * background.
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA
        self.tiles.render(prog)
        self.ctx.disable(moderngl.BLEND)

    def ice_program(self, look: str) -> moderngl.Program:
        """The ice pass compiled for `look` (its #define variant), made on first use."""
        if look not in self._ice_progs:
            self._ice_progs[look] = load_program(self.ctx, "tile.vert", "ice.frag",
                                                 LOOK_DEFINES[look])
        return self._ice_progs[look]

    def _ice_uniforms(self) -> dict:
        m = self.material
        light = np.asarray(self.light, np.float64)
        return {
            "u_heights": 1, "u_ice": 2, "u_tile": float(TILE),
            "u_screen": self.size, "u_grid_size": self.grid_size,
            "u_spacing": float(self.params.grid_spacing),
            "u_height_scale": self.height_scale, "u_background": 0,
            "u_refraction": m.refraction,
            "u_show_bumps": float(self.show_bumps), "u_show_features": float(self.show_features),
            "u_light": tuple(light / np.linalg.norm(light)),
            "u_ice_color": m.ice_color, "u_ambient": m.ambient, "u_diffuse": m.diffuse,
            "u_specular": m.specular, "u_shininess": m.shininess, "u_opacity": m.opacity,
            "u_density": m.density, "u_relief": m.relief,
        }

    @staticmethod
    def _set(prog, values: dict) -> None:
        for name, value in values.items():
            if name in prog:
                prog[name].value = value


class FeatureLayer:
    """The sharp features: their triangles are queued as they arrive and rasterized once
    into a persistent screen-sized "ice" texture (normal xy, height, coverage), a depth
    test keeping the higher surface where two overlap."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int]):
        self.ctx, self.size = ctx, size
        self.texture = ctx.texture(size, 4)
        self._fbo = ctx.framebuffer([self.texture], ctx.depth_renderbuffer(size))
        self._pending = 0  # vertices queued in _vbo, not yet drawn into the texture
        self.height_scale, self.look = FEATURE_HEIGHT_SCALE, "paper"
        self._progs: dict[str, moderngl.Program] = {}  # per look (FEATURE_DEFINES)
        self._arrays: dict[str, moderngl.VertexArray] = {}  # per look, over _vbo
        self._vbo = ctx.buffer(reserve=1 << 16, dynamic=True)

    def clear(self) -> None:
        """No features, nothing queued."""
        self._fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self._pending = 0

    def wipe(self, box: tuple[float, float, float, float]) -> None:
        """Clear the features inside a px box (y down), after drawing what is queued
        (older than the wipe); the delta then re-sends the survivors."""
        self.draw_queued()
        x0, y0 = max(int(np.floor(box[0])) - 1, 0), max(int(np.floor(box[1])) - 1, 0)
        x1 = min(int(np.ceil(box[2])) + 1, self.size[0])
        y1 = min(int(np.ceil(box[3])) + 1, self.size[1])
        if x1 > x0 and y1 > y0:
            viewport = (x0, self.size[1] - y1, x1 - x0, y1 - y0)  # GL rows count up
            self._fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0, viewport=viewport)

    def append(self, verts: np.ndarray) -> None:
        """Queue new feature vertices (drawn once, next frame)."""
        if len(verts) == 0:
            return
        need = (self._pending + len(verts)) * VERTEX_BYTES
        if need > self._vbo.size:
            self._grow(max(2 * self._vbo.size, need))
        self._vbo.write(np.ascontiguousarray(verts, np.float32).tobytes(),
                        offset=self._pending * VERTEX_BYTES)
        self._pending += len(verts)

    def draw_queued(self) -> None:
        """Rasterize the queued triangles into the texture."""
        if self._pending == 0:
            return
        prog, array = self._program(self.look)
        Renderer._set(prog, {"u_screen": self.size, "u_max_depth": MAX_DEPTH,
                             "u_height_scale": self.height_scale})
        self._fbo.use()
        self.ctx.viewport = (0, 0, *self.size)
        self.ctx.disable(moderngl.BLEND)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.depth_func = "<"
        array.render(moderngl.TRIANGLES, vertices=self._pending)
        self.ctx.disable(moderngl.DEPTH_TEST)
        self._pending = 0

    def _grow(self, size: int) -> None:
        """A vertex buffer of `size` bytes in place of the old one, the queue copied over."""
        vbo = self.ctx.buffer(reserve=size, dynamic=True)
        self.ctx.copy_buffer(vbo, self._vbo, self._pending * VERTEX_BYTES)
        self._vbo.release()
        for array in self._arrays.values():
            array.release()
        self._vbo, self._arrays = vbo, {}

    def _program(self, look: str) -> tuple[moderngl.Program, moderngl.VertexArray]:
        """The feature pass compiled for `look` and its vertex array, made on first use."""
        if look not in self._progs:
            self._progs[look] = load_program(self.ctx, "feature.vert", "feature.frag",
                                             FEATURE_DEFINES[look])
        if look not in self._arrays:
            self._arrays[look] = self.ctx.vertex_array(
                self._progs[look], [(self._vbo, "3f 3f", "in_position", "in_normal")])
        return self._progs[look], self._arrays[look]


class TileSet:
    """The screen tiles that hold ice, drawn as instanced quads. Tiles are only added
    (until a reset): a melt leaves its tiles marked, which costs their fragments but
    draws the melted glass exactly (zero alpha blends to the background), and the ice
    regrows there. The instance list is re-sent (at most a few kB) on the frames after
    one was added."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], spacing: int):
        self.ctx, self.spacing = ctx, spacing
        self.mask = np.zeros((-(-size[1] // TILE), -(-size[0] // TILE)), bool)
        corners = np.array([0, 0, 1, 0, 0, 1, 1, 1], np.float32)
        self._corners = ctx.buffer(corners.tobytes())
        self._instances = ctx.buffer(reserve=self.mask.size * 8)
        self._vaos: dict[int, moderngl.VertexArray] = {}  # per ice program (look)
        self._count, self._dirty = 0, False

    def clear(self) -> None:
        self.mask[:] = False
        self._count, self._dirty = 0, False

    def fill(self) -> None:
        """Every tile: the ice pass over the whole screen (for checks and debugging)."""
        self.mask[:] = True
        self._dirty = True

    def mark_heights(self, iced: np.ndarray, first_row: int) -> None:
        """Mark the tiles that see the `iced` grid vertices (a bool block of grid rows
        from first_row): bilinear filtering spreads a vertex one grid cell each way."""
        r, c = np.nonzero(iced)
        y, x = (r + first_row) * self.spacing, c * self.spacing
        self._mark_boxes(x - self.spacing, y - self.spacing, x + self.spacing, y + self.spacing)

    def mark_triangles(self, xy: np.ndarray) -> None:
        """Mark the tiles under each triangle's bounding box (xy: 3 rows per triangle)."""
        if len(xy) == 0:
            return
        tri = xy.reshape(-1, 3, 2)
        lo, hi = tri.min(axis=1), tri.max(axis=1)
        self._mark_boxes(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1])

    def _mark_boxes(self, x0, y0, x1, y1) -> None:
        """Mark every tile that the px boxes [x0, x1] x [y0, y1] overlap."""
        if len(x0) == 0:
            return
        rows, cols = self.mask.shape
        tx0, ty0 = (np.clip(np.floor_divide(v, TILE), 0, n - 1).astype(np.int64)
                    for v, n in ((x0, cols), (y0, rows)))
        tx1, ty1 = (np.clip(np.floor_divide(v, TILE), 0, n - 1).astype(np.int64)
                    for v, n in ((x1, cols), (y1, rows)))
        span = int(max((tx1 - tx0).max(), (ty1 - ty0).max())) + 1
        oy, ox = (a.ravel() for a in np.mgrid[0:span, 0:span])
        ty, tx = ty0[:, None] + oy, tx0[:, None] + ox
        keep = (ty <= ty1[:, None]) & (tx <= tx1[:, None])
        ty, tx = ty[keep], tx[keep]
        new = ~self.mask[ty, tx]
        if new.any():
            self.mask[ty[new], tx[new]] = True
            self._dirty = True

    def render(self, prog: moderngl.Program) -> None:
        if self._dirty:
            self._upload()
        if self._count:
            self._vao(prog).render(moderngl.TRIANGLE_STRIP, vertices=4, instances=self._count)

    def _vao(self, prog: moderngl.Program) -> moderngl.VertexArray:
        if prog.glo not in self._vaos:
            self._vaos[prog.glo] = self.ctx.vertex_array(
                prog, [(self._corners, "2f", "in_corner"), (self._instances, "2f/i", "in_tile")])
        return self._vaos[prog.glo]

    def _upload(self) -> None:
        rows, cols = np.nonzero(self.mask)
        tiles = np.column_stack((cols, rows)).astype(np.float32)
        self._instances.write(tiles.tobytes())
        self._count, self._dirty = len(tiles), False
