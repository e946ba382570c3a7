"""Session files: the seed, parameters and input events of a frost run, written and read
back with every entry checked (`SessionLog`); sim.io.timeline applies the events.

Kinds of event: "touch" (x, y), "melt" (x, y, r), "params" (params: a dict; rebuilds the
simulation), "clear" (drops the touches and melts, rebuilds) and, from version 10, "clock"
(minute: the lock screen's clock shows that minute from here on, "YYYY-MM-DDTHH:MM", local
time; the frost is untouched) and, from version 11, "backdrop" (name: the backdrop shown
from here on, a built-in's or a photo's name; the frost is untouched) and, from version
12, "weather" (reading: what the weather API said, sim.weather.Reading's JSON; glass: the
glazing and the room it acts on, sim.weather.Glass's: the frost grows or thaws as they
make it from here on). Each has its
"tick": the tick of its timeline it applied at (a rebuild starts a new timeline at tick 0).
From version 13 a file may say where it was grown: "source": "phone" (a phone's own
session, grown by the page's simulation: it replays here, but not bit for bit).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field, fields
from datetime import datetime
from pathlib import Path
from typing import Any

from ..core.frost import VERSION as FROST_VERSION
from ..core.versions import PHONE_VERSION
from ..params import Params
from ..screen import HEIGHT, WIDTH, melt_problem, touch_problem
from ..weather import Glass, Reading
from .files import one_line, read_json, write_atomic

FORMAT = "frost-session"
# The rules a file grows by; sim/core/versions.py lists what each version changed. Older
# files replay as frost did when they were written.
VERSION = FROST_VERSION
# The keys each event kind needs besides "tick" and "kind".
EVENT_FIELDS = {"touch": ("x", "y"), "melt": ("x", "y", "r"), "params": ("params",),
                "clear": (), "clock": ("minute",), "backdrop": ("name",),
                "weather": ("reading", "glass")}
REBUILDS = ("params", "clear")  # kinds that start a new timeline at tick 0
# Kinds that change only what is shown, not the frost: a session of these alone has
# nothing to replay (no file is written for it).
SHOWN_ONLY = ("clock", "backdrop")
# The first version whose files may hold each kind of event (kinds not named: all).
SINCE = {"clock": 10, "backdrop": 11, "weather": 12}
# A backdrop event's name: a built-in's ("dusk") or a photo's ("photo-" and 32 hex digits):
# the names the pages' protocol carries, never a path.
BACKDROP_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}\Z")
DEFAULT_BACKDROP = "dusk"  # what a session shows before its first backdrop event
MINUTE_FORMAT = "%Y-%m-%dT%H:%M"  # a clock event's minute, local time
# Where a file may say it was grown ("source", from version 13): a phone's page, whose
# simulation draws other random numbers. A file without it was grown by sim/.
SOURCES = ("phone",)


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
    version: int = VERSION  # the rules it replays with (the frost's and the timeline's)
    source: str | None = None  # "phone": grown by a phone's page (SOURCES), not bit for bit

    def as_json(self) -> dict[str, Any]:
        data = {"format": FORMAT, "version": self.version, "seed": self.seed, "width": self.width,
                "height": self.height, "params": self.params, "steps": self.steps,
                "events": self.events}
        if self.source is not None:
            data["source"] = self.source
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
        version = _whole(data, "version", 1, VERSION, VERSION)
        late = next((e for e in events if version < SINCE.get(e["kind"], 1)), None)
        if late is not None:
            raise SessionError(f"event {late!r}: a {late['kind']} event needs version "
                               f"{SINCE[late['kind']]} or later (this file is version {version})")
        try:
            view = None if data.get("view") is None else check_view(data["view"])
        except ValueError as err:
            raise SessionError(str(err)) from None
        return cls(_whole(data, "seed", 0, MAX_SEED), dict(data["params"]), *size,
                   events, _whole(data, "steps", 0, MAX_TICK, 0), view, version,
                   _source(data, version))

    def bit_for_bit(self) -> bool:
        """Whether a replay here grows this very frost (not a phone's, whose random numbers
        were its own)."""
        return self.source is None

    def replayable(self) -> bool:
        """Whether it holds an event that changes the frost (not only clock minutes)."""
        return any(e["kind"] not in SHOWN_ONLY for e in self.events)


# Coordinates and radii beyond this many px are refused before their range is checked:
# no float overflows in the checks, whatever a file holds.
MAX_COORD = 1e9
# The largest seed and tick anywhere (files, command line): numpy's seeds are any whole
# number, but a session keeps what fits 64 signed bits; 2**31 ticks is 2.7 years at 25 a
# second.
MAX_SEED = 2**63 - 1
MAX_TICK = 2**31 - 1


def _source(data: dict, version: int) -> str | None:
    """The file's "source" (None: grown by sim/); SessionError if not one of SOURCES or
    in a file older than PHONE_VERSION."""
    source = data.get("source")
    if source is None:
        return None
    if source not in SOURCES:
        raise SessionError(f"'source' {str(source)[:40]!r} must be one of {', '.join(SOURCES)}")
    if version < PHONE_VERSION:
        raise SessionError(f"'source' needs version {PHONE_VERSION} or later "
                           f"(this file is version {version})")
    return source


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
    if event["kind"] == "clock" and not _minute(event["minute"]):
        raise SessionError(f"event {event!r}: 'minute' must be a local time as "
                           "YYYY-MM-DDTHH:MM")
    if event["kind"] == "backdrop" and not (isinstance(event["name"], str)
                                            and BACKDROP_NAME.match(event["name"])):
        raise SessionError(f"event {event!r}: 'name' must be a backdrop's name (1 to 64 "
                           "letters, digits, '-' or '_')")
    if event["kind"] == "weather":
        _weather(event)
    return event


def weather_event(reading: Reading, glass: Glass, tick: int = 0) -> dict[str, Any]:
    """The weather event of `reading` on `glass` (at `tick`: a timeline given it records
    its own tick)."""
    return {"tick": tick, "kind": "weather", "reading": reading.as_json(), "glass": glass.as_json()}


def _weather(event: dict) -> None:
    try:
        Reading.from_json(event["reading"])
        Glass.from_json(event["glass"])
    except ValueError as err:
        raise SessionError(f"weather event at tick {event['tick']}: {err}") from None


def _minute(v: Any) -> bool:
    """Whether `v` names a minute as "YYYY-MM-DDTHH:MM" exactly (a real date and time)."""
    if not isinstance(v, str) or len(v) != 16:
        return False
    try:
        return datetime.strptime(v, MINUTE_FORMAT).strftime(MINUTE_FORMAT) == v
    except ValueError:
        return False


def _coordinate(v: Any) -> bool:
    # abs(v) <= MAX_COORD is False for nan and inf, and exact for ints of any size
    return not isinstance(v, bool) and isinstance(v, (int, float)) and abs(v) <= MAX_COORD
