"""The tuning panel in the window: shown and hidden (key M), the window widened by its
width so the phone keeps its size, GLFW's input handed to Dear ImGui, and its frame drawn
over the right-hand strip and timed.

Hidden, it costs nothing and the window is as before. Shown, the phone is letterboxed in
the rest (`Sizes.panel`), so clicks map to the phone as before and a click on the panel
never reaches it. The panel draws only when the window presents (on input, on change).
"""

from __future__ import annotations

import logging
import statistics
import time

import glfw
import moderngl
from imgui_bundle import imgui

from app.gl.imgui_renderer import ImGuiRenderer
from app.window.panel import TuningPanel
from app.window.view import PHONE, Sizes

log = logging.getLogger("app.window")
# Where the widgets lie, at debug level (scripts that click on them turn it on).
rects_log = logging.getLogger("app.window.panel")

WIDTH = 400  # window px
# ImGui settles in a frame or two after an input (hover, open a list, let go of a slider).
FRAMES_AFTER_INPUT = 3
MOUSE_BUTTONS = {glfw.MOUSE_BUTTON_LEFT: 0, glfw.MOUSE_BUTTON_RIGHT: 1, glfw.MOUSE_BUTTON_MIDDLE: 2}
# The keys a text field needs (the file name), GLFW's to ImGui's.
KEYS = {glfw.KEY_BACKSPACE: imgui.Key.backspace, glfw.KEY_DELETE: imgui.Key.delete,
        glfw.KEY_ENTER: imgui.Key.enter, glfw.KEY_KP_ENTER: imgui.Key.keypad_enter,
        glfw.KEY_LEFT: imgui.Key.left_arrow, glfw.KEY_RIGHT: imgui.Key.right_arrow,
        glfw.KEY_HOME: imgui.Key.home, glfw.KEY_END: imgui.Key.end, glfw.KEY_TAB: imgui.Key.tab,
        glfw.KEY_ESCAPE: imgui.Key.escape, glfw.KEY_A: imgui.Key.a, glfw.KEY_C: imgui.Key.c,
        glfw.KEY_V: imgui.Key.v, glfw.KEY_X: imgui.Key.x,
        glfw.KEY_LEFT_CONTROL: imgui.Key.mod_ctrl, glfw.KEY_RIGHT_CONTROL: imgui.Key.mod_ctrl,
        glfw.KEY_LEFT_SHIFT: imgui.Key.mod_shift, glfw.KEY_RIGHT_SHIFT: imgui.Key.mod_shift}
# No background of its own: the window's clear colour shows through (on llvmpipe a
# 400x1280 blended quad alone cost ~5 ms a frame; the clear is done anyway).
WINDOW_FLAGS = (imgui.WindowFlags_.no_move | imgui.WindowFlags_.no_resize
                | imgui.WindowFlags_.no_collapse | imgui.WindowFlags_.no_saved_settings
                | imgui.WindowFlags_.no_background)
ITEM_WIDTH = 210  # px of a slider; its label and reset button take the rest


class PanelHost:
    """The panel's ImGui context, its input and its place in one GLFW window."""

    def __init__(self, window, ctx: moderngl.Context, sizes: Sizes, actions):
        self.window, self.ctx, self.sizes = window, ctx, sizes
        self.context = imgui.create_context()
        io = imgui.get_io()
        io.set_ini_filename(None)  # no imgui.ini beside the user's files
        io.config_flags &= ~imgui.ConfigFlags_.nav_enable_keyboard
        self.renderer = ImGuiRenderer(ctx)
        self.panel = TuningPanel(actions)
        self.visible, self.wanted = False, 0
        self.last = time.monotonic()
        self.logged: tuple[int, int] | None = None  # the window size the rects were logged at

    # ---- showing and hiding ----------------------------------------------------------

    def toggle(self) -> None:
        self.visible = not self.visible
        (ww, wh), (fw, _) = self.sizes.window, self.sizes.framebuffer
        self.sizes.panel = round(WIDTH * fw / max(1, ww)) if self.visible else 0
        glfw.set_window_aspect_ratio(self.window, glfw.DONT_CARE, glfw.DONT_CARE)
        width = ww + WIDTH if self.visible else max(1, ww - WIDTH)
        glfw.set_window_size(self.window, width, wh)
        if not self.visible:
            glfw.set_window_aspect_ratio(self.window, *PHONE)
        self.wanted = FRAMES_AFTER_INPUT
        log.info("panel: %s (window %dx%d)", "shown" if self.visible else "hidden", width, wh)

    def on_resize(self) -> None:
        """The window's or framebuffer's size changed: the panel keeps its width in px."""
        if self.visible:
            (ww, _), (fw, _) = self.sizes.window, self.sizes.framebuffer
            self.sizes.panel = round(WIDTH * fw / max(1, ww))
            self.wanted = FRAMES_AFTER_INPUT

    def needs_frame(self) -> bool:
        return self.visible and self.wanted > 0

    # ---- input: True where the panel takes it from the phone and the keys --------------

    def on_cursor(self, x: float, y: float) -> None:
        if self.visible:
            imgui.get_io().add_mouse_pos_event(x, y)
            self.wanted = FRAMES_AFTER_INPUT

    def on_button(self, button: int, action: int) -> bool:
        if not self.visible or button not in MOUSE_BUTTONS:
            return False
        imgui.get_io().add_mouse_button_event(MOUSE_BUTTONS[button], action == glfw.PRESS)
        self.wanted = FRAMES_AFTER_INPUT
        return action == glfw.PRESS and self._over_panel()

    def on_scroll(self, dx: float, dy: float) -> None:
        if self.visible:
            imgui.get_io().add_mouse_wheel_event(dx, dy)
            self.wanted = FRAMES_AFTER_INPUT

    def on_char(self, codepoint: int) -> None:
        if self.visible:
            imgui.get_io().add_input_character(codepoint)
            self.wanted = FRAMES_AFTER_INPUT

    def on_key(self, key: int, action: int) -> bool:
        """A key for a text field being typed into (the frost keys wait meanwhile)."""
        if not self.visible:
            return False
        io = imgui.get_io()
        if key in KEYS:
            io.add_key_event(KEYS[key], action != glfw.RELEASE)
            self.wanted = FRAMES_AFTER_INPUT
        return io.want_text_input

    def _over_panel(self) -> bool:
        x, _ = glfw.get_cursor_pos(self.window)
        return x >= self.sizes.window[0] - WIDTH or imgui.get_io().want_capture_mouse

    # ---- a frame ---------------------------------------------------------------------

    def draw(self) -> None:
        """The panel over the right-hand strip of the current framebuffer, timed (GL work
        included: finished before and after, so the phone's frame is not counted)."""
        if not self.visible:
            return
        self.ctx.finish()
        t0 = time.perf_counter()
        self._frame()
        self.ctx.finish()
        self.panel.add_cost(1000.0 * (time.perf_counter() - t0))
        self.wanted = max(0, self.wanted - 1)

    def _frame(self) -> None:
        io = imgui.get_io()
        (ww, wh), (fw, fh) = self.sizes.window, self.sizes.framebuffer
        io.display_size = imgui.ImVec2(ww, wh)
        io.display_framebuffer_scale = imgui.ImVec2(fw / max(1, ww), fh / max(1, wh))
        now = time.monotonic()
        io.delta_time, self.last = max(1e-4, now - self.last), now
        imgui.new_frame()
        imgui.set_next_window_pos((ww - WIDTH, 0))
        imgui.set_next_window_size((WIDTH, wh))
        imgui.begin("tuning (M hides)", None, WINDOW_FLAGS)
        imgui.push_item_width(ITEM_WIDTH)
        self.panel.draw()
        imgui.pop_item_width()
        imgui.end()
        imgui.render()
        self.renderer.render(imgui.get_draw_data(), (fw, fh))
        self._log_rects()

    def _log_rects(self) -> None:
        """Where each widget lies, once for each window size (debug level): for scripts
        that click on them."""
        if self.logged != self.sizes.window and self.panel.rects:
            self.logged = self.sizes.window
            for name, (x, y, w, h) in self.panel.rects.items():
                rects_log.debug("panel: %s at %.0f,%.0f size %.0fx%.0f", name, x, y, w, h)

    def close(self) -> None:
        costs = self.panel.costs
        if costs:
            log.info("panel: %d frames, median %.2f ms, max %.2f ms (GL finished)", len(costs),
                     statistics.median(costs), max(costs))
        self.renderer.release()
        imgui.destroy_context(self.context)
