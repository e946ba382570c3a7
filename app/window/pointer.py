"""The mouse: a left click plants a seed and a left drag a trail of them; a right drag is
the warm finger that melts the ice along its path. Both become commands for the
simulation thread; where the cursor is comes from the events, not from a query."""

from __future__ import annotations

import time
from collections.abc import Callable

import glfw

from app.simthread.thread import SimThread
from app.window.view import Sizes
from sim.io.gestures import DRAG_SPACING_HC, MELT_SPACING, path_points


class Pointer:
    """GLFW's mouse-button and cursor callbacks for one window."""

    def __init__(self, window, sizes: Sizes, thread: SimThread, melt_radius: float,
                 hc: Callable[[], float], tick: Callable[[], int],
                 melted: Callable[[int, int, float], None]):
        self.window, self.sizes, self.thread = window, sizes, thread
        self.melt_radius = melt_radius
        self.hc, self.tick = hc, tick  # the freezing radius asked for; the tick shown
        self.melted = melted  # (last command, melts, radius) of a right drag just ended
        self.cursor: tuple[float, float] | None = None  # the last motion event's, window px
        self.drag_from = None  # where a left drag last planted
        self.melt_from = None  # where a right drag last melted
        self.melts_sent = 0  # by the current right drag

    def on_button(self, _window, button, action, _mods) -> None:
        if button == glfw.MOUSE_BUTTON_RIGHT:
            self._warm_finger(action)
        elif button == glfw.MOUSE_BUTTON_LEFT:
            self._finger(action)

    def on_cursor(self, _window, x, y) -> None:
        self.cursor = (x, y)
        if self.melt_from is not None:
            self.melt_from = self._trail(self.melt_from, MELT_SPACING * self.melt_radius,
                                         self._send_melt)
        if self.drag_from is not None:
            self.drag_from = self._trail(self.drag_from, DRAG_SPACING_HC * self.hc(),
                                         lambda spot: self.thread.send("touch", (spot, None)))

    def _finger(self, action) -> None:
        """Left button down: a touch, timed from the click for the latency log."""
        self.drag_from = None
        if action == glfw.RELEASE:
            return
        spot = self._phone_spot()
        if spot is not None:
            self.thread.send("touch", (spot, (self.tick(), time.monotonic())))
            self.drag_from = spot

    def _warm_finger(self, action) -> None:
        """Right button down: melt under the cursor, and along the path while it is held."""
        if action == glfw.RELEASE:
            if self.melt_from is not None:
                self.melted(self.thread.sent, self.melts_sent, self.melt_radius)
            self.melt_from = None
            return
        self.melt_from, self.melts_sent = self._phone_spot(), 0
        if self.melt_from is not None:
            self._send_melt(self.melt_from)

    def _send_melt(self, spot) -> None:
        self.thread.send("melt", (*spot, self.melt_radius))
        self.melts_sent += 1

    def _trail(self, start, spacing: float, send):
        """Spots every `spacing` px from `start` toward the cursor, each sent; the last spot
        (the start while the cursor is off the phone or not far enough yet)."""
        spot = self._phone_spot()
        if spot is None:
            return start
        points = path_points(start, spot, spacing)
        for point in points:
            send(point)
        return points[-1] if points else start

    def _phone_spot(self):
        """Where the events so far put the cursor (a drag follows its path even when the
        frame loop runs behind the pointer), in phone px; None outside the phone."""
        cursor = self.cursor if self.cursor is not None else glfw.get_cursor_pos(self.window)
        return self.sizes.phone_at(cursor)
