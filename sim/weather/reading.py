"""One reading of the weather where the window is: what the forecast API said of the
current conditions, as it said it (`Reading`), and its JSON form (a session's "weather"
events and the kept last reading hold it). Every value is checked when read back."""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass, fields
from typing import Any

# The API's local time of a reading: "YYYY-MM-DDTHH:MM".
TIME = re.compile(r"\d{4}-\d{2}-\d{2}T\d{2}:\d{2}\Z")
# Bounds a value must lie in to be a reading of this planet's weather at all.
BOUNDS = {"latitude": (-90.0, 90.0), "longitude": (-180.0, 180.0),
          "temperature_c": (-100.0, 70.0), "humidity_pct": (0.0, 100.0),
          "dew_point_c": (-120.0, 70.0), "wind_speed_kmh": (0.0, 500.0),
          "apparent_c": (-120.0, 90.0), "cloud_pct": (0.0, 100.0)}
OPTIONAL = ("wind_speed_kmh", "apparent_c", "cloud_pct")


@dataclass(frozen=True)
class Reading:
    """The current conditions at one place. `latitude` and `longitude` are those the API
    was asked for (rounded as sent); `time` is the API's local time of the reading."""

    place: str
    latitude: float
    longitude: float
    temperature_c: float
    humidity_pct: float
    dew_point_c: float
    weather_code: int
    is_day: bool
    time: str
    wind_speed_kmh: float | None = None
    apparent_c: float | None = None
    cloud_pct: float | None = None

    def __post_init__(self):
        problem = reading_problem(asdict(self))
        if problem:
            raise ValueError(problem)

    def as_json(self) -> dict[str, Any]:
        """The reading as a JSON object (the optional values left out where unknown)."""
        data = asdict(self)
        return {k: v for k, v in data.items() if v is not None or k not in OPTIONAL}

    @classmethod
    def from_json(cls, data: Any) -> Reading:
        """The reading `data` holds; ValueError naming the first problem, in one line."""
        if not isinstance(data, dict):
            raise ValueError(f"a weather reading must be an object, not {short(data)}")
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(data) - names, key=repr)
        if unknown:
            raise ValueError(f"a weather reading has no {', '.join(map(repr, unknown))}")
        missing = [n for n in names if n not in data and n not in OPTIONAL]
        if missing:
            raise ValueError(f"a weather reading lacks {', '.join(sorted(missing))}")
        problem = reading_problem(data)
        if problem:
            raise ValueError(problem)
        values: dict[str, Any] = {k: float(v) if k in BOUNDS and v is not None else v
                                  for k, v in data.items()}
        return cls(**values)

    @property
    def clock(self) -> str:
        """The reading's local time of day, "HH:MM"."""
        return self.time[11:16]


def reading_problem(data: dict[str, Any]) -> str | None:
    """What is wrong with a reading's values (None when nothing is)."""
    place = data.get("place")
    if not isinstance(place, str) or not 0 < len(place) <= 200 or not place.isprintable():
        return f"a weather reading's place must be a name of 1 to 200 characters, not {short(place)}"
    for name, (lo, hi) in BOUNDS.items():
        value = data.get(name)
        if value is None and name in OPTIONAL:
            continue
        number = value if _number(value) else None
        if number is None or not lo <= number <= hi:
            return f"a weather reading's {name} must be a number in [{lo:g}, {hi:g}], not {short(value)}"
    code = data.get("weather_code")
    if isinstance(code, bool) or not isinstance(code, int) or not 0 <= code <= 99:
        return f"a weather reading's weather_code must be a whole number in [0, 99], not {short(code)}"
    if not isinstance(data.get("is_day"), bool):
        return f"a weather reading's is_day must be true or false, not {short(data.get('is_day'))}"
    if not isinstance(data.get("time"), str) or not TIME.match(data["time"]):
        return f"a weather reading's time must be YYYY-MM-DDTHH:MM, not {short(data.get('time'))}"
    return None


def _number(v: Any) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v)


def short(value: Any, limit: int = 60) -> str:
    """`value`'s repr on one line, cut to `limit` characters (a reply may be anything)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."
