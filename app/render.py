"""The frost renderer: background, bumpy ice and sharp features, alpha-blended and Phong-shaded.

Design (frame cost independent of the amount of ice):
- the height grid lives in a one-channel float texture (one texel per vertex, sampled
  bilinearly); `apply` rewrites only a delta's dirty rows;
- feature triangles are rasterized ONCE, when they arrive, into a persistent screen-sized
  "ice" texture (normal xy, height, coverage) with a depth test so the higher surface wins;
- each frame is then one full-screen composite pass (shaders/composite.frag).
Only the main thread may call this (GL).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from sim.geometry import VERTEX_FLOATS, GeometryDelta
from sim.params import Params

from .shaders import load_program

log = logging.getLogger(__name__)

BACKGROUND = Path(__file__).resolve().parent.parent / "assets" / "background.png"
# Feature heights are stored in 8 bits as z / FEATURE_HEIGHT_SCALE: 16 px covers a
# 32 px segment at feature_height 0.5 (links are at most about hc + step long)
# in steps of 0.06 px.
FEATURE_HEIGHT_SCALE = 16.0
MAX_DEPTH = 64.0  # px; features higher than this share the nearest depth
VERTEX_BYTES = VERTEX_FLOATS * 4


@dataclass(frozen=True)
class Material:
    """How the ice looks: Phong terms and the thickness-to-opacity law."""

    ice_color: tuple[float, float, float] = (0.90, 0.95, 1.0)
    ambient: float = 0.62  # frost scatters light: bright even away from the lamp
    diffuse: float = 0.40
    specular: float = 0.85
    shininess: float = 24.0
    opacity: float = 0.88  # very thick ice still lets a little of the view through
    density: float = 0.45  # alpha = opacity * (1 - exp(-density * thickness_px))
    relief: float = 1.6  # exaggerate slopes so px-high ice still catches the light
    refraction: float = 4.0  # px of background shift per unit of normal tilt


def default_light() -> np.ndarray:
    """Toward the light: up-left of the screen and in front (x right, y down, z viewer)."""
    v = np.array([-0.45, -0.55, 0.70])
    return v / np.linalg.norm(v)


def load_background(path: Path = BACKGROUND) -> np.ndarray:
    """The view through the window, H x W x 3 uint8 top-down."""
    if not path.is_file():
        raise FileNotFoundError(f"background image {path} is missing; "
                                "make it with: python3 assets/make_background.py")
    return np.asarray(Image.open(path).convert("RGB"))


class Renderer:
    """Draws the frost frame into a given framebuffer."""

    def __init__(self, ctx: moderngl.Context, params: Params, width: int = 760,
                 height: int = 1280, background: np.ndarray | None = None):
        self.ctx, self.params = ctx, params
        self.size = (width, height)
        self.light = default_light()
        self.material = Material()
        self.show_features = True
        self.show_bumps = True
        spacing = params.grid_spacing
        self.grid_size = (width // spacing + 1, height // spacing + 1)
        self._background = self._background_texture(background)
        self._heights = ctx.texture(self.grid_size, 1, dtype="f2")
        self._ice = ctx.texture(self.size, 4)
        self._ice_fbo = ctx.framebuffer([self._ice], ctx.depth_renderbuffer(self.size))
        self._feature_prog = load_program(ctx, "feature.vert", "feature.frag")
        self._composite_prog = load_program(ctx, "fullscreen.vert", "composite.frag")
        self._composite = ctx.vertex_array(self._composite_prog, [])
        self._vbo, self._features, self._pending = None, None, 0
        self._grow(1 << 16)
        self.reset()

    # ---- uploads ----------------------------------------------------------------

    def apply(self, delta: GeometryDelta) -> None:
        """Upload a tick's changes: its dirty height rows and its new feature vertices."""
        if delta.reset:
            self.reset()
        if delta.rows.stop > delta.rows.start:
            rows = delta.heights.astype(np.float16)
            viewport = (0, delta.rows.start, self.grid_size[0], len(rows))
            self._heights.write(rows.tobytes(), viewport=viewport)
        self._append(delta.features)

    def reset(self) -> None:
        """Clear glass: no heights, no features."""
        self._heights.write(np.zeros(self.grid_size[::-1], np.float16).tobytes())
        self._ice_fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self._pending = 0

    def _append(self, verts: np.ndarray) -> None:
        """Queue new feature vertices in the vertex buffer (drawn once, next frame)."""
        if len(verts) == 0:
            return
        need = (self._pending + len(verts)) * VERTEX_BYTES
        if need > self._vbo.size:
            self._grow(max(2 * self._vbo.size, need))
        self._vbo.write(np.ascontiguousarray(verts, np.float32).tobytes(),
                        offset=self._pending * VERTEX_BYTES)
        self._pending += len(verts)

    def _grow(self, size: int) -> None:
        vbo = self.ctx.buffer(reserve=size, dynamic=True)
        if self._vbo is not None:
            self.ctx.copy_buffer(vbo, self._vbo, self._pending * VERTEX_BYTES)
            self._vbo.release()
            self._features.release()
        self._vbo = vbo
        self._features = self.ctx.vertex_array(
            self._feature_prog, [(vbo, "3f 3f", "in_position", "in_normal")])

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
        self._draw_new_features()
        fbo.use()
        self.ctx.viewport = (0, 0, *self.size)
        self.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._background.use(0)
        self._heights.use(1)
        self._ice.use(2)
        self._set_composite_uniforms()
        self._composite.render(moderngl.TRIANGLES, vertices=3)

    def _draw_new_features(self) -> None:
        """Rasterize the queued feature triangles into the persistent ice texture."""
        if self._pending == 0:
            return
        prog = self._feature_prog
        prog["u_screen"].value = self.size
        prog["u_max_depth"].value = MAX_DEPTH
        prog["u_height_scale"].value = FEATURE_HEIGHT_SCALE
        self._ice_fbo.use()
        self.ctx.viewport = (0, 0, *self.size)
        self.ctx.disable(moderngl.BLEND)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.depth_func = "<"
        self._features.render(moderngl.TRIANGLES, vertices=self._pending)
        self.ctx.disable(moderngl.DEPTH_TEST)
        self._pending = 0

    def _set_composite_uniforms(self) -> None:
        prog, m = self._composite_prog, self.material
        light = np.asarray(self.light, np.float64)
        values = {
            "u_background": 0, "u_heights": 1, "u_ice": 2,
            "u_screen": self.size, "u_grid_size": self.grid_size,
            "u_spacing": float(self.params.grid_spacing),
            "u_height_scale": FEATURE_HEIGHT_SCALE,
            "u_show_bumps": float(self.show_bumps), "u_show_features": float(self.show_features),
            "u_light": tuple(light / np.linalg.norm(light)),
            "u_ice_color": m.ice_color, "u_ambient": m.ambient, "u_diffuse": m.diffuse,
            "u_specular": m.specular, "u_shininess": m.shininess, "u_opacity": m.opacity,
            "u_density": m.density, "u_relief": m.relief, "u_refraction": m.refraction,
        }
        for name, value in values.items():
            if name in prog:
                prog[name].value = value
