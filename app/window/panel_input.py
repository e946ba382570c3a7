"""Input to the tuning panel's window: GLFW's events handed to Dear ImGui, and when the
panel must redraw because of them (a click at once; a hover at most every HOVER_PERIOD)."""

from __future__ import annotations

from collections.abc import Callable

import glfw
from imgui_bundle import imgui

# ImGui settles in a frame or two after an input (hover, open a list, let go of a slider).
FRAMES_AFTER_INPUT = 3
# The pointer moving over the panel with no button held redraws it (hover highlights,
# tooltips) at most this often: on llvmpipe a redraw is ~6-8 ms, and a redraw at every
# move of a pointer crossing the panel would cost about 10 ms a phone frame.
HOVER_PERIOD = 0.1  # s
HOVER_FRAMES = 2  # ImGui shows a new tooltip one frame after it is first asked for
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


class Redraws:
    """When the panel redraws: what it shows changed, or an input is settling."""

    def __init__(self) -> None:
        self.wanted = 0  # redraws still wanted after the last input
        self.hurry = False  # a click, key or scroll: redraw at once, not at HOVER_PERIOD
        self.held = 0  # mouse buttons held down (bits): a drag redraws at once
        self.drawn_at = -HOVER_PERIOD  # perf_counter of the last redraw
        self.drawn_state: tuple | None = None  # what the last redraw showed

    def want(self) -> None:
        """An input that changes the panel at once."""
        self.wanted, self.hurry = FRAMES_AFTER_INPUT, True

    def hovered(self) -> None:
        """The pointer moved: two redraws (a tooltip shows on the second), HOVER_PERIOD
        apart; a drag (a button held) redraws at once."""
        if self.held:
            self.want()
        else:
            self.wanted = max(self.wanted, HOVER_FRAMES)

    def due(self, state: tuple, now: float) -> bool:
        """Redraw at `now` (perf_counter): `state` is not what the last redraw showed, or
        an input is settling (a hover's at most every HOVER_PERIOD)."""
        if state != self.drawn_state:
            return True
        soon = self.hurry or self.held or now - self.drawn_at >= HOVER_PERIOD
        return self.wanted > 0 and bool(soon)

    def drew(self, state: tuple, now: float) -> None:
        """A redraw showing `state` ended at `now`."""
        self.wanted, self.drawn_state, self.drawn_at = max(0, self.wanted - 1), state, now
        self.hurry = self.hurry and self.wanted > 0


class PanelInput:
    """GLFW's callbacks for the panel's window (`connect`): each input goes to ImGui and
    asks `redraws` for frames. Keys are the phone's (`phone_key(key, scancode, action,
    mods)`: M hides the panel, Esc quits) but while its text field is typed into; closing
    the window calls `hide()` instead."""

    def __init__(self, redraws: Redraws, phone_key: Callable[..., None],
                 hide: Callable[[], None]):
        self.redraws, self.phone_key, self.hide = redraws, phone_key, hide

    def connect(self, window) -> None:
        glfw.set_cursor_pos_callback(window, self.on_cursor)
        glfw.set_cursor_enter_callback(window, self.on_enter)
        glfw.set_mouse_button_callback(window, self.on_button)
        glfw.set_scroll_callback(window, self.on_scroll)
        glfw.set_char_callback(window, self.on_char)
        glfw.set_key_callback(window, self.on_key)
        glfw.set_window_close_callback(window, self.on_close)
        glfw.set_window_refresh_callback(window, lambda _window: self.redraws.want())
        glfw.set_framebuffer_size_callback(window, lambda *_: self.redraws.want())

    def on_cursor(self, _window, x: float, y: float) -> None:
        imgui.get_io().add_mouse_pos_event(x, y)
        self.redraws.hovered()

    def on_enter(self, _window, entered: int) -> None:
        if not entered:  # nothing stays hovered once the pointer has left
            imgui.get_io().add_mouse_pos_event(-imgui.FLT_MAX, -imgui.FLT_MAX)
            self.redraws.want()

    def on_button(self, window, button: int, action: int, _mods: int) -> None:
        if action == glfw.PRESS and not glfw.get_window_attrib(window, glfw.FOCUSED):
            glfw.focus_window(window)  # keys to its text field, with or without a WM
        if button in MOUSE_BUTTONS:
            imgui.get_io().add_mouse_button_event(MOUSE_BUTTONS[button], action == glfw.PRESS)
            bit = 1 << MOUSE_BUTTONS[button]
            held = self.redraws.held
            self.redraws.held = held | bit if action == glfw.PRESS else held & ~bit
            self.redraws.want()

    def on_scroll(self, _window, dx: float, dy: float) -> None:
        imgui.get_io().add_mouse_wheel_event(dx, dy)
        self.redraws.want()

    def on_char(self, _window, codepoint: int) -> None:
        imgui.get_io().add_input_character(codepoint)
        self.redraws.want()

    def on_key(self, _window, key: int, scancode: int, action: int, mods: int) -> None:
        """A key for the text field while it is typed into; else the phone's."""
        io = imgui.get_io()
        typing = io.want_text_input
        if key in KEYS:
            io.add_key_event(KEYS[key], action != glfw.RELEASE)
            self.redraws.want()
        if not typing:
            self.phone_key(key, scancode, action, mods)

    def on_close(self, window) -> None:
        """Closing the window hides it (M shows it again)."""
        glfw.set_window_should_close(window, False)
        self.hide()
