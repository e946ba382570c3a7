"""The simulation thread: FrostSim + FrostGeometry at a fixed 25 ticks per second.

Input (touches, parameter changes, clear, pause, single step) arrives on `inbox` and
applies at the next tick. After each tick an immutable `Snapshot` goes on `outbox`; the
main thread applies every snapshot's geometry delta in order. No GL here.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sim import FrostSim, Params
from sim.geometry import FrostGeometry, GeometryDelta

log = logging.getLogger(__name__)

TICKS_PER_SECOND = 25.0
# The achieved tick rate is measured over this many recent ticks (2 s).
RATE_WINDOW = 50


@dataclass(frozen=True)
class Stats:
    tick: int
    tick_ms: float  # simulation + geometry time of the last tick
    crystals: int
    water: int
    rate: float  # achieved ticks per second over the last RATE_WINDOW ticks
    overruns: int  # scheduled ticks skipped because a tick ran late
    paused: bool


@dataclass(frozen=True)
class Snapshot:
    """What one tick hands to the main thread; nothing in it is mutated later."""

    delta: GeometryDelta | None
    stats: Stats
    params: Params
    touches: tuple[tuple[float, float], ...]
    reset: bool = False  # the renderer must clear before applying `delta`
    clicks: tuple[tuple[int, float], ...] = ()  # (click tick, click time) planted this tick
    grown: tuple[tuple[int, float], ...] = ()  # clicks whose seed got its first crystal
    message: str | None = None  # for the HUD / log, e.g. a refused parameter
    error: str | None = None  # the thread died; the app must exit non-zero


@dataclass(frozen=True)
class Command:
    kind: str  # a key of SimThread._handlers
    arg: Any = None


class SimThread(threading.Thread):
    """Runs the simulation on a monotonic schedule: tick k is due at start + k * dt."""

    def __init__(self, params: Params, seed: int, touches=(), width=760, height=1280,
                 wake: Callable[[], None] | None = None, dt: float = 1.0 / TICKS_PER_SECOND):
        super().__init__(name="frost-sim", daemon=True)
        self.inbox: queue.Queue[Command] = queue.Queue()
        self.outbox: queue.Queue[Snapshot] = queue.Queue()
        self.size = (width, height)
        self.seed, self.dt, self.wake = seed, dt, wake or (lambda: None)
        self.touches: tuple[tuple[float, float], ...] = tuple(touches)
        self.paused, self.overruns, self.tick_ms = False, 0, 0.0
        self._stop_event = threading.Event()
        self._stamps: deque[float] = deque(maxlen=RATE_WINDOW)
        self._clicks: list[tuple[int, float]] = []  # planted, not yet shown by a step
        self._handlers = {"touch": self._touch, "params": self._set_params,
                          "clear": self._clear, "pause": self._pause, "step": self._single}
        self._build(params)

    # ---- main-thread side -------------------------------------------------------

    def send(self, kind: str, arg: Any = None) -> None:
        self.inbox.put(Command(kind, arg))

    def stop(self, timeout: float = 1.0) -> None:
        self._stop_event.set()
        if self.is_alive():
            self.join(timeout)

    def drain(self) -> list[Snapshot]:
        """Every snapshot produced since the last call, oldest first."""
        out = []
        while True:
            try:
                out.append(self.outbox.get_nowait())
            except queue.Empty:
                return out

    # ---- thread side ------------------------------------------------------------

    def run(self) -> None:
        try:
            self._loop()
        except Exception as err:
            log.exception("simulation thread failed")
            self.outbox.put(self._snapshot(None, error=f"{type(err).__name__}: {err}"))
            self.wake()

    def _loop(self) -> None:
        start, k = time.monotonic(), 0
        while not self._stop_event.is_set():
            k += 1
            if self._stop_event.wait(max(0.0, start + k * self.dt - time.monotonic())):
                return
            self._tick()
            late = int((time.monotonic() - start) / self.dt) - k
            if late > 0:  # skip the missed slots; never try to catch up
                self.overruns += late
                k += late

    def _tick(self) -> None:
        t0 = time.perf_counter()
        self._stamps.append(time.monotonic())
        notes = {"reset": False, "message": None}
        for cmd in self._pending():
            self._handlers[cmd.kind](cmd.arg, notes)
        delta, grown, clicks = None, (), ()
        if not self.paused or notes.pop("single", False):
            self.sim.step()
            # sim.added (what the geometry reads) covers touches only once a step closes it,
            # so a click made while paused shows (and is timed) at the next step.
            delta = self.geometry.update(self.sim)
            grown = self._first_growth()
            clicks, self._clicks = tuple(self._clicks), []
        self.tick_ms = (time.perf_counter() - t0) * 1000.0
        self.outbox.put(self._snapshot(delta, reset=notes["reset"], clicks=clicks, grown=grown,
                                       message=notes["message"]))
        self.wake()

    def _pending(self) -> list[Command]:
        cmds = []
        while True:
            try:
                cmds.append(self.inbox.get_nowait())
            except queue.Empty:
                return cmds

    def _first_growth(self) -> tuple[tuple[int, float], ...]:
        """Clicks whose seed crystal became a parent in this tick (for the latency log)."""
        if not self._watch:
            return ()
        parents = set(self.sim.parents[self.sim.added.crystals].tolist())
        done = parents.intersection(self._watch)
        return tuple(self._watch.pop(seed) for seed in sorted(done))

    def _snapshot(self, delta, **extra) -> Snapshot:
        return Snapshot(delta, self._stats(), self.params, self.touches, **extra)

    def _stats(self) -> Stats:
        s = self._stamps
        rate = (len(s) - 1) / (s[-1] - s[0]) if len(s) > 1 and s[-1] > s[0] else 0.0
        return Stats(self.sim.tick, self.tick_ms, len(self.sim.crystals),
                     len(self.sim.water_area), rate, self.overruns, self.paused)

    # ---- commands: each takes (arg, notes) and applies at this tick ---------------

    def _touch(self, arg, _notes: dict) -> None:
        (x, y), click = arg
        w, h = self.size
        if not (0 <= x < w and 0 <= y < h):
            return
        self.sim.touch(x, y)
        self.touches = (*self.touches, (x, y))
        if click is not None:
            self._clicks.append(click)
            self._watch[len(self.sim.crystals) - 1] = click

    def _set_params(self, params: Params, notes: dict) -> None:
        self._build(params)
        notes["reset"] = True
        notes["message"] = f"rebuilt with {len(self.touches)} touches replayed at tick 0"

    def _clear(self, _arg, notes: dict) -> None:
        self.touches = ()
        self._build(self.params)
        notes["reset"] = True

    def _pause(self, _arg, _notes: dict) -> None:
        self.paused = not self.paused

    def _single(self, _arg, notes: dict) -> None:
        notes["single"] = True

    def _build(self, params: Params) -> None:
        """A fresh simulation with `params`; the touches so far are replayed at tick 0."""
        self.params, self._watch = params, {}
        self.sim = FrostSim(params, *self.size, seed=self.seed)
        self.geometry = FrostGeometry(params, *self.size)
        for x, y in self.touches:
            self.sim.touch(x, y)
