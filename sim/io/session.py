"""Sessions: the seed, parameters and input events of a frost run, and the one place
that applies events (used by the live simulation thread, headless runs and replays).

When an event applies: an event recorded at tick t applies when `sim.tick == t`, before
the step that produces tick t + 1 (several events of one tick apply in their order).
Kinds: "touch" (x, y), "melt" (x, y, r), "params" (params: a dict; rebuilds the
simulation) and "clear" (drops the touches and melts, rebuilds).

A rebuild (params, clear) starts a new timeline at tick 0. The touches so far are planted
again in their order and at their own pace: the first at tick 0, each pause between two
touches kept but shortened to at most REGROW_GAP ticks (so a scribble regrows stroke by
stroke as it was drawn, with the water going where it went then, and a touch made minutes
after the last is back within half a second). The melts so far are scheduled again at
their own ticks (one at tick t applies in the step that produces tick t + 1, before the
walk), so a melted spot melts again when the new frost reaches the same age. Later event
ticks count from there. Session files of version 1 replant every touch at tick 0, as
frost did when they were written, so they still replay bit for bit.
No GL here: deltas are plain arrays for app/ to upload.
"""

from __future__ import annotations

import json
import logging
import math
import statistics
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from ..core.frost import VERSION as FROST_VERSION
from ..core.frost import FrostSim
from ..look.geometry import FrostGeometry, GeometryDelta
from ..params import Params
from ..screen import HEIGHT, WIDTH, melt_problem, touch_problem
from .files import one_line, read_json, write_atomic

log = logging.getLogger(__name__)

FORMAT = "frost-session"
# 6: a tick's melts given together (a warm finger's drag) apply as one melt, each recorded
# with its "group" (`Timeline.apply`); 5: a touch into an area whose pool is short brings
# new walkers, and a ringed seed's hits count together until its first child
# (sim/core/supply.py `Supply.water_seed`, sim/rules/fern.py); 4: the
# window's water draws its later tries in one batch (sim/rules/openglass.py); 3: where an
# area's disc draws fail, walkers are placed from all areas' cells in one pass
# (sim/core/frost.py, CELL_WORK); 2: a rebuild replants the touches at their own pace (1: all
# at tick 0). Older files replay as frost did when they were written.
VERSION = FROST_VERSION
# The version from which a tick's melts given together apply as one (`Timeline.apply`).
GROUPED_MELTS = 6
# Most melts one group takes (`group_melts`): a fast drag sends about 9 a tick.
MELT_GROUP = 16
# Longest pause a rebuild keeps between two touches it replants: 12 ticks, about 0.5 s.
REGROW_GAP = 12
# The keys each event kind needs besides "tick" and "kind".
EVENT_FIELDS = {"touch": ("x", "y"), "melt": ("x", "y", "r"), "params": ("params",),
                "clear": ()}
REBUILDS = ("params", "clear")  # kinds that start a new timeline at tick 0
# Time a tick may spend in all (input applied, then its step) while input waits: a
# scribble or a storm of clicks spreads over ticks instead of stalling one. The backlog
# learns what a step and each kind of input cost here (a touch costs up to a pool of
# walkers, a melt the ice under the finger: about 0.2-2.5 ms; a tuning change regrows the
# frost) and takes input while the next one should still fit: a scribble's few events a
# tick go at once; a storm of hundreds a second queues, and the tick stays short enough
# to leave the renderer the rest of its 40 ms. It applies at least one input a tick, so
# input always moves.
TICK_BUDGET_S = 0.010  # (docs/method.md 5.2: 8-9 ms queued the warm finger in fern)
# How fast an input kind's learnt cost follows its latest (an exponential mean's weight).
COST_WEIGHT = 0.25
# Input's least share of a tick, whatever the step costs: a step over the budget (a
# frosted screen of Table 1, a loaded machine) would otherwise leave one input a tick.
MIN_INPUT_S = 0.003
# A step's cost is the median of the last few: one slow step (after a rebuild, say) does
# not starve the input of the ticks after it.
STEP_SAMPLES = 9


class SessionError(ValueError):
    """A session file that cannot be read or does not describe a session; its message is
    one line, whatever the file holds."""

    def __init__(self, message: str):
        super().__init__(one_line(message))


@dataclass
class SessionLog:
    """What reproduces a run bit for bit: seed, screen, first parameters, events, steps."""

    seed: int
    params: dict[str, Any]
    width: int = WIDTH
    height: int = HEIGHT
    events: list[dict[str, Any]] = field(default_factory=list)
    steps: int = 0  # steps the run took in all (its timelines together)
    # How the renderer showed the last frame (light, features, bumps; see check_view);
    # None in files older than it: the renderer's defaults.
    view: dict[str, Any] | None = None
    version: int = VERSION  # how its rebuilds replant (see regrow_gap)

    def as_json(self) -> dict[str, Any]:
        data = {"format": FORMAT, "version": self.version, "seed": self.seed, "width": self.width,
                "height": self.height, "params": self.params, "steps": self.steps,
                "events": self.events}
        return data if self.view is None else {**data, "view": self.view}

    def save(self, path) -> Path:
        """Write the file atomically: an old file or the whole new one, never half."""
        text = json.dumps(self.as_json(), indent=1).encode()
        return write_atomic(path, lambda f: f.write(text))

    @classmethod
    def load(cls, path) -> SessionLog:
        """The session in `path`; SessionError naming the file and the problem."""
        data = read_json(path, SessionError)
        try:
            return cls.from_json(data)
        except SessionError as err:
            raise SessionError(f"{path}: not a frost session: {err}") from None

    @classmethod
    def from_json(cls, data: Any) -> SessionLog:
        """The session `data` describes; SessionError naming the first problem found."""
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise SessionError(f"'format' must be {FORMAT!r}")
        if "params" not in data:
            raise SessionError("no 'params' entry")
        params = _params(data["params"], "'params'")
        if not isinstance(data.get("events"), list):
            raise SessionError("'events' must be a list")
        size = _whole(data, "width", 1, 16384, WIDTH), _whole(data, "height", 1, 16384, HEIGHT)
        events = [check_event(e, size) for e in data["events"]]
        _check_order(events, params)
        try:
            view = None if data.get("view") is None else check_view(data["view"])
        except ValueError as err:
            raise SessionError(str(err)) from None
        return cls(_whole(data, "seed", 0, MAX_SEED), dict(data["params"]), *size,
                   events, _whole(data, "steps", 0, MAX_TICK, 0), view,
                   _whole(data, "version", 1, VERSION, VERSION))


def regrow_gap(version: int) -> int:
    """The longest pause between replanted touches in a session file of `version`."""
    return 0 if version < 2 else REGROW_GAP


def regrow(touches: list[dict[str, Any]], gap: int) -> list[dict[str, Any]]:
    """`touches` (in tick order) as a rebuild schedules them again: the first at tick 0,
    each later one after the pause it followed, shortened to at most `gap` ticks."""
    out, at, prev = [], 0, None
    for event in touches:
        if prev is not None:
            at += min(event["tick"] - prev, gap)
        prev = event["tick"]
        out.append({**event, "tick": at})
    return out


# Coordinates and radii beyond this many px are refused before their range is checked:
# no float overflows in the checks, whatever a file holds.
MAX_COORD = 1e9
# The largest seed and tick anywhere (files, command line): numpy's seeds are any whole
# number, but a session keeps what fits 64 signed bits; 2**31 ticks is 2.7 years at 25 a
# second.
MAX_SEED = 2**63 - 1
MAX_TICK = 2**31 - 1


def _whole(data: dict, key: str, lo: int, hi: int, default: int | None = None) -> int:
    if key not in data and default is None:
        raise SessionError(f"no {key!r} entry")
    value = data.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise SessionError(f"{key!r} is {value!r}; it must be a whole number in [{lo}, {hi}]")
    return value


def _params(value: Any, where: str) -> Params:
    if not isinstance(value, dict):
        raise SessionError(f"{where} must be an object of parameter values, not {value!r}")
    unknown = sorted(set(value) - {f.name for f in fields(Params)}, key=repr)
    if unknown:
        raise SessionError(f"{where}: unknown parameter {', '.join(map(repr, unknown))}")
    try:
        return Params(**value)
    except ValueError as err:
        raise SessionError(f"{where}: {err}") from None


def _check_order(events: list[dict], first: Params) -> None:
    """Ticks never go back but after a rebuild (a new timeline at tick 0); a params event
    keeps grid_spacing (the renderer's height grid is sized once per session)."""
    for prev, event in zip(events, events[1:], strict=False):
        if event["tick"] < prev["tick"] and prev["kind"] not in REBUILDS:
            raise SessionError(f"event {event!r} comes after tick {prev['tick']}: "
                               "events must be in tick order")
    for event in (e for e in events if e["kind"] == "params"):
        spacing = event["params"].get("grid_spacing", Params.grid_spacing)
        if spacing != first.grid_spacing:
            raise SessionError(f"event {event!r}: a params event cannot change grid_spacing "
                               f"(the session's is {first.grid_spacing})")


def check_view(view: Any) -> dict[str, Any]:
    """`view` if it is a renderer view state: {"light": [x, y, z] toward the light (not
    all 0), "features": bool, "bumps": bool}; else ValueError saying what is wrong."""
    light = view.get("light") if isinstance(view, dict) else None
    if (not isinstance(light, list) or len(light) != 3
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in light)
            or not any(light) or not all(abs(v) < 1e6 for v in light)):
        raise ValueError(f"view {view!r}: 'light' must be 3 numbers, not all 0")
    if not all(isinstance(view.get(k), bool) for k in ("features", "bumps")):
        raise ValueError(f"view {view!r}: 'features' and 'bumps' must be true or false")
    checked = {"light": [float(v) for v in light], "features": view["features"],
               "bumps": view["bumps"]}
    if "background" in view:  # a backdrop's name or an image file (older files: dusk)
        background = view["background"]
        if not isinstance(background, str) or not 0 < len(background) <= 4096:
            raise ValueError(f"view {view!r}: 'background' must be a backdrop's name or a file")
        checked["background"] = background
    return checked


def check_event(event: Any, size: tuple[int, int] = (WIDTH, HEIGHT)) -> dict[str, Any]:
    """`event` if it is a well-formed event on a `size` screen (a touch or a melt's centre
    on it, a melt's radius in range: sim.screen's rules), else SessionError saying what
    is wrong."""
    if not isinstance(event, dict) or not isinstance(event.get("kind"), str) \
            or event["kind"] not in EVENT_FIELDS:
        raise SessionError(f"event {event!r}: 'kind' must be one of {', '.join(EVENT_FIELDS)}")
    missing = [k for k in ("tick", *EVENT_FIELDS[event["kind"]]) if k not in event]
    if missing:
        raise SessionError(f"event {event!r} lacks {', '.join(missing)}")
    tick = event["tick"]
    if isinstance(tick, bool) or not isinstance(tick, int) or not 0 <= tick <= MAX_TICK:
        raise SessionError(f"event {event!r}: 'tick' must be a whole number in [0, {MAX_TICK}]")
    for k in ("x", "y", "r"):
        if k in EVENT_FIELDS[event["kind"]] and not _coordinate(event[k]):
            raise SessionError(f"event {event!r}: x, y and r must be numbers "
                               f"(finite, at most {MAX_COORD:g} in size)")
    problem = None
    if event["kind"] == "touch":
        problem = touch_problem(event["x"], event["y"], size)
    elif event["kind"] == "melt":
        problem = melt_problem(event["x"], event["y"], event["r"], size)
    if problem:
        raise SessionError(f"event {event!r}: {problem}")
    if event["kind"] == "params":
        _params(event["params"], f"event at tick {tick}")
    return event


def _coordinate(v: Any) -> bool:
    # abs(v) <= MAX_COORD is False for nan and inf, and exact for ints of any size
    return not isinstance(v, bool) and isinstance(v, (int, float)) and abs(v) <= MAX_COORD


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

    def extend(self, items) -> None:
        self._items.extend(items)

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


@dataclass(frozen=True)
class Applied:
    """What applying events did: a rebuild (the renderer must clear) and melt deltas."""

    reset: bool = False
    deltas: tuple[GeometryDelta, ...] = ()
    message: str | None = None


def rebuilt_words(ticks: list[int], melts: int) -> str:
    """What a rebuild regrows: the touches (planted at `ticks`) and `melts` melts."""
    if not ticks:
        planted = "nothing to replant (no touch yet)" if not melts else "no touch"
    elif len(ticks) == 1:
        planted = f"1 touch replanted at tick {ticks[0]}"
    else:
        planted = f"{len(ticks)} touches replanted in their order by tick {max(ticks)}"
    again = {0: "", 1: " and 1 melt at its tick"}.get(melts, f" and {melts} melts at their ticks")
    return f"rebuilt: {planted}{again}" if not ticks and not melts else \
        f"rebuilt with {planted}{again}"


class Timeline:
    """A FrostSim and its FrostGeometry driven by events (see the module docstring)."""

    def __init__(self, params: Params, seed: int, width: int = WIDTH, height: int = HEIGHT,
                 touches=(), version: int = VERSION, wrap: bool = False):
        self.seed, self.size, self.version = seed, (width, height), version
        self.wrap = wrap  # a tile (frost maps --tile): every edge continues at the opposite one
        self.gap = regrow_gap(version)
        self.steps = 0
        # Every touch the frost grows from: planted, or scheduled by a rebuild.
        self.touches: tuple[tuple[float, float], ...] = tuple(touches)
        self.melts: list[dict[str, Any]] = []  # this timeline's melts, as applied
        self.events: list[dict[str, Any]] = []  # every event applied, with its tick
        # This timeline's touches as planted; "group" tells those planted together.
        self._sown: list[dict[str, Any]] = []
        self._group = 0
        # Touches and melts a rebuild scheduled, in tick order.
        self._pending: list[dict[str, Any]] = touch_events(self.touches)
        self._handlers = {"touch": self._touch, "melt": self._melt,
                          "params": self._params, "clear": self._clear}
        self._groups = 0  # melt groups applied (their ids in the recorded events)
        self._build(params)

    @property
    def tick(self) -> int:
        return self.sim.tick

    @property
    def pending(self) -> list[dict[str, Any]]:
        """The touches and melts a rebuild scheduled that have not happened yet (a copy)."""
        return list(self._pending)

    def apply(self, events) -> Applied:
        """Apply `events` (all at this tick), in order. From version 6 consecutive melts
        of one group apply as one melt (`FrostSim.melt_many`): those given together without
        a "group" (the window's warm finger: a tick's drag), or recorded with the same
        "group" (a replay); every melt is recorded with its group's id, so a replay groups
        them as they were."""
        notes: dict[str, Any] = {"reset": False, "deltas": [], "message": None}
        events, i = list(events), 0
        while i < len(events):
            j = self._group_end(events, i)
            if self.version >= GROUPED_MELTS and events[i]["kind"] == "melt":
                self._melt_group(events[i:j], notes)
            else:
                self.events.append(self._record(events[i]))
                self._handlers[events[i]["kind"]](events[i], notes)
            i = j
        return Applied(notes["reset"], tuple(notes["deltas"]), notes["message"])

    def _group_end(self, events: list, i: int) -> int:
        """The end of the run of melts of one group that starts at `i` (i + 1 if none)."""
        j = i + 1
        if self.version < GROUPED_MELTS or events[i]["kind"] != "melt":
            return j
        group = events[i].get("group")
        while j < len(events) and events[j]["kind"] == "melt" and events[j].get("group") == group:
            j += 1
        return j

    def _melt_group(self, events: list, notes: dict) -> None:
        self._groups += 1
        tick = self.sim.tick
        for event in events:
            self.events.append({**self._record(event), "group": self._groups})
            self.melts.append({"tick": tick, "kind": "melt", "x": event["x"], "y": event["y"],
                               "r": event["r"]})
        melted = self.sim.melt_many([(e["x"], e["y"], e["r"]) for e in events])
        notes["deltas"].append(self.geometry.melt(self.sim, melted))

    def _record(self, event: dict) -> dict:
        params = event.get("params")
        if isinstance(params, Params):
            event = {**event, "params": params.as_dict()}
        return {**event, "tick": self.sim.tick}

    def step(self) -> list[GeometryDelta]:
        """The melts a rebuild scheduled for this tick, then one step: their deltas and
        the step's, in the order the renderer must apply them. (Scheduled melts apply
        here, not in `apply`, so a pause or the end of a recording cannot move them.)"""
        notes: dict[str, Any] = {"deltas": []}
        self._due(notes)
        self.sim.step()
        self.steps += 1
        return [*notes["deltas"], self.geometry.update(self.sim)]

    def touch_ticks(self) -> list[tuple[int, float, float]]:
        """(tick, x, y) of every touch the frost grows from, planted or scheduled."""
        return [(e["tick"], e["x"], e["y"]) for e in self._sown + self._pending
                if e["kind"] == "touch"]

    def _due(self, notes: dict) -> None:
        while self._pending and self._pending[0]["tick"] <= self.sim.tick:
            if self._pending[0]["kind"] == "melt":
                self._melt(self._pending.pop(0), notes)
            else:
                self._sow_due()

    def _sow_due(self) -> None:
        """Plant the touches due first, together if they were planted together before
        (with gap 0, as version 1 did: every touch due)."""
        head, n = self._pending, 1
        while (n < len(head) and head[n]["kind"] == "touch" and head[n]["tick"] == head[0]["tick"]
               and (self.gap == 0 or head[n].get("group") == head[0].get("group"))):
            n += 1
        self._sow(head[:n])
        del head[:n]

    def _sow(self, touches: list[dict[str, Any]]) -> None:
        """Plant `touches` now, together (one top-up per area they touch)."""
        self.sim.plant([(e["x"], e["y"]) for e in touches])
        self._group += 1
        self._sown += [{**e, "tick": self.sim.tick, "group": self._group} for e in touches]

    # ---- event handlers: (event, notes) ------------------------------------------------

    def _touch(self, event: dict, _notes: dict) -> None:
        x, y = float(event["x"]), float(event["y"])
        if touch_problem(x, y, self.size) is None:  # a touch off the screen is ignored
            self._sow([{"tick": self.sim.tick, "kind": "touch", "x": x, "y": y}])
            self.touches = (*self.touches, (x, y))

    def _melt(self, event: dict, notes: dict) -> None:
        melted = self.sim.melt(float(event["x"]), float(event["y"]), float(event["r"]))
        self.melts.append({"tick": self.sim.tick, "kind": "melt", "x": event["x"],
                           "y": event["y"], "r": event["r"]})
        notes["deltas"].append(self.geometry.melt(self.sim, melted))

    def _params(self, event: dict, notes: dict) -> None:
        params = event["params"]
        params = params if isinstance(params, Params) else Params(**params)
        old: Params = self.params
        if params.look != old.look and params.replace(look=old.look) == old:
            self._relook(params, notes)  # the look alone changed: the same frost, redrawn
            return
        self._rebuild(params, notes)
        ticks = [t for t, _x, _y in self.touch_ticks()]
        notes["message"] = rebuilt_words(ticks, sum(e["kind"] == "melt" for e in self._pending))

    def _relook(self, params: Params, notes: dict) -> None:
        self.params, self.geometry = params, FrostGeometry(params, *self.size, wrap=self.wrap)
        notes["reset"] = True
        notes["deltas"][:] = [self.geometry.redraw(self.sim)]

    def _clear(self, _event: dict, notes: dict) -> None:
        self.touches, self.melts, self._pending, self._sown = (), [], [], []
        self._rebuild(self.params, notes)

    def _rebuild(self, params: Params, notes: dict) -> None:
        # What an earlier rebuild scheduled and has not happened yet comes again too.
        touches = self._sown + [e for e in self._pending if e["kind"] == "touch"]
        melts = self.melts + [e for e in self._pending if e["kind"] == "melt"]
        touches = regrow(sorted(touches, key=lambda e: e["tick"]), self.gap)
        self.touches = tuple((e["x"], e["y"]) for e in touches)
        # (stable: a tick's touches before its melts, as they applied)
        self._pending = sorted(touches + melts, key=lambda e: e["tick"])
        self.melts, self._sown = [], []
        self._build(params)
        notes["reset"] = True
        notes["deltas"].clear()  # older melt deltas belong to the old frost

    def _build(self, params: Params) -> None:
        self.params = params
        self.sim = FrostSim(params, *self.size, seed=self.seed, version=self.version,
                            wrap=self.wrap)
        self.geometry = FrostGeometry(params, *self.size, wrap=self.wrap)
        while self._pending and self._pending[0]["tick"] == 0 \
                and self._pending[0]["kind"] == "touch":  # (melts wait for the step)
            self._sow_due()


def group_melts(items: list, disc: Callable[[Any], Any], group: Callable[[list], Any]) -> list:
    """`items` (input in arrival order) with each run of consecutive melts that overlap
    the one before (a drag's: `disc(item)` gives a melt's (x, y, r), None for other
    input) replaced by `group(run)`, at most MELT_GROUP to a group: a fast drag's melts
    then apply as one (`Timeline.apply`). Melts apart (a storm of clicks all over) stay
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


def touch_events(points, tick: int = 0) -> list[dict[str, Any]]:
    """Touch events at `tick` for (x, y) points."""
    return [{"tick": tick, "kind": "touch", "x": float(x), "y": float(y)} for x, y in points]


def grow(timeline: Timeline, steps: int, events=(), on_apply=None, on_step=None,
         on_tick=None) -> int:
    """Step `timeline` `steps` times, applying each of `events` (in order, each at its
    tick as the timeline counts it) when due; events due after the last step apply too.
    `on_apply(Applied)` and `on_step(GeometryDelta)` see every result in order, `on_tick(sim)`
    every step once it is done. Every run of frost that is not the live window goes
    through here; returns how many of `events` applied."""
    events = list(events)
    on_apply, on_step = on_apply or (lambda _a: None), on_step or (lambda _d: None)
    i = apply_due(timeline, events, 0, on_apply)
    for _ in range(steps):
        for delta in timeline.step():
            on_step(delta)
        if on_tick:
            on_tick(timeline.sim)
        i = apply_due(timeline, events, i, on_apply)
    return i


def replay(log_: SessionLog, steps: int | None = None, on_apply=None, on_step=None,
           on_tick=None) -> Timeline:
    """Run `log_` for `steps` steps (default: as many as it took) through `grow`."""
    steps = log_.steps if steps is None else steps
    timeline = Timeline(Params(**log_.params), log_.seed, log_.width, log_.height,
                        version=log_.version)
    applied = grow(timeline, steps, log_.events, on_apply, on_step, on_tick)
    if applied < len(log_.events):
        log.warning("replay: %d events after step %d were not applied",
                    len(log_.events) - applied, steps)
    return timeline


def apply_due(timeline: Timeline, events: list, i: int, on_apply) -> int:
    """Apply `events[i:]` that are due at the timeline's tick; the index of the first left.
    A batch ends at a rebuild: the events after it count from the new tick 0."""
    while i < len(events) and events[i]["tick"] == timeline.tick:
        j = i + 1
        while (j < len(events) and events[j]["tick"] == timeline.tick
               and events[j - 1]["kind"] not in REBUILDS):
            j += 1
        on_apply(timeline.apply(events[i:j]))
        i = j
    return i
