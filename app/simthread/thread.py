"""The simulation thread: FrostSim + FrostGeometry at a fixed 25 ticks per second.

Input (touches, melts, parameter changes, clear, pause, single step) arrives on `inbox`
and applies at the next tick; the simulation's events go through `sim.io.timeline.Timeline`
(the same code headless runs and replays use), which records them with their ticks.
After each tick an immutable `Snapshot` goes on `outbox` (and to each reader that
`subscribe`d: `frost serve --window` feeds pages beside the window), the work asked with
`between_ticks` runs, and every reader's `wake` is called; the main thread applies every
snapshot's geometry deltas in order. No GL here.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime
from typing import Any

import numpy as np

from app.lockscreen import minute_name
from app.simthread.backlog import Backlog
from app.simthread.clicks import Click, Clicks
from app.simthread.commands import Command, Commands, command_kind, inputs, merged, take_all
from app.simthread.export import MapExports
from app.simthread.readers import Readers
from app.simthread.schedule import Schedule, TickTimes
from sim import Params
from sim.io.session import VERSION, SessionLog
from sim.io.timeline import Timeline, apply_due
from sim.look.geometry import GeometryDelta
from sim.screen import HEIGHT, TICKS_PER_SECOND, WIDTH
from sim.weather import Glass, Reading

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Stats:
    tick: int
    tick_ms: float  # simulation + geometry time of the last tick
    crystals: int  # alive: a melt or a thaw takes them off
    water: int
    rate: float  # achieved ticks per second over the last RATE_WINDOW ticks
    overruns: int  # scheduled ticks skipped because a tick ran late
    paused: bool
    handled: int = 0  # commands applied so far (the first `handled` that send() sent)
    tick_median_ms: float = 0.0  # tick_ms's median over the last RATE_WINDOW ticks
    waiting: int = 0  # commands received and not yet applied (a storm of input queues)


@dataclass(frozen=True)
class Snapshot:
    """What one tick hands to the main thread; nothing in it is mutated later."""

    delta: GeometryDelta | None
    stats: Stats
    params: Params
    touches: tuple[tuple[float, float], ...]
    reset: bool = False  # the renderer must clear before applying `delta`
    clicks: tuple[Click, ...] = ()  # clicks this tick's step shows
    grown: tuple[Click, ...] = ()  # clicks whose seed got its first crystal
    message: str | None = None  # for the HUD / log, e.g. a refused parameter
    error: str | None = None  # the thread died; the app must exit non-zero
    melts: tuple[GeometryDelta, ...] = ()  # melt deltas, applied before `delta`
    steps: int = 0  # steps taken by the session so far
    events: int = 0  # events recorded so far (a session file of this frame keeps these)
    minute: str | None = None  # the minute the lock screen's clock shows (None: none yet)
    backdrop: str | None = None  # the backdrop shown (None: none said yet, the default)
    # The weather outside: the last weather event's {"reading": ..., "glass": ...} (None: none).
    weather: dict[str, Any] | None = None

    def touch_ticks(self, timeline: Timeline) -> list[tuple[int, float, float]]:
        """(tick, x, y) of the touches its frame grows from: the timeline's, as long as no
        rebuild has replaced them since (then the frame's, tick unknown: -1)."""
        now = timeline.touch_ticks()[:len(self.touches)]
        if [(x, y) for _t, x, y in now] == [tuple(t) for t in self.touches]:
            return now
        return [(-1, x, y) for x, y in self.touches]


@dataclass(frozen=True)
class Step:
    """What one step of the timeline gave a tick (nothing while paused)."""

    delta: GeometryDelta | None = None
    melts: tuple[GeometryDelta, ...] = ()  # melts a rebuild scheduled for this step
    clicks: tuple[Click, ...] = ()
    grown: tuple[Click, ...] = ()


class SimThread(threading.Thread):
    """The simulation on its own thread: input in, a snapshot out at every tick of its
    `schedule` (25 a second by default), told to its `readers` (`drain`, `subscribe`,
    `between_ticks`, `wake`, `notify`: theirs); its `commands` apply the input."""

    def __init__(self, params: Params, seed: int, touches=(), width=WIDTH, height=HEIGHT,
                 wake: Callable[[], None] | None = None, dt: float = 1.0 / TICKS_PER_SECOND,
                 script=(), version: int = VERSION):
        super().__init__(name="frost-sim", daemon=True)
        self.inbox: queue.Queue[Command] = queue.Queue()
        # Who is told of a snapshot or a notice: the maker (`wake`), then the other readers.
        self.readers = r = Readers[Snapshot](wake)
        self.outbox, self.notices, self.drain, self.subscribe = r.outbox, r.notices, r.drain, r.subscribe
        self.between_ticks, self.wake, self.notify = r.between_ticks, r.wake, r.notify
        self.size = (width, height)
        self.seed = seed
        self.first_params = params
        self.script, self._script_at = list(script), 0  # a replayed session's events
        self.sent = 0  # commands sent (main thread)
        self._stop_event = threading.Event()
        self.schedule = Schedule(dt, self._stop_event.wait)
        self.times = TickTimes()
        self._clicks = Clicks()  # for the latency log
        self.exports = MapExports(self.notify)
        # (a replayed session's version: its rules, and those of what is added to it)
        self.timeline = Timeline(params, seed, width, height, version=version)
        self.backlog = Backlog(kind=command_kind)  # commands past what a tick takes wait
        self.commands = Commands(self.timeline, self._clicks, self.backlog, self.exports.ask)
        # The lock screen's clock: while something shows it (`show_clock`), each tick
        # whose minute (of `clock()`, local time) differs from the last recorded records
        # a clock event. None: no live clock (a replay's minutes are its own).
        self.clock: Callable[[], datetime] | None = datetime.now
        self._clock_shown: set[str] = set()
        events = [{"kind": "touch", "x": float(x), "y": float(y)} for x, y in touches]
        self.timeline.apply(events)

    @property
    def sim(self):
        return self.timeline.sim

    @property
    def geometry(self):
        return self.timeline.geometry

    @property
    def params(self) -> Params:
        return self.timeline.params

    @property
    def touches(self) -> tuple[tuple[float, float], ...]:
        return self.timeline.touches

    @property
    def paused(self) -> bool:
        return self.commands.paused

    @paused.setter
    def paused(self, paused: bool) -> None:
        self.commands.paused = paused

    @property
    def handled(self) -> int:
        """Commands applied (this thread): the first `handled` that `send` sent."""
        return self.commands.handled

    @property
    def backdrop(self) -> str | None:
        """The backdrop shown, as the last snapshot says it (None: the default)."""
        return self.commands.backdrop

    def session(self, steps: int | None = None, events: int | None = None) -> SessionLog:
        """The session so far (or its first `events` events and `steps` steps, as a
        snapshot reports them): enough to replay it bit for bit."""
        timeline = self.timeline
        return SessionLog(self.seed, self.first_params.as_dict(), *self.size,
                          list(timeline.events[:events]),
                          timeline.steps if steps is None else steps, version=timeline.version)

    # ---- main-thread side -------------------------------------------------------

    def touch_ticks(self, snapshot: Snapshot | None) -> list[tuple[int, float, float]]:
        """(tick, x, y) of the touches `snapshot`'s frame grows from (`Snapshot.touch_ticks`)."""
        return [] if snapshot is None else snapshot.touch_ticks(self.timeline)

    def send(self, kind: str, arg: Any = None) -> int:
        """Queue a command for the next ticks; how many commands have been sent so far (a
        snapshot whose stats.handled reaches it shows this one applied)."""
        self.sent += 1
        self.inbox.put(Command(kind, arg))
        return self.sent

    def stop(self, timeout: float = 1.0, apply_s: float = 0.0) -> None:
        """End the thread; the map exports still asked for written (from the last tick,
        when the thread has ended) and every writer waited for. With `apply_s`, the input
        still waiting is applied after the last step (`apply_waiting`) for at most that
        many seconds. Input left waiting (a storm of clicks, then Esc) is reported: it
        never applied, so neither the frame nor the session holds it."""
        self._stop_event.set()
        if self.is_alive() and threading.current_thread() is not self:
            self.join(timeout)
        waiting = [*self.backlog.take_all(), *take_all(self.inbox)]
        if apply_s > 0 and not self.is_alive():
            waiting = self.apply_waiting(waiting, apply_s)
        for level, text in self.commands.said_at_the_end(waiting):
            self.notify(level, text)
        self.exports.finish([command.arg for command in waiting if command.kind == "export"],
                            None if self.is_alive() else self.timeline, self.seed)

    def apply_waiting(self, commands: list[Command], seconds: float) -> list[Command]:
        """After the last tick (the thread ended): `commands`, the input that waited,
        applied in order with no step after them (a session's events due after its last
        step still replay) until `seconds` have passed; a snapshot of them published. What
        is left (and the map exports, written by `stop`) is returned, oldest first. So
        `frost serve` keeps in its session what a page was told the server had."""
        notes: dict[str, Any] = {"applied": []}
        left = self.commands.apply_in_time(commands, seconds, notes)
        if len(left) < len(commands):
            reset, melts, message = merged(notes["applied"])
            self.readers.publish(self._snapshot(None, reset=reset, melts=melts, message=message))
        return left

    def show_clock(self, who: str, shown: bool) -> None:
        """`who` (the window, the pages) shows the lock screen's clock or not (any thread):
        its minutes are recorded while one does."""
        if shown:
            self._clock_shown.add(who)
        else:
            self._clock_shown.discard(who)

    def show_backdrop(self, name: str) -> int:
        """The backdrop is now `name` (any thread): a backdrop event at the next tick (by a
        session version that records them) that every later snapshot says; `send`'s count."""
        return self.send("backdrop", name)

    def show_weather(self, reading: Reading, glass: Glass) -> int:
        """The weather outside is now `reading` on `glass` (any thread: a WeatherFeed's): a
        weather event at the next tick, the frost grows or thaws by it; `send`'s count."""
        return self.send("weather", (reading, glass))

    # ---- thread side ------------------------------------------------------------

    def run(self) -> None:
        try:
            self.schedule.run(self.tick)
        except Exception as err:
            log.exception("simulation thread failed")
            self.readers.publish(self._snapshot(None, error=f"{type(err).__name__}: {err}"))

    def tick(self) -> None:
        """One tick now: the input due applied, a step unless paused, the map exports
        asked for written, and its snapshot on `outbox`. The schedule calls it on this
        thread; a driver that keeps its own time (a test) may call it instead."""
        started = time.perf_counter()
        self.times.began(self.schedule.clock())
        notes: dict[str, Any] = {"applied": []}
        self._script_at = apply_due(self.timeline, self.script, self._script_at,
                                    notes["applied"].append)
        self._tell_time(notes)
        self.commands.run(take_all(self.inbox), notes)
        reset, melts, message = merged(notes["applied"])
        if reset:
            self._clicks.forget_seeds()
        # A click made while paused shows (and is timed) at the next step.
        stepping = not self.paused or notes.pop("single", False)
        step_started = self.backlog.clock()
        step = self._step() if stepping else Step()
        if stepping:  # the backlog leaves the step its room in the next ticks
            self.backlog.stepped(self.backlog.clock() - step_started)
        self.exports.write_asked(self.timeline, self.seed)  # the tick the snapshot shows
        self.times.took((time.perf_counter() - started) * 1000.0)
        self.readers.publish(self._snapshot(step.delta, reset=reset, clicks=step.clicks,
                                            grown=step.grown, message=message,
                                            melts=(*melts, *step.melts)))

    def _tell_time(self, notes: dict) -> None:
        """The clock's minute recorded, if it is shown and turned since the last."""
        clock = self.clock
        if clock is None or not self._clock_shown:
            return
        minute = minute_name(clock())
        if minute != self.timeline.minute:
            notes["applied"].append(self.timeline.apply([{"kind": "clock", "minute": minute}]))

    def _step(self) -> Step:
        """One step of the timeline: its deltas, and the clicks it shows and grew."""
        *scheduled, delta = self.timeline.step()
        # (sim.added, what the geometry reads, covers a touch once a step closes it)
        clicks, grown = self._clicks.stepped(self.sim.parents[self.sim.added.crystals])
        return Step(delta, tuple(scheduled), clicks, grown)

    def _snapshot(self, delta, **extra) -> Snapshot:
        return Snapshot(delta, self._stats(), self.params, self.touches, steps=self.timeline.steps,
                        events=len(self.timeline.events), minute=self.timeline.minute,
                        backdrop=self.backdrop, weather=self.timeline.weather, **extra)

    def _stats(self) -> Stats:
        return Stats(self.sim.tick, self.times.last_ms, int(np.count_nonzero(self.sim.crystal_alive)),
                     len(self.sim.water_area), self.times.rate(), self.schedule.overruns,
                     self.paused, self.handled, self.times.median_ms(),
                     sum(map(inputs, self.backlog)))
