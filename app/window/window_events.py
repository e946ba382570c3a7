"""The phone window's own events, from GLFW's callbacks: its sizes and content scale,
whether it is iconified or damaged; and the callbacks of its input (keys, mouse, drops)."""

from __future__ import annotations

from collections.abc import Callable

import glfw

from app.window.view import Sizes


class WindowEvents:
    """What the frame loop asks of the window between frames, kept up to date by the
    callbacks: each GLFW call from Python waits for the GIL, which the simulation thread
    may hold for a few ms, so the frame loop makes as few as it can."""

    def __init__(self, window, on_scale: Callable[[float], None]):
        """`on_scale(x_scale)`: the window moved to a screen of another content scale."""
        self.window, self._on_scale = window, on_scale
        self.sizes = Sizes(glfw.get_window_size(window), glfw.get_framebuffer_size(window))
        self.iconified = False
        self.damaged = True  # present again (the window's contents were lost or resized)

    def connect(self, on_key, on_button, on_cursor, on_drop) -> None:
        """The callbacks: the window's own, and those of its input."""
        window = self.window
        glfw.set_key_callback(window, on_key)
        glfw.set_mouse_button_callback(window, on_button)
        glfw.set_cursor_pos_callback(window, on_cursor)
        glfw.set_framebuffer_size_callback(window, self._on_framebuffer)
        glfw.set_window_size_callback(window, self._on_window_size)
        glfw.set_window_iconify_callback(window,
                                         lambda _window, on: setattr(self, "iconified", bool(on)))
        glfw.set_window_refresh_callback(window, lambda *_: setattr(self, "damaged", True))
        glfw.set_window_content_scale_callback(window, self._on_content_scale)
        # (pyGLFW hands the callback the list of paths, whatever its type stubs say)
        glfw.set_drop_callback(window, on_drop)

    def minimized(self) -> bool:
        return self.iconified or 0 in self.sizes.framebuffer

    def _on_framebuffer(self, _window, w: int, h: int) -> None:
        self.sizes.framebuffer = (w, h)
        self.damaged = True

    def _on_window_size(self, _window, w: int, h: int) -> None:
        self.sizes.window = (w, h)

    def _on_content_scale(self, _window, x_scale: float, _y_scale: float) -> None:
        """The window moved to a screen of another scale: the HUD's text follows."""
        self._on_scale(x_scale)
        self.damaged = True
