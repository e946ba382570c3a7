"""The moderngl renderer of Dear ImGui's draw lists against rectangles worked by hand: a
filled rectangle lands on the framebuffer pixels its window coordinates name (y down in
ImGui, y up in GL; twice as many framebuffer pixels on a HiDPI screen), its clip
rectangle cuts it, and blending is ImGui's straight alpha."""

from __future__ import annotations

import numpy as np
import pytest
from imgui_bundle import imgui

from app.gl.imgui_renderer import ImGuiRenderer
from app.images import read_image

pytestmark = pytest.mark.gl

SIZE = (80, 60)  # window px
CLEAR = (0.0, 0.0, 1.0)  # blue


@pytest.fixture
def gui(gl_ctx):
    context = imgui.create_context()
    imgui.get_io().set_ini_filename(None)
    renderer = ImGuiRenderer(gl_ctx)
    yield renderer
    renderer.release()
    imgui.destroy_context(context)


def drawn(gl_ctx, renderer, scale: float, paint) -> np.ndarray:
    """One ImGui frame whose foreground list holds what `paint` adds, drawn into a fresh
    framebuffer (the window times `scale`) cleared blue; top row first."""
    io = imgui.get_io()
    io.display_size = imgui.ImVec2(*SIZE)
    io.display_framebuffer_scale = imgui.ImVec2(scale, scale)
    io.delta_time = 0.04
    imgui.new_frame()
    paint(imgui.get_foreground_draw_list())
    imgui.render()
    fb = (round(SIZE[0] * scale), round(SIZE[1] * scale))
    fbo = gl_ctx.simple_framebuffer(fb, components=4)
    fbo.use()
    fbo.clear(*CLEAR, 1.0)
    renderer.render(imgui.get_draw_data(), fb)
    image = read_image(fbo).astype(int)
    fbo.release()
    return image


def red(alpha: int = 255) -> int:
    return imgui.color_convert_float4_to_u32(imgui.ImVec4(1.0, 0.0, 0.0, alpha / 255))


def box(image: np.ndarray, colour) -> set:
    """(x0, y0, x1, y1) of the pixels of `colour`, top row first; empty if none."""
    ys, xs = np.nonzero((image == colour).all(axis=-1))
    return {(xs.min(), ys.min(), xs.max() + 1, ys.max() + 1)} if len(xs) else set()


@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_a_rectangle_lands_where_its_window_coordinates_say(gl_ctx, gui, scale):
    image = drawn(gl_ctx, gui, scale, lambda dl: dl.add_rect_filled((10, 5), (30, 25), red()))
    s = int(scale)
    assert box(image, (255, 0, 0)) == {(10 * s, 5 * s, 30 * s, 25 * s)}
    assert (image[:5 * s] == (0, 0, 255)).all() and (image[:, 30 * s:] == (0, 0, 255)).all()


def test_its_clip_rectangle_cuts_it(gl_ctx, gui):
    def paint(dl):
        dl.push_clip_rect((20, 0), (80, 15))
        dl.add_rect_filled((10, 5), (30, 25), red())
        dl.pop_clip_rect()
    assert box(drawn(gl_ctx, gui, 2.0, paint), (255, 0, 0)) == {(40, 10, 60, 30)}


def test_it_blends_with_straight_alpha(gl_ctx, gui):
    image = drawn(gl_ctx, gui, 1.0, lambda dl: dl.add_rect_filled((10, 5), (30, 25), red(128)))
    want = np.array([255, 0, 0]) * 128 / 255 + np.array([0, 0, 255]) * (1 - 128 / 255)
    assert np.abs(image[15, 20] - want).max() <= 1

