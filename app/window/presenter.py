"""The phone on the screen: the frost rendered into an offscreen 760x1280 framebuffer,
then drawn letterboxed into the window with the HUD on top. Only the main thread calls it."""

from __future__ import annotations

import time

import moderngl
import numpy as np

from app.gl.renderer import Renderer
from app.gl.shaders import load_program
from app.images import read_image
from app.window.hud import Hud
from app.window.view import PHONE, letterbox
from sim import Params

BACKDROP = (0.08, 0.08, 0.09)  # the letterbox bars


class Presenter:
    """Owns the window's GL objects: the renderer, the phone framebuffer, the blit, the HUD."""

    def __init__(self, ctx: moderngl.Context, params: Params, view: dict | None = None,
                 photos=None):
        self.ctx = ctx
        self.renderer = Renderer(ctx, params, *PHONE)
        self.renderer.photos = photos  # (the folder a photo backdrop is found in by name)
        self.renderer.set_view(view)  # a replayed session's view
        self.texture = ctx.texture(PHONE, 4)
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.phone = ctx.framebuffer(color_attachments=[self.texture],
                                     depth_attachment=ctx.depth_renderbuffer(PHONE))
        self.blit = load_program(ctx, "blit.vert", "blit.frag")
        self.blit["u_texture"].value = 0
        self.blit["u_rect"].value = (-1.0, -1.0, 1.0, 1.0)  # the whole viewport
        self.quad = ctx.vertex_array(self.blit, [])
        self.hud = Hud(ctx)
        self.renders, self.render_ms = 0, 0.0  # render_ms: a moving average

    def render_phone(self) -> None:
        t0 = time.perf_counter()
        self.phone.use()
        self.renderer.render(self.phone)
        self.render_ms = 0.9 * self.render_ms + 100.0 * (time.perf_counter() - t0)
        self.renders += 1

    def read_phone(self) -> np.ndarray:
        """The phone frame last rendered, H x W x 3 uint8, top row first."""
        return read_image(self.phone)

    def present(self, framebuffer_size: tuple[int, int], stats: list[str], help_lines: list[str]) -> None:
        """The phone letterboxed into the window's framebuffer, the HUD over it (the caller
        swaps buffers)."""
        ctx = self.ctx
        ctx.screen.use()
        ctx.viewport = (0, 0, *framebuffer_size)
        ctx.screen.clear(*BACKDROP)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        ctx.viewport = letterbox(framebuffer_size)
        self.texture.use(0)
        self.quad.render(moderngl.TRIANGLE_STRIP, vertices=4)
        ctx.viewport = (0, 0, *framebuffer_size)
        self.hud.draw(framebuffer_size, stats, help_lines)
