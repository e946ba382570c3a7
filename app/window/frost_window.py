"""The interactive phone window: the frame loop and the parts it calls.

Each frame the main thread drains every snapshot of the simulation thread, applies the
geometry deltas in order, renders the phone into an offscreen 760x1280 framebuffer when
it changed, and presents it letterboxed with the HUD on top. Only this thread calls GL.
Input: `Pointer` (mouse), `Actions` (keys); files: `Capture`; words: `Status`.
"""

from __future__ import annotations

import contextlib
import logging
import math
import signal
import time
from collections.abc import Callable
from pathlib import Path

import glfw
import moderngl

from app.backdrops import BACKDROPS, LIVE
from app.keys import help_lines
from app.lockscreen import clock_from, outside_line
from app.photos import PhotoError, is_photo, keep, read_file, store_of
from app.simthread.thread import SimThread, Snapshot
from app.weather.feed import feed_for
from app.window.actions import Actions
from app.window.capture import Capture
from app.window.clock_drawer import ClockDrawer
from app.window.drop import PhotoDrop
from app.window.glfw_setup import WindowError, open_window, x_window_ids
from app.window.lost_display import on_lost_display, on_lost_window
from app.window.no_panel import NoPanel
from app.window.pointer import Pointer
from app.window.presenter import Presenter
from app.window.record import Recorder
from app.window.status import Status
from app.window.view import PHONE
from app.window.window_events import WindowEvents
from sim import Params
from sim.io.files import one_line
from sim.io.session import VERSION

PANEL_ERROR = ""  # why the panel's module did not import
try:  # imgui-bundle is installed only where it has a wheel (app/window/no_panel.py)
    from app.window.panel_host import PanelHost
except ImportError as err:
    PanelHost = None  # type: ignore[assignment,misc]
    PANEL_ERROR = str(err)

log = logging.getLogger("app.window")

IDLE_WAIT = 0.1  # s to wait for events while minimized or idle
PANEL_WAIT = 0.02  # s, while the panel settles after an input (a few redraws)
HELP = help_lines("\t")  # the help overlay, key and description in two columns


class FrostWindow:
    """One window: its parts, the simulation thread feeding it, and the frame loop."""

    def __init__(self, window, args, params: Params):
        self.window, self.max_seconds = window, args.max_seconds
        self.events = WindowEvents(window, lambda scale: self.presenter.hud.set_scale(scale))
        self.display_gone = False  # (lost_display: no GLFW call may meet the dead connection)
        self.thread = SimThread(params, args.seed, args.touch or (), *PHONE, wake=self._wake,
                                script=getattr(args, "script", ()),
                                version=getattr(args, "session_version", VERSION))
        # The lock screen's clock: local time, or --clock-start's; a replay's own minutes.
        self.thread.clock = None if self.thread.script else clock_from(getattr(args, "clock_start", None))
        self.presenter = Presenter(moderngl.create_context(), params, getattr(args, "view", None),
                                   photos=store_of(args.session_dir))
        self.drop = PhotoDrop(self.thread, store_of(args.session_dir))  # a photo dropped on it
        self.clock = ClockDrawer(self.presenter.renderer.clock_box, self._wake)
        self.thread.show_clock("window", self.presenter.renderer.backdrop == LIVE)
        self.presenter.hud.set_scale(glfw.get_window_content_scale(window)[0])
        self.status = Status()
        self.recorder = Recorder(args.screenshot_dir, self.thread.notify)
        self.capture = Capture(self.thread, self.presenter, self.status.say, args.screenshot_dir,
                               args.session_dir)
        self.actions = Actions(params, self.thread, self.presenter, self.status, self.capture,
                               self.recorder, lambda: self.latest, self.redraw, self.stop)
        first_backdrop(args, self.thread, self.actions, self.drop.store)
        self.pointer = Pointer(window, self.events.sizes, self.thread, args.melt_radius,
                               lambda: self.actions.params.hc, self.shown_tick, self.status.melted)
        self.panel = PanelHost(window, self.actions) if PanelHost is not None \
            else NoPanel(self.status.say, PANEL_ERROR)
        self.actions.toggle_panel = self.panel.toggle
        # --weather: readings beside the loop (its own thread); T and Y then change nothing.
        self.weather = feed_for(args, self.thread.show_weather, log.info)
        self.actions.weather_sets_temperature = self.weather is not None
        self.latest: Snapshot | None = None
        self.running, self.exit_status = True, 0
        self.ended_by: signal.Signals | None = None  # the signal that ended the loop
        self.lost_window: int | None = None  # the X id of a window destroyed from outside
        self.dirty, self.snapshots, self.new_ticks = True, 0, 0  # dirty: render the phone again
        self.events.connect(self.actions.on_key, self.pointer.on_button, self.pointer.on_cursor,
                            self.drop.on_drop)
        # Kept while the window is open and until GLFW has terminated.
        self._x_handlers = (on_lost_display(self.display_lost), on_lost_window(self.window_lost))
        self.phone_ids = x_window_ids(window)  # the X ids naming it in X errors

    def _wake(self) -> None:
        """The simulation thread's wake-up (any thread): the frame loop's wait ends."""
        if not self.display_gone:
            glfw.post_empty_event()

    def redraw(self) -> None:
        self.dirty = True

    def stop(self) -> None:
        self.running = False

    def end_by(self, signum: int) -> None:
        """Ctrl-C, SIGTERM or SIGHUP: end the loop at the next frame, as Esc does (the
        session is saved), and exit as the shell reports that signal: 128 + its number.
        Once the loop has ended (Esc, a signal, an error) it changes nothing."""
        if self.running:
            self.running, self.ended_by = False, signal.Signals(signum)
            self.exit_status = 128 + signum

    def _minimized(self) -> bool:
        return self.events.minimized()

    def shown_tick(self) -> int:
        return self.latest.stats.tick if self.latest else 0

    def loop(self) -> int:
        self.thread.start()
        deadline = self.status.started + (self.max_seconds or math.inf)
        while self.running and not glfw.window_should_close(self.window):
            self._drain()
            self.capture.keep_session(self.latest, time.monotonic())
            if time.monotonic() >= deadline:
                log.info("window: --max-seconds %.1f reached", self.max_seconds)
                break
            if self._minimized():
                self.new_ticks = 0  # nothing to record while nothing is shown
            else:
                self._frame()
            glfw.wait_events_timeout(PANEL_WAIT if self.panel.needs_frame() else IDLE_WAIT)
        self.running = False
        if self.ended_by is not None:
            log.info("window: %s received: closing", self.ended_by.name)
        return self.exit_status

    def close(self) -> None:
        if self.weather is not None:
            self.weather.stop()
        self.thread.stop()
        self.clock.close()
        self._write_out()
        self.panel.close()

    def window_lost(self, resource: int) -> tuple[int, ...]:
        """A request failed on a window that is gone (destroyed from outside, e.g. by
        `xdotool windowclose`; `resource`: its X id); the X ids of that window, whose
        errors are ignored from now on. The tuning panel's: the panel closes (M opens a new
        one) and the app runs on; the phone's, or one unknown: the loop ends and closes as
        Esc does, with status 1. Called inside Xlib: no GLFW or GL call."""
        panel = self.panel.lost(resource)
        if panel:
            self.status.say(f"window: the tuning panel's window was destroyed from outside "
                            f"(X id {resource:#x}): panel closed, M opens a new one",
                            logging.WARNING)
            return panel
        which = "the phone's window" if resource in self.phone_ids else "a window"
        log.error("window: %s was destroyed from outside (X id %#x): closing", which, resource)
        self.running, self.exit_status, self.lost_window = False, 1, resource
        return self.phone_ids if resource in self.phone_ids else (resource,)

    def display_lost(self) -> None:
        """The X connection is gone (lost_display): Xlib ends the process with status 1
        when this returns, so the files are written now, with no GLFW or GL call."""
        log.error("window: the display connection is lost (X server gone or window killed)")
        self.display_gone = True  # the thread's wake-ups would meet the dead connection
        self.running, self.exit_status = False, 1
        self.thread.stop()
        self._write_out()

    def _write_out(self) -> None:
        """A running recording, the session and the summary (the thread has stopped)."""
        self.recorder.close()
        self._drain_notices()
        self.capture.save_session(self.latest)  # (a failure is said in the log)
        self.status.summary(self.latest, self.presenter.renders, self.snapshots,
                            len(self.capture.screenshots), self.exit_status)

    # ---- snapshots in, frames out ------------------------------------------------------

    def _drain(self) -> None:
        for snapshot in self.thread.drain():
            self._apply(snapshot)
        if self.clock.upload(self.presenter.renderer):
            self.dirty = True
        self._drain_notices()

    def _drain_notices(self) -> None:
        """Messages of the workers (map exports, recordings) to the HUD and the log."""
        while not self.thread.notices.empty():
            self.status.say(*self.thread.notices.get()[::-1])

    def _apply(self, snapshot: Snapshot) -> None:
        if snapshot.error:
            log.error("simulation thread died: %s", snapshot.error)
            self.running, self.exit_status = False, 1
            return
        renderer = self.presenter.renderer
        if snapshot.reset:
            renderer.reset()
            self.dirty = True
            if self.thread.script:  # a replayed parameter change
                self.actions.params = snapshot.params
            else:  # the keys' own change, or a page's (frost serve --window)
                self.actions.follow(snapshot.params, snapshot.stats.handled)
        if self.actions.follow_backdrop(snapshot.backdrop, snapshot.stats.handled):
            self.dirty = True
        if self.clock.follow(renderer, snapshot.minute, outside_line(snapshot.weather)):
            self.dirty = True
        for melt in snapshot.melts:
            renderer.apply(melt)
            self.dirty = True
        if snapshot.delta is not None:
            renderer.apply(snapshot.delta)
            self.dirty = self.dirty or _changes(snapshot.delta)
        if snapshot.message:
            self.status.say(snapshot.message)
        self.snapshots, self.new_ticks = self.snapshots + 1, self.new_ticks + 1
        self.status.shown(snapshot)
        self.latest = snapshot

    def _frame(self) -> None:
        now, drawn = time.monotonic(), self.dirty
        if drawn:
            self.presenter.render_phone()
        if self.new_ticks and self.recorder.active:  # each frame lasts until the next
            self.recorder.offer(self.presenter.read_phone, self.presenter.renders)
        self.new_ticks = 0
        if self.dirty or now >= self.status.hud_next or self.events.damaged:
            self._present(now)
        if drawn:
            self.status.drawing.drew(now)
        self.panel.frame(drawn)

    def _present(self, now: float) -> None:
        self.status.refresh(now, self._stats_lines)
        self.presenter.present(self.events.sizes.framebuffer, self.status.stats, HELP)
        glfw.swap_buffers(self.window)
        self.dirty = self.events.damaged = False
        self.status.presented(now, self._stats_lines)

    def _stats_lines(self, now: float) -> list[str]:
        return self.status.lines(now, self.latest, self.actions.params, self.presenter.renderer,
                                 self.recorder.readout(),
                                 self.presenter.render_ms,
                                 self.panel.readout(len(self.status.drawing.times)))


def first_backdrop(args, thread: SimThread, actions: Actions, store) -> None:
    """The session records the backdrop it starts on (a replay's come from its own
    events, or stay as --background imposes them). A --background file is kept as a
    photo in the session folder (`store`) first, so that the session can be replayed
    anywhere."""
    renderer = actions.presenter.renderer
    if getattr(args, "fixed_backdrop", False):
        actions.follows_backdrops = False
    if thread.script:
        return
    if renderer.backdrop not in BACKDROPS and not is_photo(renderer.backdrop):
        try:
            renderer.set_backdrop(keep(read_file(Path(renderer.backdrop)), store))
        except (PhotoError, OSError, ValueError) as err:
            log.warning("background %s shown, but not kept for the session (a replay "
                        "elsewhere will lack it): %s", renderer.backdrop, err)
    actions.backdrop_sent = thread.show_backdrop(renderer.backdrop)


def _changes(delta) -> bool:
    return delta.reset or delta.rows.stop > delta.rows.start or len(delta.features) > 0


def run(args, params: Params, attach: Callable[[FrostWindow], None] | None = None) -> int:
    """Open the phone window and run until it closes; the exit status. `attach` is handed
    the window before its loop starts (frost serve --window feeds pages from its thread)."""
    try:
        window, scale = open_window(args.scale)
    except WindowError as err:
        log.error("%s", err)
        return 1
    log.info("window: %dx%d at scale %.2f, framebuffer %dx%d",
             *glfw.get_window_size(window), scale, *glfw.get_framebuffer_size(window))
    try:
        app = FrostWindow(window, args, params)
        if attach is not None:
            attach(app)
    except Exception:
        log.exception("window failed")
        glfw.terminate()
        return 1
    with _signals_end(app):
        status = _run(app)
    if app.ended_by == signal.SIGINT:  # closed and saved; the caller says so and exits 130
        raise KeyboardInterrupt
    return status


def _run(app: FrostWindow) -> int:
    """The frame loop, then the window closed (session saved) whatever ended it."""
    try:
        return app.loop()
    except Exception as err:
        if app.lost_window is None:
            log.exception("window failed")
        else:  # the rest of the frame that met the dead window: already said, in one line
            log.info("window: the frame under way ended with the window gone (%s)", one_line(repr(err)))
        app.running, app.exit_status = False, 1
        return 1
    finally:
        app.close()
        glfw.terminate()


# Signals that end the window as Esc does, and the handler each has by default (a signal
# the parent set to be ignored, as nohup does with SIGHUP, is left alone); those this
# platform has (Windows has no SIGHUP).
ENDING_SIGNALS: dict[signal.Signals, Callable | int] = {
    sig: default for sig, default in ((getattr(signal, name, None), default) for name, default in (
        ("SIGINT", signal.default_int_handler), ("SIGTERM", signal.SIG_DFL),
        ("SIGHUP", signal.SIG_DFL))) if sig is not None}


@contextlib.contextmanager
def _signals_end(app: FrostWindow):
    """While the window runs and closes, Ctrl-C, SIGTERM and SIGHUP end the frame loop
    like Esc, so the session, a running recording and queued exports are written, instead
    of killing the process at once or raising KeyboardInterrupt wherever the main thread
    is (inside a GLFW callback ctypes would swallow it). A second one while closing
    changes nothing: the files are being written."""
    mine = [s for s, default in ENDING_SIGNALS.items() if signal.getsignal(s) is default]
    for signum in mine:
        signal.signal(signum, lambda num, _frame: app.end_by(num))
    try:
        yield
    finally:
        for signum in mine:
            signal.signal(signum, ENDING_SIGNALS[signum])
