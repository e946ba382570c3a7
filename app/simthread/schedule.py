"""When the simulation thread ticks: a fixed rate on a monotonic clock, late ticks
skipping the slots they missed, and the achieved rate and tick times it reports."""

from __future__ import annotations

import statistics
import time
from collections import deque
from collections.abc import Callable

# The achieved tick rate is measured over this many recent ticks (2 s).
RATE_WINDOW = 50


class Schedule:
    """Tick k is due at start + k * dt on `clock`; `wait(seconds)` sleeps and answers
    whether to stop. A tick that ends late skips the missed slots (counted as overruns)
    and never tries to catch up."""

    def __init__(self, dt: float, wait: Callable[[float], bool],
                 clock: Callable[[], float] = time.monotonic):
        self.dt, self.wait, self.clock = dt, wait, clock
        self.overruns = 0

    def run(self, tick: Callable[[], None]) -> None:
        """Call `tick()` at each slot until `wait` says stop."""
        start, k = self.clock(), 0
        while True:
            k += 1
            if self.wait(max(0.0, start + k * self.dt - self.clock())):
                return
            tick()
            late = int((self.clock() - start) / self.dt) - k
            if late > 0:
                self.overruns += late
                k += late


class TickTimes:
    """The recent ticks: when each began (the schedule's clock) and how long it took."""

    def __init__(self) -> None:
        self.starts: deque[float] = deque(maxlen=RATE_WINDOW)
        self.durations_ms: deque[float] = deque(maxlen=RATE_WINDOW)
        self.last_ms = 0.0  # simulation + geometry time of the last tick

    def began(self, now: float) -> None:
        self.starts.append(now)

    def took(self, ms: float) -> None:
        self.last_ms = ms
        self.durations_ms.append(ms)

    def rate(self) -> float:
        """Ticks per second over the last RATE_WINDOW ticks (0 before two)."""
        starts = self.starts
        if len(starts) < 2 or starts[-1] <= starts[0]:
            return 0.0
        return (len(starts) - 1) / (starts[-1] - starts[0])

    def median_ms(self) -> float:
        return statistics.median(self.durations_ms) if self.durations_ms else 0.0
