"""Input waiting for the simulation thread's ticks: how much applies in a tick (`Backlog`,
timed on the thread's own CPU clock) and which melts apply together (`group_melts`).

What applies when is recorded with its tick as it applies (sim.io.timeline), so these
choices shape a live run but never a replay.
"""

from __future__ import annotations

import math
import statistics
import time
from collections import deque
from collections.abc import Callable
from typing import Any

# Time a tick may spend in all (input applied, then its step) while input waits: a
# scribble or a storm of clicks spreads over ticks instead of stalling one. The backlog
# learns what a step and each kind of input cost here (a touch costs up to a pool of
# walkers, a melt the ice under the finger: about 0.2-2.5 ms; a tuning change regrows the
# frost) and takes input while the next one should still fit: a scribble's few events a
# tick go at once; a storm of hundreds a second queues, and the tick stays short enough
# to leave the renderer the rest of its 40 ms. It applies at least one input a tick, so
# input always moves.
TICK_BUDGET_S = 0.010  # (docs/method.md 5.2: 8-9 ms queued the warm finger in fern)
# `frost serve`'s own thread: sixteen pages tapping at 12 a second each kept a 10 ms budget's
# tick median at 9.5 ms, and the fan-out to the pages shares the process with it; 7 ms keeps
# it under 8 (docs/method.md 5.2). The window, one person's input, keeps TICK_BUDGET_S.
SERVE_TICK_BUDGET_S = 0.007
# How fast an input kind's learnt cost follows its latest (an exponential mean's weight).
COST_WEIGHT = 0.25
# Input's least share of a tick, whatever the step costs: a step over the budget (a
# frosted screen of Table 1, a loaded machine) would otherwise leave one input a tick.
MIN_INPUT_S = 0.003
# A step's cost is the median of the last few: one slow step (after a rebuild, say) does
# not starve the input of the ticks after it.
STEP_SAMPLES = 9
# Most melts one group takes (`group_melts`): a fast drag sends about 9 a tick.
MELT_GROUP = 16


class Backlog:
    """Input waiting to apply, oldest first. `run` applies at least one item, then more
    while the tick's time so far, plus what the next item's kind and the step have lately
    cost, stays under `budget_s`; the rest wait for the next tick. `kind(item)` names an item's
    kind; tell the backlog each step's cost with `stepped`. (The ticks input lands on are
    recorded as it applies, so replays stay exact whatever the clock says.) The clock is
    the calling thread's CPU time: the work a tick does, not the time it waited for the
    other threads (the window's renderer holds the interpreter's lock while llvmpipe
    draws; counted in wall time, a loaded machine's steps left no room for input, and a
    tuning key waited behind hundreds of melts)."""

    def __init__(self, budget_s: float = TICK_BUDGET_S, clock=time.thread_time,
                 kind=lambda item: None):
        self.budget_s, self.clock, self.kind = budget_s, clock, kind
        self._items: deque = deque()
        self.item_s: dict[Any, float] = {}  # what an item of each kind lately cost, s
        self._steps: deque = deque(maxlen=STEP_SAMPLES)

    @property
    def step_s(self) -> float:
        """What a step lately cost, s: the median of the last STEP_SAMPLES."""
        return statistics.median(self._steps) if self._steps else 0.0

    def extend(self, items, replaces: Callable[[Any, Any], bool] | None = None) -> int:
        """Queue `items`, oldest first. An item that `replaces(last waiting, item)` takes
        the place of the last item waiting (one the item would undo at once: a tuning change
        right behind another, each a regrowth of the frost). How many items were replaced."""
        replaced = 0
        for item in items:
            if replaces is not None and self._items and replaces(self._items[-1], item):
                self._items[-1] = item
                replaced += 1
            else:
                self._items.append(item)
        return replaced

    def run(self, apply) -> int:
        """`apply(item)` for this tick's share of the items; how many went."""
        start = now = self.clock()
        done = 0
        room = max(self.budget_s - self.step_s, min(MIN_INPUT_S, self.budget_s))
        while self._items:
            kind = self.kind(self._items[0])
            if done and now - start + self.item_s.get(kind, 0.0) >= room:
                break
            apply(self._items.popleft())
            done, was, now = done + 1, now, self.clock()
            cost = now - was
            mean = self.item_s.get(kind)
            self.item_s[kind] = cost if mean is None else mean + COST_WEIGHT * (cost - mean)
        return done

    def stepped(self, seconds: float) -> None:
        """The step after `run` took `seconds`: the room the next ticks leave for it."""
        self._steps.append(seconds)

    def take_all(self) -> list:
        """Every item still waiting, oldest first; the backlog is left empty."""
        items, self._items = list(self._items), deque()
        return items

    def __len__(self) -> int:
        return len(self._items)

    def __iter__(self):
        """The items waiting, oldest first."""
        return iter(self._items)


def group_melts(items: list, disc: Callable[[Any], Any], group: Callable[[list], Any]) -> list:
    """`items` (input in arrival order) with each run of consecutive melts that overlap
    the one before (a drag's: `disc(item)` gives a melt's (x, y, r), None for other
    input) replaced by `group(run)`, at most MELT_GROUP to a group: a fast drag's melts
    then apply as one (`sim.io.timeline.Timeline.apply`). Melts apart (a storm of clicks all over) stay
    single: one melt over discs all over the screen would redraw the whole screen's ice."""
    out: list = []
    run: list = []
    for item in items:
        d = disc(item)
        if run and not (d is not None and len(run) < MELT_GROUP and _overlap(disc(run[-1]), d)):
            out.append(group(run) if len(run) > 1 else run[0])
            run = []
        if d is None:
            out.append(item)
        else:
            run.append(item)
    if run:
        out.append(group(run) if len(run) > 1 else run[0])
    return out


def _overlap(a, b) -> bool:
    return math.hypot(a[0] - b[0], a[1] - b[1]) <= a[2] + b[2]
