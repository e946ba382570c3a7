"""The maps' preview: a grown frost drawn by the renderer at its own size, headless (EGL),
over a flat backdrop, from one redraw of its live ice (what the window would show)."""

from __future__ import annotations

import numpy as np

from app.gl.renderer import Renderer
from app.images import read_image
from app.tools.offscreen import make_context
from sim import FrostSim, Params
from sim.look.geometry import FrostGeometry


def draw_preview(sim: FrostSim, params: Params, wrap: bool,
                 rgb: tuple[int, int, int]) -> np.ndarray:
    """H x W x 3 uint8: the frost of `sim` drawn over a flat `rgb` backdrop."""
    w, h = sim.width, sim.height
    ctx = make_context()
    try:
        backdrop = np.empty((h, w, 3), np.uint8)
        backdrop[:] = rgb
        renderer = Renderer(ctx, params, w, h, background=backdrop)
        renderer.backdrop = "flat"
        renderer.apply(FrostGeometry(params, w, h, wrap=wrap).redraw(sim))
        fbo = ctx.simple_framebuffer((w, h), components=4)
        renderer.render(fbo)
        return read_image(fbo)
    finally:
        ctx.release()
