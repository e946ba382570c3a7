"""The tuning panel in a window of its own beside the phone's (key M shows and hides it),
GLFW's input handed to Dear ImGui, and its frames drawn only when something changed.

The phone's window keeps its size and pays nothing for the panel between the panel's
redraws: the panel redraws on input to it, on a change of the parameters, preset or
backdrop, and when the window system asks; otherwise its pixels stay on the screen. On
llvmpipe under Xvfb a redraw costs several ms (mostly rasterizing its widgets), which a
panel drawn with every phone frame paid each frame. The panel's window has its own GL
context (its draws never disturb the phone's state) and swaps without waiting for the
screen. Closing it hides it, as M does; a click in it never reaches the phone.
"""

from __future__ import annotations

import logging
import statistics
import time
from collections import deque
from typing import Any

import glfw
import moderngl
from imgui_bundle import imgui

from app.gl.imgui_renderer import ImGuiRenderer
from app.window.glfw_setup import open_side_window, x_window_id
from app.window.panel import TuningPanel

log = logging.getLogger("app.window")
# Where the widgets lie, at debug level (scripts that click on them turn it on).
rects_log = logging.getLogger("app.window.panel")

WIDTH = 400  # window px
TITLE = "frost tuning (M hides)"
BACKGROUND = (0.11, 0.11, 0.13)
# ImGui settles in a frame or two after an input (hover, open a list, let go of a slider).
FRAMES_AFTER_INPUT = 3
# The pointer moving over the panel with no button held redraws it (hover highlights,
# tooltips) at most this often: on llvmpipe a redraw is ~6-8 ms, and a pointer crossing
# the panel otherwise redrew it every phone frame (~10 ms a frame, measured).
HOVER_PERIOD = 0.1  # s
HOVER_FRAMES = 2  # ImGui shows a new tooltip one frame after it is first asked for
COST_WINDOW = 2.0  # s of redraws the stats line's cost a frame is counted over
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
# The ImGui window fills the GLFW window, whose clear colour is its background (on
# llvmpipe a blended 400x1280 quad cost ~5 ms more than the clear).
WINDOW_FLAGS = (imgui.WindowFlags_.no_move | imgui.WindowFlags_.no_resize
                | imgui.WindowFlags_.no_collapse | imgui.WindowFlags_.no_saved_settings
                | imgui.WindowFlags_.no_background | imgui.WindowFlags_.no_title_bar)
ITEM_WIDTH = 210  # px of a slider; its label and reset button take the rest


class Deferred:
    """The window's actions as the panel sees them while it draws: reads pass through,
    `run` waits until the phone's GL context is current again (a screenshot reads the
    phone's framebuffer, a backdrop uploads a texture: in the panel's context they would
    touch the wrong objects)."""

    def __init__(self, actions):
        self.actions, self.queue = actions, []

    def __getattr__(self, name: str):
        return getattr(self.actions, name)

    def run(self, action: str, arg=None) -> None:
        self.queue.append((action, arg))

    def flush(self) -> None:
        queue, self.queue = self.queue, []
        for action, arg in queue:
            self.actions.run(action, arg)


class PanelHost:
    """The panel's ImGui context, its window (opened when first shown) and its costs.
    `phone` is the phone's GLFW window, whose context is current between calls."""

    def __init__(self, phone, actions):
        self.phone, self.actions = phone, actions
        self.context = imgui.create_context()
        io = imgui.get_io()
        io.set_ini_filename(None)  # no imgui.ini beside the user's files
        io.config_flags &= ~imgui.ConfigFlags_.nav_enable_keyboard
        self.deferred = Deferred(actions)
        self.panel = TuningPanel(self.deferred)
        self.window: Any = None  # a GLFW window once first shown
        self.x_id: int | None = None  # its X window id
        self.ctx: moderngl.Context | None = None
        self.renderer: ImGuiRenderer | None = None
        self.visible, self.wanted = False, 0
        self.hurry = False  # a click, key or scroll: redraw at once, not at HOVER_PERIOD
        self.held = 0  # mouse buttons held down (bits): a drag redraws at once
        self.drawn_at = -HOVER_PERIOD  # perf_counter of the last redraw
        self.drawn_state: tuple | None = None  # what the last redraw showed
        self.last = time.monotonic()
        self.logged: tuple[int, int] | None = None  # the window size the rects were logged at
        self.recent: deque[tuple[float, float]] = deque()  # (when, ms) of recent redraws
        self.phone_frames = 0  # phone frames drawn while the panel was shown
        self.total_ms = 0.0  # all its redraws
        self.shown_s, self.shown_at = 0.0, 0.0  # s shown in all; when last shown

    # ---- showing and hiding ----------------------------------------------------------

    def toggle(self) -> None:
        if self.window is None and not self._open():
            return
        self.visible = not self.visible
        if self.visible:
            self.shown_at = time.monotonic()
            x, y = self._beside_phone()
            glfw.set_window_pos(self.window, x, y)
            glfw.show_window(self.window)
            self.wanted = FRAMES_AFTER_INPUT
            log.info("panel: shown (its own window, %dx%d at %d,%d)",
                     *glfw.get_window_size(self.window), x, y)
        else:
            self.shown_s += time.monotonic() - self.shown_at
            glfw.hide_window(self.window)
            log.info("panel: hidden")

    def _open(self) -> bool:
        _, height = glfw.get_window_size(self.phone)
        window = open_side_window((WIDTH, height), TITLE)
        if window is None:
            glfw.make_context_current(self.phone)
            log.warning("panel: its window could not open")
            return False
        try:
            self.ctx = moderngl.create_context()
            self.renderer = ImGuiRenderer(self.ctx)
        finally:
            glfw.make_context_current(self.phone)
        self.window, self.x_id = window, x_window_id(window)
        self._connect(window)
        return True

    def _beside_phone(self) -> tuple[int, int]:
        """Just right of the phone's window, its frame included, tops level."""
        x, y = glfw.get_window_pos(self.phone)
        width, _ = glfw.get_window_size(self.phone)
        _, _, right, _ = glfw.get_window_frame_size(self.phone)
        left, _, _, _ = glfw.get_window_frame_size(self.window)
        return x + width + right + left, y

    def _connect(self, w) -> None:
        glfw.set_cursor_pos_callback(w, lambda _w, x, y: self._mouse_moved(x, y))
        glfw.set_cursor_enter_callback(w, lambda _w, entered: self._entered(entered))
        glfw.set_mouse_button_callback(w, lambda _w, b, action, _m: self._button(b, action))
        glfw.set_scroll_callback(w, lambda _w, dx, dy: self._scrolled(dx, dy))
        glfw.set_char_callback(w, lambda _w, c: self._char(c))
        glfw.set_key_callback(w, self._key)
        glfw.set_window_close_callback(w, lambda _w: self._closed())
        glfw.set_window_refresh_callback(w, lambda _w: self._want())
        glfw.set_framebuffer_size_callback(w, lambda *_: self._want())

    def needs_frame(self) -> bool:
        """A redraw is waiting on input just given (the frame loop should not sleep)."""
        return self.visible and self.wanted > 0

    # ---- input to the panel's window ---------------------------------------------------

    def _want(self) -> None:
        self.wanted, self.hurry = FRAMES_AFTER_INPUT, True

    def _mouse_moved(self, x: float, y: float) -> None:
        imgui.get_io().add_mouse_pos_event(x, y)
        if self.held:
            self._want()
        else:  # a hover: two redraws (a tooltip shows on the second), HOVER_PERIOD apart
            self.wanted = max(self.wanted, HOVER_FRAMES)

    def _entered(self, entered: int) -> None:
        if not entered:  # nothing stays hovered once the pointer has left
            imgui.get_io().add_mouse_pos_event(-imgui.FLT_MAX, -imgui.FLT_MAX)
            self._want()

    def _button(self, button: int, action: int) -> None:
        if action == glfw.PRESS and not glfw.get_window_attrib(self.window, glfw.FOCUSED):
            glfw.focus_window(self.window)  # keys to its text field, with or without a WM
        if button in MOUSE_BUTTONS:
            imgui.get_io().add_mouse_button_event(MOUSE_BUTTONS[button], action == glfw.PRESS)
            bit = 1 << MOUSE_BUTTONS[button]
            self.held = self.held | bit if action == glfw.PRESS else self.held & ~bit
            self._want()

    def _scrolled(self, dx: float, dy: float) -> None:
        imgui.get_io().add_mouse_wheel_event(dx, dy)
        self._want()

    def _char(self, codepoint: int) -> None:
        imgui.get_io().add_input_character(codepoint)
        self._want()

    def _key(self, _window, key, scancode, action, mods) -> None:
        """A key for the text field while it is typed into; else the window's keys, as
        if pressed over the phone (M hides the panel, Esc quits)."""
        io = imgui.get_io()
        typing = io.want_text_input
        if key in KEYS:
            io.add_key_event(KEYS[key], action != glfw.RELEASE)
            self._want()
        if not typing:
            self.actions.on_key(self.phone, key, scancode, action, mods)

    def _closed(self) -> None:
        glfw.set_window_should_close(self.window, False)
        if self.visible:
            self.toggle()

    # ---- a frame ---------------------------------------------------------------------

    def _state(self) -> tuple:
        """What the panel shows that can change without input to it."""
        return self.actions.params, self.actions.preset, self.actions.backdrop()

    def due(self, state: tuple, now: float) -> bool:
        """Redraw at `now` (perf_counter): `state` is not what the last redraw showed, or an
        input is settling (a hover's at most every HOVER_PERIOD)."""
        if not self.visible:
            return False
        if state != self.drawn_state:
            return True
        soon = self.hurry or self.held or now - self.drawn_at >= HOVER_PERIOD
        return self.wanted > 0 and bool(soon)

    def frame(self, phone_drawn: bool) -> None:
        """The panel redrawn in its window if something changed, timed (GL finished and
        the buffers swapped, the switches between the two contexts included)."""
        if not self.visible:
            return
        self.phone_frames += phone_drawn
        state = self._state()
        t0 = time.perf_counter()
        if not self.due(state, t0):
            return
        glfw.make_context_current(self.window)
        try:
            self._draw()
            glfw.swap_buffers(self.window)
            self.ctx.finish()  # type: ignore[union-attr]
        finally:
            glfw.make_context_current(self.phone)
        now = time.perf_counter()
        self._add_cost(now, 1000.0 * (now - t0))
        self.wanted, self.drawn_state, self.drawn_at = max(0, self.wanted - 1), state, now
        self.hurry = self.hurry and self.wanted > 0
        self.deferred.flush()

    def _draw(self) -> None:
        ctx, renderer = self.ctx, self.renderer
        assert ctx is not None and renderer is not None  # opened before it was shown
        (ww, wh) = glfw.get_window_size(self.window)
        (fw, fh) = glfw.get_framebuffer_size(self.window)
        ctx.screen.use()
        ctx.viewport = (0, 0, fw, fh)
        ctx.screen.clear(*BACKGROUND)
        io = imgui.get_io()
        io.display_size = imgui.ImVec2(ww, wh)
        io.display_framebuffer_scale = imgui.ImVec2(fw / max(1, ww), fh / max(1, wh))
        now = time.monotonic()
        io.delta_time, self.last = max(1e-4, now - self.last), now
        imgui.new_frame()
        imgui.set_next_window_pos((0, 0))
        imgui.set_next_window_size((ww, wh))
        imgui.begin(TITLE, None, WINDOW_FLAGS)
        imgui.push_item_width(ITEM_WIDTH)
        self.panel.draw()
        imgui.pop_item_width()
        imgui.end()
        imgui.render()
        renderer.render(imgui.get_draw_data(), (fw, fh))
        self._log_rects((ww, wh))

    def _add_cost(self, now: float, ms: float) -> None:
        self.panel.add_cost(ms)
        self.total_ms += ms
        self.recent.append((now, ms))
        while self.recent[0][0] < now - COST_WINDOW:
            self.recent.popleft()

    def readout(self, phone_frames: int) -> str | None:
        """The panel's cost for the stats line while it is shown: its ms over the last
        COST_WINDOW s shared among the `phone_frames` drawn meanwhile, and its redraws."""
        if not self.visible:
            return None
        now = time.perf_counter()
        ms = [m for t, m in self.recent if t >= now - COST_WINDOW]
        each = f", {statistics.median(ms):.1f} ms each" if ms else ""
        return (f"panel {sum(ms) / max(1, phone_frames):4.2f} ms/frame "
                f"({len(ms)} redraws{each})")

    def _log_rects(self, size: tuple[int, int]) -> None:
        """Where each widget lies in the panel's window, once for each size (debug level):
        for scripts that click on them."""
        if self.logged != size and self.panel.rects:
            self.logged = size
            for name, (x, y, w, h) in self.panel.rects.items():
                rects_log.debug("panel: %s at %.0f,%.0f size %.0fx%.0f", name, x, y, w, h)

    def close(self) -> None:
        costs = self.panel.costs
        shown = self.shown_s + (time.monotonic() - self.shown_at if self.visible else 0.0)
        if costs:
            log.info("panel: %d redraws, median %.2f ms, max %.2f ms (GL finished); shown "
                     "%.1f s: %.1f ms a second, %.2f ms a phone frame over %d frames", len(costs),
                     statistics.median(costs), max(costs), shown, self.total_ms / max(shown, 1e-9),
                     self.total_ms / max(1, self.phone_frames), self.phone_frames)
        if self.window is not None:
            glfw.make_context_current(self.window)
            self.renderer.release()  # type: ignore[union-attr]
            glfw.make_context_current(self.phone)
            glfw.destroy_window(self.window)
        imgui.destroy_context(self.context)
