"""The one place that applies a session's events to a frost: `Timeline` (a FrostSim and its
FrostGeometry driven by events), and `grow` / `replay`, which every run but the live window
goes through. Events and their kinds are those of a session file (sim.io.session).

When an event applies: an event recorded at tick t applies when `sim.tick == t`, before
the step that produces tick t + 1 (several events of one tick apply in their order).

A rebuild (params, clear) starts a new timeline at tick 0. The touches so far are planted
again in their order and at their own pace: the first at tick 0, each pause between two
touches kept but shortened to at most REGROW_GAP ticks (sim/core/versions.py) (so a scribble regrows stroke by
stroke as it was drawn, with the water going where it went then, and a touch made minutes
after the last is back within half a second). The melts so far are scheduled again at
their own ticks (one at tick t applies in the step that produces tick t + 1, before the
walk), so a melted spot melts again when the new frost reaches the same age. Later event
ticks count from there. Session files of version 1 replant every touch at tick 0, as
frost did when they were written, so they still replay bit for bit.
No GL here: deltas are plain arrays for app/ to upload.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

from ..core.frost import FrostSim
from ..core.versions import Rules, rules_of
from ..look.geometry import FrostGeometry, GeometryDelta
from ..params import Params
from ..screen import HEIGHT, WIDTH, touch_problem
from ..weather import THAW_TICKS, Glass, Reading, frost_of
from .session import REBUILDS, VERSION, SessionLog

log = logging.getLogger(__name__)

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


@dataclass(frozen=True)
class Applied:
    """What applying events did: a rebuild (the renderer must clear) and melt deltas."""

    reset: bool = False
    deltas: tuple[GeometryDelta, ...] = ()
    message: str | None = None
    minute: str | None = None  # a clock event's minute: the lock screen shows it from now
    backdrop: str | None = None  # a backdrop event's name: shown from now
    weather: dict[str, Any] | None = None  # a weather event (its reading, its glass): from now


def rebuilt_words(ticks: list[int], melts: int) -> str:
    """What a rebuild regrows: the touches (planted at `ticks`) and `melts` melts."""
    if not ticks:
        planted = "nothing to replant (no touch yet)" if not melts else "no touch"
    elif len(ticks) == 1:
        planted = f"1 touch replanted at tick {ticks[0]}"
    else:
        planted = f"{len(ticks)} touches replanted in their order by tick {max(ticks)}"
    again = {0: "", 1: " and 1 melt at its tick"}.get(melts, f" and {melts} melts at their ticks")
    joined = ": " if not ticks and not melts else " with "
    return f"rebuilt{joined}{planted}{again}"


class Surroundings:
    """A Timeline's events of the world around the frost, each kept across a rebuild: the
    clock's minute, the backdrop behind the glass and the weather outside (which sets how
    the frost grows or thaws)."""

    rules: Rules
    version: int
    sim: FrostSim
    minute: str | None
    backdrop: str | None
    weather: dict[str, Any] | None

    def _clock(self, event: dict, notes: dict) -> None:
        """The lock screen's clock shows `minute` from this tick on (the frost is untouched;
        a rebuild keeps it: the clock is the screen's, not the frost's)."""
        if not self.rules.clock_events:
            raise ValueError(f"a clock event needs session version 10 or later, not {self.version}")
        self.minute = notes["minute"] = event["minute"]

    def _backdrop(self, event: dict, notes: dict) -> None:
        """The backdrop `name` is shown from this tick on (the frost is untouched; a
        rebuild keeps it)."""
        if not self.rules.backdrop_events:
            raise ValueError(f"a backdrop event needs session version 11 or later, not {self.version}")
        self.backdrop = notes["backdrop"] = event["name"]

    def _weather(self, event: dict, notes: dict) -> None:
        """The weather outside from this tick on (sim/weather): the frost grows as its glass
        makes it, or thaws; a rebuild keeps it (the weather is the night's, not the frost's)."""
        if not self.rules.weather_events:
            raise ValueError(f"a weather event needs session version 12 or later, not {self.version}")
        self.weather = notes["weather"] = {"reading": event["reading"], "glass": event["glass"]}
        self._set_weather()

    def _set_weather(self) -> None:
        if self.weather is not None:
            reading = Reading.from_json(self.weather["reading"])
            frost = frost_of(reading.temperature_c, Glass.from_json(self.weather["glass"]))
            self.sim.set_weather(frost.temperature, frost.supply)


class Timeline(Surroundings):
    """A FrostSim and its FrostGeometry driven by events (see the module docstring)."""

    def __init__(self, params: Params, seed: int, width: int = WIDTH, height: int = HEIGHT,
                 touches=(), version: int = VERSION, wrap: bool = False):
        self.seed, self.size, self.version = seed, (width, height), version
        self.wrap = wrap  # a tile (frost maps --tile): every edge continues at the opposite one
        self.rules = rules_of(version)
        self.gap = self.rules.regrow_gap
        self.steps = 0
        # Every touch the frost grows from: planted, or scheduled by a rebuild.
        self.touches: tuple[tuple[float, float], ...] = tuple(touches)
        self.melts: list[dict[str, Any]] = []  # this timeline's melts, as applied
        self.events: list[dict[str, Any]] = []  # every event applied, with its tick
        # This timeline's touches as planted; "group" tells those planted together.
        self._planted: list[dict[str, Any]] = []
        self._group = 0
        # Touches and melts a rebuild scheduled, in tick order.
        self._pending: list[dict[str, Any]] = touch_events(self.touches)
        self._handlers = {"touch": self._touch, "melt": self._melt,
                          "params": self._params, "clear": self._clear, "clock": self._clock,
                          "backdrop": self._backdrop, "weather": self._weather}
        # The minute the lock screen shows (the last clock event's; None before any).
        self.minute: str | None = None
        # The backdrop shown (the last backdrop event's; None before any).
        self.backdrop: str | None = None
        # The weather outside (the last weather event; None before any: the preset's own).
        self.weather: dict[str, Any] | None = None
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
        notes: dict[str, Any] = {"reset": False, "deltas": [], "message": None, "minute": None,
                                 "backdrop": None, "weather": None}
        events, i = list(events), 0
        while i < len(events):
            j = self._group_end(events, i)
            if self.rules.grouped_melts and events[i]["kind"] == "melt":
                self._melt_group(events[i:j], notes)
            else:
                self.events.append(self._record(events[i]))
                self._handlers[events[i]["kind"]](events[i], notes)
            i = j
        return Applied(notes["reset"], tuple(notes["deltas"]), notes["message"], notes["minute"],
                       notes["backdrop"], notes["weather"])

    def _group_end(self, events: list, i: int) -> int:
        """The end of the run of melts of one group that starts at `i` (i + 1 if none)."""
        j = i + 1
        if not self.rules.grouped_melts or events[i]["kind"] != "melt":
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
        self._thaw(notes)
        self.sim.step()
        self.steps += 1
        return [*notes["deltas"], self.geometry.update(self.sim)]

    def touch_ticks(self) -> list[tuple[int, float, float]]:
        """(tick, x, y) of every touch the frost grows from, planted or scheduled."""
        return [(e["tick"], e["x"], e["y"]) for e in self._planted + self._pending
                if e["kind"] == "touch"]

    def _due(self, notes: dict) -> None:
        while self._pending and self._pending[0]["tick"] <= self.sim.tick:
            if self._pending[0]["kind"] == "melt":
                self._melt(self._pending.pop(0), notes)
            else:
                self._plant_due()

    def _plant_due(self) -> None:
        """Plant the touches due first, together if they were planted together before
        (with gap 0, as version 1 did: every touch due)."""
        head, n = self._pending, 1
        while (n < len(head) and head[n]["kind"] == "touch" and head[n]["tick"] == head[0]["tick"]
               and (self.gap == 0 or head[n].get("group") == head[0].get("group"))):
            n += 1
        self._plant(head[:n])
        del head[:n]

    def _plant(self, touches: list[dict[str, Any]]) -> None:
        """Plant `touches` now, together (one top-up per area they touch)."""
        self.sim.plant([(e["x"], e["y"]) for e in touches])
        self._group += 1
        self._planted += [{**e, "tick": self.sim.tick, "group": self._group} for e in touches]

    # ---- event handlers: (event, notes) ------------------------------------------------

    def _touch(self, event: dict, _notes: dict) -> None:
        x, y = float(event["x"]), float(event["y"])
        if touch_problem(x, y, self.size) is None:  # a touch off the screen is ignored
            self._plant([{"tick": self.sim.tick, "kind": "touch", "x": x, "y": y}])
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

    def _thaw(self, notes: dict) -> None:
        """In a thaw, every THAW_TICKS ticks the ice's thin edges melt (one layer of tips)."""
        if self.sim.thawing and self.sim.tick % THAW_TICKS == 0:
            melted = self.sim.melt_tips()
            if len(melted.crystals):
                notes["deltas"].append(self.geometry.melt(self.sim, melted))

    def _clear(self, _event: dict, notes: dict) -> None:
        self.touches, self.melts, self._pending, self._planted = (), [], [], []
        self._rebuild(self.params, notes)

    def _rebuild(self, params: Params, notes: dict) -> None:
        # What an earlier rebuild scheduled and has not happened yet comes again too.
        touches = self._planted + [e for e in self._pending if e["kind"] == "touch"]
        melts = self.melts + [e for e in self._pending if e["kind"] == "melt"]
        touches = regrow(sorted(touches, key=lambda e: e["tick"]), self.gap)
        self.touches = tuple((e["x"], e["y"]) for e in touches)
        # (stable: a tick's touches before its melts, as they applied)
        self._pending = sorted(touches + melts, key=lambda e: e["tick"])
        self.melts, self._planted = [], []
        self._build(params)
        notes["reset"] = True
        notes["deltas"].clear()  # older melt deltas belong to the old frost

    def _build(self, params: Params) -> None:
        self.params = params
        self.sim = FrostSim(params, *self.size, seed=self.seed, version=self.version,
                            wrap=self.wrap)
        self.geometry = FrostGeometry(params, *self.size, wrap=self.wrap)
        self._set_weather()
        while self._pending and self._pending[0]["tick"] == 0 \
                and self._pending[0]["kind"] == "touch":  # (melts wait for the step)
            self._plant_due()


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
