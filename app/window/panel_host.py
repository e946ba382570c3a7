"""The tuning panel in a window of its own beside the phone's (key M shows and hides it),
its frames drawn only when something changed, and what they cost.

The phone's window keeps its size and pays nothing for the panel between the panel's
redraws: the panel redraws on input to it (`panel_input`), on a change of the parameters,
preset or backdrop, and when the window system asks; otherwise its pixels stay on the
screen. On llvmpipe under Xvfb a redraw costs several ms (mostly rasterizing its
widgets), which a panel drawn with every phone frame would pay each frame. The panel's window
has its own GL context (its draws never disturb the phone's state) and swaps without
waiting for the screen. Closing it hides it, as M does; a click in it never reaches the
phone. Its window destroyed from outside (X11: `lost`) closes the panel, and M opens a new
one.
"""

from __future__ import annotations

import logging
import statistics
import time
from collections import deque
from typing import Any

import glfw
from imgui_bundle import imgui

from app.window.glfw_setup import open_side_window, x_window_ids
from app.window.panel import TuningPanel
from app.window.panel_draw import PanelPainter
from app.window.panel_input import FRAMES_AFTER_INPUT, PanelInput, Redraws

log = logging.getLogger("app.window")

WIDTH = 400  # window px
TITLE = "frost tuning (M hides)"
COST_WINDOW = 2.0  # s of redraws the stats line's cost a frame is counted over


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


class PanelCosts:
    """What the panel's redraws cost, for the stats line while shown and the log at exit."""

    def __init__(self) -> None:
        self.recent: deque[tuple[float, float]] = deque()  # (when, ms) of recent redraws
        self.phone_frames = 0  # phone frames drawn while the panel was shown
        self.total_ms = 0.0  # all its redraws
        self.shown_s, self.shown_at = 0.0, 0.0  # s shown in all; when last shown

    def add(self, now: float, ms: float) -> None:
        """A redraw of `ms` ended at `now` (perf_counter)."""
        self.total_ms += ms
        self.recent.append((now, ms))
        while self.recent[0][0] < now - COST_WINDOW:
            self.recent.popleft()

    def readout(self, phone_frames: int) -> str:
        """Its ms over the last COST_WINDOW s shared among the `phone_frames` drawn
        meanwhile, and its redraws."""
        now = time.perf_counter()
        ms = [m for t, m in self.recent if t >= now - COST_WINDOW]
        each = f", {statistics.median(ms):.1f} ms each" if ms else ""
        return (f"panel {sum(ms) / max(1, phone_frames):4.2f} ms/frame "
                f"({len(ms)} redraws{each})")

    def summary(self, costs: list[float], visible: bool) -> None:
        """The log's line at exit; `costs`: the redraws' ms."""
        shown = self.shown_s + (time.monotonic() - self.shown_at if visible else 0.0)
        if costs:
            log.info("panel: %d redraws, median %.2f ms, max %.2f ms (GL finished); shown "
                     "%.1f s: %.1f ms a second, %.2f ms a phone frame over %d frames", len(costs),
                     statistics.median(costs), max(costs), shown, self.total_ms / max(shown, 1e-9),
                     self.total_ms / max(1, self.phone_frames), self.phone_frames)


class PanelHost:
    """The panel's ImGui context, its window (opened when first shown), its frames.
    `phone` is the phone's GLFW window, whose context is current between calls."""

    def __init__(self, phone, actions):
        self.phone, self.actions = phone, actions
        self.context = _imgui_context()  # ImGui's; GL's is the painter's
        self.deferred = Deferred(actions)
        self.panel = TuningPanel(self.deferred)
        self.painter = PanelPainter(self.panel, TITLE)  # its GL context and drawing
        self.window: Any = None  # a GLFW window once first shown
        self.ids: tuple[int, ...] = ()  # the X ids naming it in X errors
        self.gone = False  # its window was destroyed from outside (set inside Xlib)
        self.visible = False
        self.redraws, self.costs = Redraws(), PanelCosts()
        self.input = PanelInput(self.redraws, lambda *key: actions.on_key(phone, *key),
                                self.hide)
        self.ui = 1.0  # its widgets' and text's size, times their size at content scale 1

    # ---- showing and hiding ----------------------------------------------------------

    def toggle(self) -> None:
        """M: shown or hidden; a window destroyed from outside is met first, so M opens a
        new one rather than hide the one that is gone."""
        self._meet_if_gone()
        self._toggle()

    def _toggle(self) -> None:
        self._forget_if_gone()
        if self.window is None and not self._open():
            return
        self.visible = not self.visible
        if self.visible:
            self.costs.shown_at = time.monotonic()
            x, y = self._beside_phone()
            glfw.set_window_pos(self.window, x, y)
            glfw.show_window(self.window)
            self.redraws.wanted = FRAMES_AFTER_INPUT
            log.info("panel: shown (its own window, %dx%d at %d,%d)",
                     *glfw.get_window_size(self.window), x, y)
        else:
            self.costs.shown_s += time.monotonic() - self.costs.shown_at
            glfw.hide_window(self.window)
            log.info("panel: hidden")

    def hide(self) -> None:
        """Hidden (its window asked to close: there to hide)."""
        if self.visible:
            self._toggle()

    def _open(self) -> bool:
        _, height = glfw.get_window_size(self.phone)
        self.ui = ui_scale(self.phone)
        window = open_side_window((round(WIDTH * self.ui), height), TITLE)
        if window is None:
            glfw.make_context_current(self.phone)
            log.warning("panel: its window could not open")
            return False
        try:
            self.painter.open()
        finally:
            glfw.make_context_current(self.phone)
        self.window, self.ids = window, x_window_ids(window)
        self.input.connect(window)
        style = imgui.get_style()  # (this context's: laid out for the screen's scale)
        style.scale_all_sizes(self.ui)
        style.font_scale_dpi = self.ui
        return True

    # ---- its window destroyed from outside ---------------------------------------------

    def lost(self, resource: int) -> tuple[int, ...]:
        """An X request failed on `resource`, a window gone: if it is the panel's, the
        panel's X ids (the error handler ignores their errors from now on), and the panel
        is closed at its next call from the frame loop; else (). Called inside Xlib: no
        GLFW or GL call here."""
        if resource not in self.ids:
            return ()
        self.gone = True
        return self.ids

    def _meet_if_gone(self) -> None:
        """A round trip to the X server on its window (shown or hidden), so one destroyed
        from outside is met now: an idle panel's window gets no request, and M would
        otherwise hide the window that is gone (the error met only then) instead of
        opening a new one."""
        if self.window is not None and not self.gone:
            glfw.get_window_pos(self.window)  # (XTranslateCoordinates: waits for its reply)

    def _forget_if_gone(self) -> None:
        """Its window destroyed from outside: closed, as if never opened (M opens a new
        one). The GLFW window is destroyed (its GL context with it, and the GL objects
        made in it: released one by one they would need that context current on a drawable
        that is gone); the ImGui context is made anew, as its font atlas counts its
        texture as uploaded to the dead context."""
        if not self.gone:
            return
        if self.visible:
            self.costs.shown_s += time.monotonic() - self.costs.shown_at
        glfw.destroy_window(self.window)
        glfw.make_context_current(self.phone)
        self.window, self.ids, self.gone, self.visible = None, (), False, False
        self.painter.forget()
        imgui.destroy_context(self.context)
        self.context = _imgui_context()
        self.redraws = self.input.redraws = Redraws()  # no input left settling
        log.debug("panel: its window's remains released")

    def _beside_phone(self) -> tuple[int, int]:
        """Just right of the phone's window, its frame included, tops level."""
        x, y = glfw.get_window_pos(self.phone)
        width, _ = glfw.get_window_size(self.phone)
        _, _, right, _ = glfw.get_window_frame_size(self.phone)
        left, _, _, _ = glfw.get_window_frame_size(self.window)
        return x + width + right + left, y

    def needs_frame(self) -> bool:
        """A redraw is waiting on input just given (the frame loop should not sleep), or
        the window is gone and must be forgotten."""
        return self.gone or (self.visible and self.redraws.wanted > 0)

    # ---- a frame ---------------------------------------------------------------------

    def state(self) -> tuple:
        """What the panel shows that can change without input to it."""
        return self.actions.params, self.actions.preset, self.actions.backdrop()

    def due(self, now: float) -> bool:
        """Shown, and a redraw is due at `now` (perf_counter)."""
        return self.visible and self.redraws.due(self.state(), now)

    def frame(self, phone_drawn: bool) -> None:
        """The panel redrawn in its window if something changed, timed (GL finished and
        the buffers swapped, the switches between the two contexts included)."""
        self._forget_if_gone()
        if not self.visible:
            return
        self.costs.phone_frames += phone_drawn
        started = time.perf_counter()
        if not self.due(started):
            return
        state = self.state()
        if not self._redraw():
            self.deferred.flush()  # what was clicked before the window went still runs
            self._forget_if_gone()
            return
        now = time.perf_counter()
        self.panel.add_cost(1000.0 * (now - started))
        self.costs.add(now, 1000.0 * (now - started))
        self.redraws.drew(state, now)
        self.deferred.flush()

    def _redraw(self) -> bool:
        """Drawn and swapped; False when the window turned out to be gone. Its size is read
        first, a round trip to the X server: a window gone is told there, before its GL
        context is made current on a drawable that is gone (which Mesa's llvmpipe took
        seconds to refuse under Xvfb, the frame loop stalled meanwhile). A window that goes
        during the draw makes the draw fail (e.g. ImGui's check of the size it then reads)."""
        size = glfw.get_window_size(self.window)
        if self.gone:
            return False
        glfw.make_context_current(self.window)
        try:
            self._draw(size)
            glfw.swap_buffers(self.window)
            self.painter.finish()
        except Exception as err:
            if not self.gone:
                raise
            log.debug("panel: the redraw under way met its window gone (%r)", err)
        finally:
            glfw.make_context_current(self.phone)
        return not self.gone

    def _draw(self, size: tuple[int, int]) -> None:
        """The panel drawn into its window, `size` window px (its context current)."""
        self.painter.draw(self.window, size, self.ui)

    def readout(self, phone_frames: int) -> str | None:
        """The panel's cost for the stats line while it is shown (PanelCosts.readout)."""
        return self.costs.readout(phone_frames) if self.visible else None

    def close(self) -> None:
        self._forget_if_gone()
        self.costs.summary(self.panel.costs, self.visible)
        if self.window is not None:
            glfw.make_context_current(self.window)
            self.painter.release()
            glfw.make_context_current(self.phone)
            glfw.destroy_window(self.window)
        imgui.destroy_context(self.context)


def ui_scale(window) -> float:
    """How much larger than at content scale 1 the panel's widgets are laid out, in its
    window's coordinates: the content scale where they are pixels (Windows, X11: 1.5 at
    150 %), 1 where they are points (a Mac, whose framebuffer is already twice the
    window and ImGui draws into it at that scale)."""
    scale = glfw.get_window_content_scale(window)[0]
    (width, _), (frame, _) = glfw.get_window_size(window), glfw.get_framebuffer_size(window)
    return max(1.0, scale / max(1.0, frame / max(1, width)))


def _imgui_context():
    """A new Dear ImGui context, made current: no imgui.ini beside the user's files, no
    keyboard navigation (keys over the panel are the phone's)."""
    context = imgui.create_context()
    io = imgui.get_io()
    io.set_ini_filename(None)
    io.config_flags &= ~imgui.ConfigFlags_.nav_enable_keyboard
    return context
