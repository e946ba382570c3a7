"""The tuning panel's pixels: Dear ImGui's frame of the panel's widgets, drawn with the
panel's own GL context into its window (panel_host.py opens, shows and times it), and
where the widgets lie, logged for scripts that click on them."""

from __future__ import annotations

import logging
import time

import glfw
import moderngl
from imgui_bundle import imgui

from app.gl.imgui_renderer import ImGuiRenderer
from app.window.panel import TuningPanel

# Where the widgets lie, at debug level (scripts that click on them turn it on).
rects_log = logging.getLogger("app.window.panel")

BACKGROUND = (0.11, 0.11, 0.13)
# The ImGui window fills the GLFW window, whose clear colour is its background (on
# llvmpipe a blended 400x1280 quad cost ~5 ms more than the clear).
WINDOW_FLAGS = (imgui.WindowFlags_.no_move | imgui.WindowFlags_.no_resize
                | imgui.WindowFlags_.no_collapse | imgui.WindowFlags_.no_saved_settings
                | imgui.WindowFlags_.no_background | imgui.WindowFlags_.no_title_bar)
ITEM_WIDTH = 210  # px of a slider; its label and reset button take the rest


class PanelPainter:
    """`panel`'s widgets drawn into the panel's window under `title`: its GL context and
    ImGui renderer (made with the window, gone with it), a frame's drawing, the rects log."""

    def __init__(self, panel: TuningPanel, title: str):
        self.panel, self.title = panel, title
        self.gl_context: moderngl.Context | None = None
        self.renderer: ImGuiRenderer | None = None
        self.last = time.monotonic()
        self.logged: tuple[int, int] | None = None  # the window size the rects were logged at
        self.logged_path: str | None = None  # the file field's text, as last logged

    def open(self) -> None:
        """Its GL context and renderer, made in the context current (the panel window's)."""
        self.gl_context = moderngl.create_context()
        self.renderer = ImGuiRenderer(self.gl_context)

    def forget(self) -> None:
        """Its window is gone, its GL objects with it: nothing to release."""
        self.gl_context = self.renderer = None

    def release(self) -> None:
        """Its GL objects released (the panel window's context current)."""
        if self.renderer is not None:
            self.renderer.release()

    def finish(self) -> None:
        """GL finished (so a redraw's time is what it cost)."""
        self.gl_context.finish()  # type: ignore[union-attr]

    def draw(self, window, size: tuple[int, int], ui: float) -> None:
        """The panel drawn into `window` (its context current), `size` window px; `ui`:
        its widgets' size, times their size at content scale 1."""
        context, renderer = self.gl_context, self.renderer
        assert context is not None and renderer is not None  # opened before it was shown
        (window_w, window_h) = size
        (frame_w, frame_h) = glfw.get_framebuffer_size(window)
        context.screen.use()
        context.viewport = (0, 0, frame_w, frame_h)
        context.screen.clear(*BACKGROUND)
        io = imgui.get_io()
        io.display_size = imgui.ImVec2(window_w, window_h)
        io.display_framebuffer_scale = imgui.ImVec2(frame_w / max(1, window_w),
                                                    frame_h / max(1, window_h))
        now = time.monotonic()
        io.delta_time, self.last = max(1e-4, now - self.last), now
        imgui.new_frame()
        imgui.set_next_window_pos((0, 0))
        imgui.set_next_window_size((window_w, window_h))
        imgui.begin(self.title, None, WINDOW_FLAGS)
        imgui.push_item_width(ITEM_WIDTH * ui)
        self.panel.draw()
        imgui.pop_item_width()
        imgui.end()
        imgui.render()
        renderer.render(imgui.get_draw_data(), (frame_w, frame_h))
        self._log_rects((window_w, window_h))

    def _log_rects(self, size: tuple[int, int]) -> None:
        """Where each widget lies in the panel's window, once for each size, and what its
        file field holds, when that changes (debug level): for scripts that click on them
        and type into it."""
        if self.logged != size and self.panel.rects:
            self.logged = size
            for name, (x, y, w, h) in self.panel.rects.items():
                rects_log.debug("panel: %s at %.0f,%.0f size %.0fx%.0f", name, x, y, w, h)
        if self.logged_path != self.panel.path:  # what the file field holds, as typed
            self.logged_path = self.panel.path
            rects_log.debug("panel: the file field holds %r", self.panel.path)
