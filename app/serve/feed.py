"""The simulation thread's snapshots, encoded once a tick and fanned out to every page.

Runs on the asyncio loop, which the thread's wake-up schedules after each tick. A page
that connects or resyncs needs the whole frost: a snapshot. The live ice is copied on the
simulation thread between two ticks (`SimThread.between_ticks`: a millisecond, while
nothing changes it), with the height grid as the pages hold it then, and tagged with the
(steps, events) of the tick it follows; its features are drawn from the copy on a worker,
and the snapshot serves every page that asks for one while the ticks published since it
are all still kept (SINCE_TICKS, SINCE_BYTES): each page gets the snapshot, then those
ticks. Drawn on the simulation thread for every page, a client opening sockets as fast as
it could had a snapshot drawn every tick (25-60 ms each) and halved everyone's tick rate.
Beside the desktop window the feed is one more reader of the window's thread
(`SimThread.subscribe`). Over the lock screen, each minute the thread records is sent as
the clock box's new pixels only (`protocol.clock_message`, drawn and encoded on a worker),
to every live page and to each page that a snapshot starts.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from PIL import Image

from app.backdrops import LIVE, read_backdrop
from app.lockscreen import CLOCK_BOX, DEFAULT_MINUTE, clock_patch
from app.serve import protocol
from app.serve.controls import Controls
from app.serve.pages import Page
from app.simthread.thread import SimThread, Snapshot
from sim import Params, all_presets
from sim.look.geometry import IceCopy, feature_scale, live_features
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES, MAX_DEPTH, TILE, Material, default_light
from sim.params import LOOKS
from sim.screen import SIZE

log = logging.getLogger("app.serve")

# Per-tick figures kept for the bench (six minutes).
SIZES_KEPT = 9000
# A snapshot serves new pages while the ticks since it are kept: at most this many ticks
# with changes (2 s of growth) and bytes (a page that far behind would be resynced). While
# they add up to no more than the snapshot itself (or SINCE_LEAST bytes), a page never
# loads more than twice what a fresh one costs it; past that a new one is drawn for the
# next page, but not within REDRAW_GAP of the last drawing (a client opening sockets as
# fast as it could on the finest grid had one drawn every second).
SINCE_TICKS = 50
SINCE_BYTES = 6 << 20
SINCE_LEAST = 256 << 10
REDRAW_GAP = 2.0  # s
# s the input waiting at the end may take to apply after the last step: a burst of taps
# takes milliseconds; a storm's thousands could take seconds, and the server exits soon.
APPLY_AT_END_S = 0.5
# s the simulation thread's tick under way may take to end at the end: the input can only
# apply once it has (a loaded machine's tick can take a second; the window waits 1 s).
END_TICK_S = 2.5


@dataclass
class Kept:
    """A snapshot drawn, kept for the pages to come."""

    moment: tuple[int, int]  # (steps, events) of the tick it shows
    parts: list[bytes]
    since: int = 0  # bytes of the ticks published since it
    at: float = field(default_factory=time.monotonic)  # when it was drawn

    def worth(self) -> bool:
        """Whether it and the ticks since cost a page less than twice a fresh snapshot."""
        return self.since <= max(sum(map(len, self.parts)), SINCE_LEAST)


@dataclass(frozen=True)
class Copied:
    """The ice copied between two ticks, for a snapshot (`Feed`)."""

    moment: tuple[int, int]  # (steps, events) of the tick it follows
    ice: IceCopy
    heights: np.ndarray  # the height grid as the pages held it then (half floats, flat)
    params: Params


class Feed:
    """One simulation thread, its encoder and the pages it feeds."""

    def __init__(self, params: Params, seed: int, touches=(), melt_radius: float = 24.0,
                 backdrop: str = "dusk", thread: SimThread | None = None, preset: str = "",
                 clock: Callable | None = None):
        """A feed of a new simulation thread, or of `thread` (the desktop window's, which
        starts it, reads its notices and keeps the session file, and whose clock it is);
        `preset`, the name the command line chose (of Table 1's twins b-2 and c-2, the one
        the pages say); `clock`, the lock screen's time source for a new thread (default
        local time)."""
        self._loop: asyncio.AbstractEventLoop | None = None
        self._pumping = threading.Event()  # a pump is scheduled
        self.own_thread = thread is None
        if thread is None:
            self.thread = SimThread(params, seed, touches, *SIZE, wake=self._woken)
            self._drain = self.thread.drain
            if clock is not None:
                self.thread.clock = clock
        else:
            self.thread = thread
            self._drain = thread.subscribe(self._woken)
        geometry = self.thread.geometry
        self.encoder = protocol.Encoder(geometry.cols, geometry.rows)
        self.controls = Controls(self.thread, params, melt_radius, backdrop, self.notice,
                                 self.tick)
        self.controls.chosen = preset
        self.pages: set[Page] = set()
        self.latest: Snapshot | None = None
        # Where the session stood at the latest snapshot published: (steps, events), as
        # a session file of it would count them (a redraw is tagged with its own).
        self.moment = (0, 0)
        self.error: str | None = None
        self.ending = False  # `close`d: input is no longer taken
        self.redraws = 0  # snapshots drawn
        # For the bench: bytes sent a tick, the thread's tick time (ms), and the time from a
        # tap reaching the server to the tick that shows it being published (ms)
        self.sizes: deque[int] = deque(maxlen=SIZES_KEPT)
        self.tick_ms: deque[float] = deque(maxlen=SIZES_KEPT)
        self.tap_ms: deque[float] = deque(maxlen=SIZES_KEPT)
        self._state: dict = {}
        self._want_copy = threading.Event()  # a copy of the ice is asked for and not made
        self._lock = threading.Lock()
        self._copied: Copied | None = None  # made on the thread, not drawn yet
        self._drawing = False
        # The snapshot that serves new pages (`Kept`), and the messages of every tick
        # published lately (moment, messages).
        self._snapshot: Kept | None = None
        self._since: deque[tuple[tuple[int, int], list[bytes]]] = deque()
        self._since_bytes = 0
        self._dropped_to = (-1, -1)  # the moment of the newest tick dropped from `_since`
        # The lock screen's clock: the minute asked for last, and the message of the
        # latest drawn (minute, bytes); the static lock screen, read once.
        self._minute: str | None = None
        self.clock_message: tuple[str, bytes] | None = None
        self.clock_bytes: deque[int] = deque(maxlen=SIZES_KEPT)  # for the bench
        self._static: np.ndarray | None = None

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        if self.own_thread:
            self.thread.start()

    def tick(self) -> int:
        return self.latest.stats.tick if self.latest else 0

    def close(self) -> None:
        """The end (once; further calls do nothing): no input is taken from now on, and
        what the pages sent before is applied after the last step (for at most APPLY_AT_END_S,
        the rest said in the log's warning), so that the session holds whatever a page was
        told the server had (a photo answered, a touch answered by the pong after it).
        Under the window (not this feed's thread) the pages' input goes to its thread,
        whose end the window reports."""
        if self.ending:
            return
        self.ending = True
        self.controls.turns.flush()
        if self.own_thread:
            self.thread.stop(timeout=END_TICK_S, apply_s=APPLY_AT_END_S)
        self.pump()  # the last ticks, for the session's file

    # ---- the simulation thread's side ---------------------------------------------------

    def _woken(self) -> None:
        """The thread's wake-up: after every tick (on its thread) and for its notices."""
        loop = self._loop
        if loop is not None and not self._pumping.is_set():
            self._pumping.set()
            with contextlib.suppress(RuntimeError):  # the loop is closed: the end
                loop.call_soon_threadsafe(self.pump)

    def _copy_ice(self) -> None:
        """The live ice and heights copied, between two ticks (`SimThread.between_ticks`)."""
        self._want_copy.clear()
        timeline = self.thread.timeline
        try:
            copied = Copied((timeline.steps, len(timeline.events)), IceCopy.of(timeline.sim),
                            timeline.geometry.heights.ravel().astype(np.float16), timeline.params)
        except Exception:  # (the thread may have died in its tick)
            log.exception("serve: the copy of the frost failed")
            return
        with self._lock:
            self._copied = copied

    # ---- the loop's side -----------------------------------------------------------------

    def ask_redraw(self) -> None:
        """A snapshot of the whole frost for the pages waiting, at the next pump: the one
        kept, while the ticks since it are and it is worth loading (or was drawn within
        REDRAW_GAP); else the ice is copied between the next two ticks (once, however
        often it is asked meanwhile) and drawn."""
        kept = self._snapshot
        if kept is not None and (kept.worth() or time.monotonic() - kept.at < REDRAW_GAP):
            return  # (served at the next pump)
        self._snapshot = None
        if not self._want_copy.is_set() and not self._drawing:
            self._want_copy.set()
            self.thread.between_ticks(self._copy_ice)

    def pump(self) -> None:
        """Publish every snapshot the thread made since the last pump."""
        self._pumping.clear()
        for snap in self._drain():
            self._publish(snap)
        self.controls.turns.release(ticked=True)  # (the thread applied some: next turns)
        self._draw_copied()
        if self._snapshot is not None:
            self._serve_snapshot()
        if not self.own_thread:
            return  # (the window reads the thread's notices)
        while not self.thread.notices.empty():
            level, text = self.thread.notices.get()
            log.log(level, "%s", text)

    def _publish(self, snap: Snapshot) -> None:
        if snap.error:
            log.error("simulation thread died: %s", snap.error)
            self.error = snap.error
            return
        reset, messages = snap.reset, []
        for delta in (*snap.melts, *(() if snap.delta is None else (snap.delta,))):
            messages.append(self.encoder.delta(delta, reset=reset))
            reset = False
        if reset:
            messages.append(self.encoder.bare(snap.stats.tick, reset=True))
        if snap.reset and not self.own_thread:  # (the window's keys change them too)
            self.controls.params = snap.params
        if not self.own_thread:  # (and its backdrop)
            self.controls.follow_backdrop(snap.backdrop, snap.stats.handled)
        self.latest, self.moment = snap, (snap.steps, snap.events)
        self.sizes.append(sum(map(len, messages)))
        self.tick_ms.append(snap.stats.tick_ms)
        now = time.monotonic()
        self.tap_ms.extend((now - at) * 1000.0 for _tick, at in snap.clicks)
        self._send_state()
        self._tell_clock(snap)
        if snap.message:
            self.notice(snap.message)
        if messages:
            self._keep_since(messages)
            for page in self.pages:
                page.tick(messages)

    def _tell_clock(self, snap: Snapshot) -> None:
        """Over the lock screen: the thread records the minutes (`show_clock`), and a
        minute not sent yet is drawn and sent to the pages (on a worker while serving)."""
        live = self.controls.backdrop == LIVE
        self.thread.show_clock("pages", live)
        if not live:
            self._minute = None  # (sent again when the lock screen comes back)
            return
        minute = snap.minute or DEFAULT_MINUTE  # (the thread records one from its next tick)
        if minute == self._minute:
            return
        self._minute = minute
        if self._loop is None or not self._loop.is_running():
            self._clock_drawn(minute, self._draw_clock(minute))
            return
        future = self._loop.run_in_executor(None, self._draw_clock, minute)
        future.add_done_callback(
            lambda f: None if f.cancelled() else self._clock_drawn(minute, f.result()))

    def _draw_clock(self, minute: str) -> bytes | None:
        """The clock message of `minute` (any thread); None if drawing failed (logged)."""
        try:
            if self._static is None:
                self._static = np.asarray(read_backdrop(LIVE))
            out = io.BytesIO()
            Image.fromarray(clock_patch(self._static, minute)).save(out, "PNG", compress_level=6)
            return protocol.clock_message(CLOCK_BOX, minute, out.getvalue())
        except Exception:
            log.exception("serve: the lock screen's clock failed")
            return None

    def _clock_drawn(self, minute: str, message: bytes | None) -> None:
        """A minute's message drawn: to every live page, unless a newer minute was asked
        for meanwhile or the lock screen has gone."""
        if message is None or minute != self._minute:
            return
        self.clock_message = (minute, message)
        self.clock_bytes.append(len(message))
        for page in self.pages:
            if not page.waiting:
                page.binary(message)

    def _keep_since(self, messages: list[bytes]) -> None:
        """A tick's messages kept for the pages a snapshot will start (the oldest dropped
        beyond SINCE_TICKS or SINCE_BYTES, and with them the snapshot older than they)."""
        size = sum(map(len, messages))
        self._since.append((self.moment, messages))
        self._since_bytes += size
        while len(self._since) > SINCE_TICKS or self._since_bytes > SINCE_BYTES:
            self._dropped_to, old = self._since.popleft()
            self._since_bytes -= sum(map(len, old))
        kept = self._snapshot
        if kept is not None:
            kept.since += size
            if self._dropped_to > kept.moment:
                self._snapshot = None  # (a page it started would miss a tick)
                if any(page.idle_waiting() for page in self.pages):
                    # One told to wait for it at this pump (it asked while it was kept):
                    # drawn anew, or that page waits after its hello for good.
                    self.ask_redraw()

    def _draw_copied(self) -> None:
        """Draw the copy made between two ticks, if any: on a worker while serving (the
        loop and the simulation go on), here otherwise (a test's pump)."""
        with self._lock:
            copied, self._copied = self._copied, None
        if copied is None:
            return
        if self._loop is None or not self._loop.is_running():
            self._drawn(copied, self._draw(copied))
            return
        self._drawing = True
        future = self._loop.run_in_executor(None, self._draw, copied)
        future.add_done_callback(lambda f: None if f.cancelled() else self._drawn(copied, f.result()))

    def _draw(self, copied: Copied) -> list[bytes] | None:
        """The snapshot's messages, of the copied ice and heights (any thread); None if
        drawing failed (said in the log)."""
        params = copied.params
        try:
            features = live_features(copied.ice, params)
            return self.encoder.snapshot(copied.ice.tick, features, params.look,
                                         feature_scale(params), heights=copied.heights)
        except Exception:
            log.exception("serve: the snapshot of the frost failed")
            return None

    def _drawn(self, copied: Copied, parts: list[bytes] | None) -> None:
        """A snapshot drawn: it serves the pages waiting, and those to come while the ticks
        since it are kept; one whose next ticks were dropped meanwhile is copied anew."""
        self._drawing = False
        if parts is None:
            return
        self.redraws += 1
        if self._dropped_to > copied.moment:
            self.ask_redraw()
            return
        since = sum(len(m) for at, messages in self._since if at > copied.moment for m in messages)
        self._snapshot = Kept(copied.moment, parts, since)
        self._serve_snapshot()

    def _serve_snapshot(self) -> None:
        """The kept snapshot and the ticks since it, to every page waiting for one."""
        assert self._snapshot is not None
        waiting = [page for page in self.pages if page.idle_waiting()]
        if not waiting:
            return
        moment, parts = self._snapshot.moment, self._snapshot.parts
        since = [m for at, messages in self._since if at > moment for m in messages]
        state = protocol.text("state", **self.state())
        clock = self.clock_message if self._minute is not None else None
        for page in waiting:
            page.start(parts, state, since)
            if clock is not None:  # (a resync may have dropped the minute's message)
                page.binary(clock[1])

    # ---- JSON ----------------------------------------------------------------------------

    def state(self) -> dict:
        snap, c = self.latest, self.controls
        return {"paused": bool(snap and snap.stats.paused), "preset": c.preset(),
                "look": c.params.look, "backdrop": c.backdrop, "backdrops": c.backdrops(),
                "tick": self.tick()}

    def send_state(self) -> None:
        """What changed of the state, to every page now (not at the next tick)."""
        self._send_state()

    def _send_state(self) -> None:
        state = self.state()
        changed = {k: v for k, v in state.items() if self._state.get(k) != v and k != "tick"}
        self._state = state
        if changed:
            self.broadcast(protocol.text("state", **changed, tick=state["tick"]))

    def hello(self) -> str:
        m = Material()
        uniforms = {"u_ice_color": m.ice_color, "u_ambient": m.ambient, "u_diffuse": m.diffuse,
                    "u_specular": m.specular, "u_shininess": m.shininess,
                    "u_opacity": m.opacity, "u_density": m.density, "u_relief": m.relief,
                    "u_refraction": m.refraction}
        defines = {look: {"ice": list(LOOK_DEFINES[look]), "feature": list(FEATURE_DEFINES[look])}
                   for look in LOOKS}
        return protocol.text(
            "hello", protocol=protocol.VERSION, screen=list(SIZE),
            grid=list(self.encoder.grid), spacing=self.controls.params.grid_spacing,
            presets=list(all_presets()), looks=list(LOOKS),
            view=self.view(), uniforms=uniforms, defines=defines, tile=TILE, max_depth=MAX_DEPTH,
            melt_radius=self.controls.melt_radius, **self.state())

    def view(self) -> dict:
        """The view a session file records (what the pages show by default)."""
        return {"light": [float(v) for v in default_light()], "features": True, "bumps": True,
                "background": self.controls.backdrop}

    def notice(self, text: str) -> None:
        self.broadcast(protocol.text("notice", text=text))

    def broadcast(self, message: str) -> None:
        for page in self.pages:
            if not page.waiting:
                page.text(message)

