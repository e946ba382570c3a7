"""The simulation thread's snapshots, encoded once a tick and fanned out to every page.

Runs on the asyncio loop, which the thread's wake-up schedules after each tick. A page
that connects or resyncs starts from a snapshot (`snapshots.Snapshots`, the cache of
them); over the lock screen each minute is sent as the clock box's pixels
(`lock_clock.LockClock`). Beside the desktop window the feed is one more reader of the
window's thread (`SimThread.subscribe`).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
from collections import Counter, deque
from collections.abc import Callable

from app.backdrops import LIVE
from app.serve import protocol
from app.serve.controls import Controls
from app.serve.hello import WeatherWords, hello_fields
from app.serve.hello import view as default_view
from app.serve.lock_clock import LockClock
from app.serve.pages import ConnectedPage
from app.serve.snapshots import Snapshots
from app.serve.workers import Workers
from app.simthread.backlog import SERVE_TICK_BUDGET_S
from app.simthread.thread import SimThread, Snapshot
from app.weather.feed import WeatherFeed
from sim import Params, all_presets
from sim.screen import SIZE

log = logging.getLogger("app.serve")

# Per-tick figures kept for the bench (six minutes).
SIZES_KEPT = 9000
# s the input waiting at the end may take to apply after the last step: a burst of taps
# takes milliseconds; a storm's thousands could take seconds, and the server exits soon.
APPLY_AT_END_S = 0.5
# s the simulation thread's tick under way may take to end at the end: the input can only
# apply once it has (a loaded machine's tick can take a second; the window waits 1 s).
END_TICK_S = 2.5


class Feed:
    """One simulation thread, its encoder and the pages it feeds: each tick's messages
    fanned out, the state and notices broadcast."""

    def __init__(self, params: Params, seed: int, touches=(), melt_radius: float = 24.0,
                 backdrop: str = "dusk", thread: SimThread | None = None, preset: str = "",
                 clock: Callable | None = None):
        """A feed of a new simulation thread, or of `thread` (the desktop window's, which
        starts it, reads its notices and keeps the session file, and whose clock it is);
        `preset`, the name the command line chose (of Table 1's twins b-2 and c-2, the one
        the pages say); `clock`, the lock screen's time source for a new thread (default
        local time)."""
        self.workers = Workers()
        self._pumping = threading.Event()  # a pump is scheduled
        self.own_thread = thread is None
        if thread is None:
            self.thread = SimThread(params, seed, touches, *SIZE, wake=self._woken)
            self.thread.backlog.budget_s = SERVE_TICK_BUDGET_S
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
        self.pages: set[ConnectedPage] = set()
        self.latest: Snapshot | None = None
        # Where the session stood at the latest snapshot published: (steps, events), as
        # a session file of it would count them (a redraw is tagged with its own).
        self.moment = (0, 0)
        self.error: str | None = None
        self.ending = False  # `close`d: input is no longer taken
        # The pages' input that came once ending (none taken), by what it is: the end's warning.
        self.late: Counter[str] = Counter()
        self.weather: WeatherFeed | None = None  # --weather's readings (frost serve sets it)
        # For the bench: bytes sent a tick, the thread's tick time (ms), and the time from a
        # tap reaching the server to the tick that shows it being published (ms)
        self.sizes: deque[int] = deque(maxlen=SIZES_KEPT)
        self.tick_ms: deque[float] = deque(maxlen=SIZES_KEPT)
        self.tap_ms: deque[float] = deque(maxlen=SIZES_KEPT)
        self._state: dict = {}
        self._weather = WeatherWords()
        self.lock_clock = LockClock(self.thread, self.pages, self.workers, SIZES_KEPT)
        self.snapshots = Snapshots(self.thread, self.encoder, self.pages, self.workers,
                                   self._starting)

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        self.workers.loop = loop
        if self.own_thread:
            self.thread.start()

    def tick(self) -> int:
        return self.latest.stats.tick if self.latest else 0

    @property
    def redraws(self) -> int:
        """Snapshots drawn."""
        return self.snapshots.redraws

    def ask_redraw(self) -> None:
        """A snapshot for the pages waiting (`Snapshots.ask_redraw`)."""
        self.snapshots.ask_redraw()

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

    def say_late(self) -> None:
        """The warning of the input the pages sent once the server was ending (`late`), if
        any: none of it is in the session. Said once (then counted anew)."""
        if self.late:
            log.warning("input sent once frost serve was ending, not taken (not in the "
                        "session): %s", ", ".join(f"{n} {k}" for k, n in self.late.items()))
            self.late.clear()

    def _woken(self) -> None:
        """The thread's wake-up: after every tick (on its thread) and for its notices."""
        loop = self.workers.loop
        if loop is not None and not self._pumping.is_set():
            self._pumping.set()
            with contextlib.suppress(RuntimeError):  # the loop is closed: the end
                loop.call_soon_threadsafe(self.pump)

    def pump(self) -> None:
        """Publish every snapshot the thread made since the last pump."""
        self._pumping.clear()
        for snap in self._drain():
            self._publish(snap)
        self.controls.turns.release(ticked=True)  # (the thread applied some: next turns)
        self.snapshots.pumped()
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
        self.lock_clock.tell(snap, self.controls.backdrop == LIVE)
        if snap.message:
            self.notice(snap.message)
        if messages:
            self.snapshots.keep(self.moment, messages)
            for page in self.pages:
                page.tick(messages)

    def _starting(self) -> tuple[str, bytes | None]:
        """What a page a snapshot starts gets after it: the state, the clock's minute."""
        return protocol.text("state", **self.state()), self.lock_clock.current()

    # ---- JSON ----------------------------------------------------------------------------

    def state(self) -> dict:
        snap, c = self.latest, self.controls
        return {"paused": bool(snap and snap.stats.paused), "preset": c.preset(),
                "look": c.params.look, "backdrop": c.backdrop, "backdrops": c.backdrops(),
                "weather": self._weather(snap.weather if snap else None), "tick": self.tick()}

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
        params = self.controls.params
        return protocol.text(
            "hello", **hello_fields(params, self.controls.backdrop, self.encoder.grid),
            presets=list(all_presets()), melt_radius=self.controls.melt_radius, **self.state())

    def view(self) -> dict:
        """The view a session file records (what the pages show by default)."""
        return default_view(self.controls.backdrop)

    def notice(self, text: str) -> None:
        self.broadcast(protocol.text("notice", text=text))

    def notice_soon(self, text: str) -> None:
        """`notice` from any thread (the weather feed's), on the loop once it runs."""
        loop = self.workers.loop
        if loop is not None:
            with contextlib.suppress(RuntimeError):  # (the loop is closed: the end)
                loop.call_soon_threadsafe(self.notice, text)

    def broadcast(self, message: str) -> None:
        for page in self.pages:
            if not page.waiting:
                page.text(message)
