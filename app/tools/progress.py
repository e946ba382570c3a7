"""Progress of long offline runs, for a person watching the terminal (no GL)."""

from __future__ import annotations

import time

PROGRESS_EVERY_S = 2.0  # a progress line at most this often on long runs


class Progress:
    """A line on stdout every PROGRESS_EVERY_S seconds of a long run, counting against
    the whole run's ticks (all its stages together). Where the simulation's own tick
    differs from that count (a replay's rebuild starts it again at 0, figure8 grows one
    preset after another), the line says which simulation the tick belongs to."""

    def __init__(self, total: int):
        self.total, self.done = total, 0
        self.stage = ""  # what grows now, e.g. "preset b-1" (figure8); "" for one growth
        self.rebuilds = 0  # times this stage's simulation started again at tick 0
        self._sim: object | None = None
        self._last = time.perf_counter()

    def begin(self, stage: str) -> None:
        """A new stage with a simulation of its own starts (its ticks count from 0)."""
        self.stage, self.rebuilds, self._sim = stage, 0, None

    def step(self, sim) -> None:
        self.done += 1
        if self._sim is not None and sim is not self._sim:
            self.rebuilds += 1  # a rebuild (params, clear) made a new simulation
        self._sim = sim
        now = time.perf_counter()
        if now - self._last >= PROGRESS_EVERY_S:
            print(self.line(sim.tick, len(sim.crystals)), flush=True)
            self._last = now

    def line(self, tick: int, crystals: int) -> str:
        """The progress line once `done` ticks of the run are done and the simulation
        growing now is at `tick` with `crystals` crystals."""
        said = ""
        if self.stage or self.rebuilds or tick != self.done:
            at = f"{self.stage} at " if self.stage else ""
            since = f" since rebuild {self.rebuilds}" if self.rebuilds else ""
            said = f" ({at}tick {tick}{since})"
        plural = "" if crystals == 1 else "s"
        return f"tick {self.done}/{self.total}{said}, {crystals} crystal{plural} (Ctrl-C stops)"
