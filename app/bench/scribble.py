"""Scripted scribbles: what a person does to a touch demo, as events tick by tick.

A schedule is a list with one entry per tick: the events the window's simulation thread
would receive in that tick. `play` drives a Timeline through a Backlog exactly as that
thread does (input applies within a time budget a tick, the rest waits), so the benchmark and
the tests measure what a user meets. No GL, no window.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from app.simthread.backlog import Backlog, group_melts
from sim import tuning
from sim.io.gestures import DRAG_SPACING_HC, MELT_SPACING, path_points
from sim.io.timeline import Timeline
from sim.params import PRESETS, Params
from sim.screen import MELT_RADIUS, SIZE, TICKS_PER_SECOND
from sim.tuning import BUMP_STEP, HUMIDITY_FACTOR, LENGTH_STEP

FINGER_SPEED = 800.0  # px per second: a brisk drag across a phone
STROKE_GAP = 5  # ticks between the strokes of a scribble (the finger lifts)


@dataclass(frozen=True)
class Played:
    """What a played schedule cost: each tick's seconds (events applied + step)."""

    tick_s: np.ndarray
    touches: int
    walkers_max: int
    crystals: int
    backlog_max: int
    # Ticks from each touch on glass to its seed's first child (a seed melted first is
    # left out; one never grown, or replanted by a rebuild first, counts the ticks it
    # waited: a lower bound). A touch on glass lands at least hc from every crystal.
    first_growth: np.ndarray
    # The same for touches on ice (within hc of a crystal: in its freezing area), which
    # have little or no glass to grow into.
    first_growth_on_ice: np.ndarray
    # Ticks after the schedule's last until no input waited (0: none waited at its end;
    # input still waiting when play stopped: a lower bound).
    drained: int = 0


def stroke(start, end, spacing: float, kind: str, radius: float = MELT_RADIUS) -> list[list[dict]]:
    """One drag from `start` to `end` at FINGER_SPEED: per tick, the touches (kind
    "touch") or melts (kind "melt") the window sends as the cursor passes."""
    length = math.dist(start, end)
    ticks = max(1, math.ceil(length / FINGER_SPEED * TICKS_PER_SECOND))
    out, at = [], start
    first = [_event(kind, start, radius)]
    for k in range(1, ticks + 1):
        cursor = (start[0] + (end[0] - start[0]) * k / ticks,
                  start[1] + (end[1] - start[1]) * k / ticks)
        points = path_points(at, cursor, spacing)
        if points:
            at = points[-1]
        out.append(first + [_event(kind, p, radius) for p in points])
        first = []
    return out


def _event(kind: str, point, radius: float) -> dict:
    x, y = (float(v) for v in point)
    return {"kind": "touch", "x": x, "y": y} if kind == "touch" else \
        {"kind": "melt", "x": x, "y": y, "r": radius}


def scribble(params: Params, seed: int = 0, seconds: float = 60.0, size=SIZE) -> list[list[dict]]:
    """Left-button strokes between random points over the whole screen, then half as long
    of right-button (warm finger) strokes, then every tuning change once (5 ticks apart),
    `seconds` in all."""
    rng = np.random.default_rng(seed)
    changes = tuning_changes(params)
    drawing = max(0, int(seconds * TICKS_PER_SECOND) - 5 * len(changes))
    phases = (("touch", DRAG_SPACING_HC * params.hc, 2 * drawing // 3),
              ("melt", MELT_SPACING * MELT_RADIUS, drawing))
    schedule: list[list[dict]] = []
    for kind, spacing, until in phases:
        while len(schedule) < until:
            a, b = (tuple(rng.uniform((0, 0), size)) for _ in range(2))
            schedule += stroke(a, b, spacing, kind) + [[] for _ in range(STROKE_GAP)]
        del schedule[until:]
    for p in changes:  # a key press every 5 ticks
        schedule += [[{"kind": "params", "params": p}]] + [[] for _ in range(4)]
    return schedule


def tuning_changes(params: Params) -> list[Params]:
    """Each change the window's tuning keys make (sim/tuning.py, as the keys do), applied
    one after another: every length and humidity step up and down, growth mode on and off,
    every Table 1 preset."""
    def shift(name: str, by: float) -> Callable[[Params], Params]:
        return lambda p: tuning.shifted(p, name, by)
    changes: list[Callable[[Params], Params]] = [
        lambda p: tuning.scaled(p, "humidity", HUMIDITY_FACTOR),
        lambda p: tuning.scaled(p, "humidity", 1 / HUMIDITY_FACTOR),
        *(shift(name, sign * LENGTH_STEP) for name in ("hc", "D", "step") for sign in (1, -1)),
        shift("bump", BUMP_STEP), shift("bump", -BUMP_STEP),
        lambda p: tuning.toggled(p, "grow"), lambda p: tuning.toggled(p, "grow"),
        *((lambda p, name=name: tuning.preset(p, name)) for name in PRESETS)]
    out, p = [], params
    for change in changes:
        p = change(p)
        out.append(p)
    return out


def storm(seed: int = 0, events: int = 2000, seconds: float = 10.0, size=SIZE,
          radius: float = MELT_RADIUS) -> list[list[dict]]:
    """`events` touches and melts (half each, in random order) at random spots, sent as
    fast as they come: evenly over `seconds`."""
    rng = np.random.default_rng(seed)
    ticks = int(seconds * TICKS_PER_SECOND)
    xy = rng.uniform((0, 0), size, (events, 2))
    kinds = rng.permutation(np.arange(events) % 2)
    per_tick = np.array_split(np.arange(events), ticks)
    return [[_event("melt" if kinds[i] else "touch", xy[i], radius) for i in part]
            for part in per_tick]


def spread(seed: int = 0, ticks: int = 1200, size=SIZE) -> list[list[dict]]:
    """One touch a tick at a random spot for `ticks` ticks: clicks all over the screen."""
    xy = np.random.default_rng(seed).uniform((0, 0), size, (ticks, 2))
    return [[_event("touch", p, 0.0)] for p in xy]


# The most quiet ticks `play` adds to let queued input apply (about 7 minutes).
DRAIN_LIMIT = 10_000


def play(params: Params, schedule: list[list[dict]], seed: int = 0, tail: int = 0,
         size=SIZE, drain: bool = False) -> Played:
    """Run `schedule` (and `tail` quiet ticks after it; with `drain`, more until no input
    waits) through a Timeline, timing each tick's applied events and step together, as
    the simulation thread's tick_ms does; the Backlog learns the step's cost as there."""
    timeline, backlog, seeds = Timeline(params, seed, *size), Backlog(kind=_kind), _Seeds()
    times, walkers, waiting, last_waiting = [], 0, 0, -1
    clock = time.perf_counter
    ticks = iter([*schedule, *([[]] * tail)])
    k = 0
    while True:
        events = next(ticks, None)
        if events is None:
            if not (drain and len(backlog) and k < len(schedule) + tail + DRAIN_LIMIT):
                break
            events = []
        backlog.extend(group_melts(events, _disc, _melts))  # as the window's thread
        t0 = clock()
        backlog.run(lambda event: seeds.apply(timeline, event))
        s1 = backlog.clock()  # (its own clock: a test may give it a still one)
        timeline.step()
        backlog.stepped(backlog.clock() - s1)
        times.append(clock() - t0)
        seeds.stepped(timeline.sim)
        walkers = max(walkers, len(timeline.sim.water_area))
        waiting = max(waiting, len(backlog))
        if len(backlog):
            last_waiting = k
        k += 1
    return Played(np.array(times), len(timeline.touches), walkers, len(timeline.sim.crystals),
                  waiting, *seeds.waits(timeline.sim.tick),
                  drained=max(0, last_waiting + 2 - len(schedule)))


def _kind(event: dict) -> str:
    return event["kind"]


def _disc(event: dict):
    return (event["x"], event["y"], event["r"]) if event["kind"] == "melt" else None


def _melts(events: list[dict]) -> dict:
    return {"kind": "melts", "events": events}


class _Seeds:
    """Each touch's seed until its first child: how long a touch waits to grow."""

    def __init__(self) -> None:
        self.planted: dict[int, tuple[int, bool]] = {}  # seed -> (tick planted, on ice)
        self.waited: list[tuple[int, bool]] = []

    def apply(self, timeline: Timeline, event: dict) -> None:
        if event["kind"] == "melts":  # a run of melts, applied as one
            timeline.apply(event["events"])
            return
        sim, n = timeline.sim, len(timeline.sim.crystals)
        on_ice = event["kind"] == "touch" and _on_ice(sim, event["x"], event["y"])
        timeline.apply([event])
        if timeline.sim is not sim:  # a rebuild replants every touch: stop watching
            self.waited += [(sim.tick - t, ice) for t, ice in self.planted.values()]
            self.planted = {}
        elif event["kind"] == "touch" and len(sim.crystals) > n:
            self.planted[n] = (sim.tick, on_ice)

    def stepped(self, sim) -> None:
        if self.planted:
            alive = sim.crystal_alive
            for s in set(sim.parents[sim.added.crystals].tolist()).intersection(self.planted):
                t, ice = self.planted.pop(s)
                self.waited.append((sim.tick - t, ice))
            for s in [s for s in self.planted if not alive[s]]:
                del self.planted[s]  # melted before it grew

    def waits(self, tick: int) -> tuple[np.ndarray, np.ndarray]:
        """Ticks waited by the touches on glass, and by those on ice."""
        waits = self.waited + [(tick - t, ice) for t, ice in self.planted.values()]
        glass = np.array([w for w, ice in waits if not ice], np.int64)
        return glass, np.array([w for w, ice in waits if ice], np.int64)


def _on_ice(sim, x: float, y: float) -> bool:
    """Within hc of a live crystal: in a crystal's freezing area (the cells' lists hold
    every crystal that near, so this costs the ice around the touch)."""
    return len(sim.index.crystals_near(x, y, sim.params.hc)) > 0
