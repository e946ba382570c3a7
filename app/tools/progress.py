"""Progress of long offline runs, for a person watching the terminal (no GL)."""

from __future__ import annotations

import time

PROGRESS_EVERY_S = 2.0  # a progress line at most this often on long runs


class Progress:
    """A line on stdout every PROGRESS_EVERY_S seconds of a long run, counting against
    the whole run's ticks (all its stages together)."""

    def __init__(self, total: int):
        self.total, self.done = total, 0
        self._last = time.perf_counter()

    def step(self, sim) -> None:
        self.done += 1
        now = time.perf_counter()
        if now - self._last >= PROGRESS_EVERY_S:
            print(f"tick {sim.tick} ({self.done}/{self.total}), {len(sim.crystals)} crystals "
                  "(Ctrl-C stops)", flush=True)
            self._last = now
