"""Click latency bookkeeping on the simulation thread: which clicks a step shows, and which
seeds got their first crystal (the window logs click-to-first-frost and -growth)."""

from __future__ import annotations

import numpy as np

Click = tuple[int, float]  # (the tick it was made at, its time on the main thread's clock)


class Clicks:
    """Clicks planted and not yet shown by a step, and seeds waiting for their first child."""

    def __init__(self) -> None:
        self._planted: list[Click] = []
        self._seeds: dict[int, Click] = {}  # seed crystal index -> its click

    def planted(self, click: Click, seed: int) -> None:
        """`click` planted seed crystal `seed` in this tick."""
        self._planted.append(click)
        self._seeds[seed] = click

    def forget_seeds(self) -> None:
        """A rebuild renumbers the crystals: the seeds watched so far are gone."""
        self._seeds = {}

    def stepped(self, parents: np.ndarray) -> tuple[tuple[Click, ...], tuple[Click, ...]]:
        """After a step whose new crystals have `parents`: the clicks this step shows, and
        those whose seed crystal became a parent."""
        shown, self._planted = tuple(self._planted), []
        if not self._seeds:
            return shown, ()
        done = set(parents.tolist()).intersection(self._seeds)
        return shown, tuple(self._seeds.pop(seed) for seed in sorted(done))
