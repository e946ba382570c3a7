"""The glass between the room and the night, and what it does to the frost
(docs/method.md, section 12).

The inner surface of a pane sits between the room's air and the outside's: with the
inner surface resistance R_si and the glazing's U-value, glass = room - U R_si (room -
outside) (EN ISO 6946's surface resistance; the U-values of old single and of double
glazing). Frost deposits where the glass is below 0 C and below the room's frost point
(Magnus over ice, WMO-No. 8); the colder the glass below that point, the faster and
more branched it grows: the window preset's `temperature` (degrees below freezing) is
that undercooling. Glass at or above 0 C grows nothing and its ice melts; glass below 0
C but above the room's frost point (a dry room) grows nothing and its ice sublimes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .reading import Reading, short

R_SI = 0.13  # m2K/W: the inner surface's resistance (EN ISO 6946, heat flowing out)
U_VALUES = {"single": 5.8, "double": 2.8}  # W/m2K: old single glazing, double glazing
GLAZINGS = tuple(U_VALUES)
ROOM_C = 20.0  # the room's air, degrees C
ROOM_HUMIDITY = 40.0  # the room's relative humidity, %: its dew point is 6 C
ROOM_C_RANGE = (0.0, 40.0)
ROOM_HUMIDITY_RANGE = (1.0, 100.0)
# Magnus's form of the saturation vapour pressure, e = E0 exp(A t / (B + t)) hPa, over water
# and over ice (WMO-No. 8, Annex 4.B, after Sonntag 1990).
E0 = 6.112
WATER = (17.62, 243.12)
ICE = (22.46, 272.62)
# The `temperature` parameter's range (sim/params.py: (0, 40]); the floor keeps a glass
# just below its frost point growing, at a twentieth of the pace of -10 C's hit counts.
LEAST_UNDERCOOLING = 0.5
MOST_UNDERCOOLING = 40.0
# The thaw's pace: one layer of the ice's tips melts every this many ticks (2 s at 25 ticks
# a second). A fern is mostly short side branches: the window preset's frost of 900 ticks
# at -25 C loses four fifths of its crystals in the first 20 s and the last in about 2.5 min
# (at 12 ticks, 5 s and 35 s: a collapse, not a melt).
THAW_TICKS = 50
# The supply's range: the room's vapour against the stated room's (1 at 20 C and 40 %).
SUPPLY_RANGE = (0.25, 2.0)


@dataclass(frozen=True)
class Glass:
    """The window the weather acts on: its glazing and the room behind it."""

    glazing: str = "single"
    room_c: float = ROOM_C
    room_humidity: float = ROOM_HUMIDITY

    def __post_init__(self):
        if self.glazing not in U_VALUES:
            raise ValueError(f"glazing {short(self.glazing)} must be one of {', '.join(GLAZINGS)}")
        for name, (lo, hi) in (("room_c", ROOM_C_RANGE), ("room_humidity", ROOM_HUMIDITY_RANGE)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not lo <= value <= hi:
                raise ValueError(f"{name} must be a number in [{lo:g}, {hi:g}], not {short(value)}")

    def as_json(self) -> dict[str, Any]:
        return {"glazing": self.glazing, "room_c": float(self.room_c),
                "room_humidity": float(self.room_humidity)}

    @classmethod
    def from_json(cls, data: Any) -> Glass:
        """The glass `data` describes; ValueError naming the problem, in one line."""
        if not isinstance(data, dict) or set(data) != {"glazing", "room_c", "room_humidity"}:
            raise ValueError("a weather event's glass must hold glazing, room_c and "
                             f"room_humidity, not {short(data)}")
        return cls(data["glazing"], data["room_c"], data["room_humidity"])


@dataclass(frozen=True)
class Frost:
    """What the glass does to the frost: it `grows` with the window preset's `temperature`
    set to `temperature` and the pane's water times `supply`, or it does not (`melts`:
    the glass is at or above 0 C; `fades`: below 0 C but above the room's frost point)."""

    glass_c: float
    state: str  # "grows", "melts" or "fades"
    temperature: float | None  # degrees below the frost's onset, while it grows
    supply: float

    @property
    def thaw(self) -> bool:
        """Nothing grows and the ice goes back from its thin edges."""
        return self.state != "grows"


def glass_temperature(outside_c: float, room_c: float = ROOM_C, glazing: str = "single") -> float:
    """The inner surface's temperature, degrees C: room - U R_si (room - outside)."""
    return room_c - U_VALUES[glazing] * R_SI * (room_c - outside_c)


def saturation(t_c: float, over: tuple[float, float] = WATER) -> float:
    """Saturation vapour pressure at `t_c`, hPa (Magnus)."""
    a, b = over
    return E0 * math.exp(a * t_c / (b + t_c))


def _inverse(e_hpa: float, over: tuple[float, float]) -> float:
    a, b = over
    x = math.log(e_hpa / E0)
    return b * x / (a - x)


def dew_point(t_c: float, humidity_pct: float) -> float:
    """The air's dew point, degrees C (Magnus over water)."""
    return _inverse(humidity_pct / 100.0 * saturation(t_c), WATER)


def frost_point(t_c: float, humidity_pct: float) -> float:
    """Where the air's vapour saturates over ice, degrees C (Magnus over ice)."""
    return _inverse(humidity_pct / 100.0 * saturation(t_c), ICE)


def frost_of(outside_c: float, glass: Glass = Glass()) -> Frost:
    """What `outside_c` outside does to the frost on `glass` (see the module doc)."""
    g = glass_temperature(outside_c, glass.room_c, glass.glazing)
    onset = min(0.0, frost_point(glass.room_c, glass.room_humidity))
    vapour = glass.room_humidity * saturation(glass.room_c)
    stated = ROOM_HUMIDITY * saturation(ROOM_C)
    supply = min(max(vapour / stated, SUPPLY_RANGE[0]), SUPPLY_RANGE[1])
    if g >= 0.0:
        return Frost(g, "melts", None, supply)
    if g >= onset:
        return Frost(g, "fades", None, supply)
    return Frost(g, "grows", min(max(onset - g, LEAST_UNDERCOOLING), MOST_UNDERCOOLING), supply)


WORDS = {"grows": "frost grows", "melts": "frost melts", "fades": "frost fades (the room is dry)"}


def describe(reading: Reading, glass: Glass = Glass()) -> str:
    """The one line that says what was read and what it does, e.g. `weather: -25.0 C,
    80 %, dew point -27.6 C at 23:00: glass -14 C, frost grows` (ASCII only)."""
    frost = frost_of(reading.temperature_c, glass)
    return (f"weather: {_signed(reading.temperature_c, 1)} C, {reading.humidity_pct:.0f} %, "
            f"dew point {_signed(reading.dew_point_c, 1)} C at {reading.clock}: "
            f"glass {glass_words(frost.glass_c)} C, {WORDS[frost.state]}")


def glass_words(glass_c: float) -> str:
    """The glass's temperature in whole degrees, never read across 0 C from where it is (the
    state beside it turns at 0): one decimal where whole degrees would read 0 (-0.36: "-0.4",
    +0.4: "0.4"), "just below 0" / "just above 0" where one decimal would too; 0 itself "0"."""
    if glass_c == 0:
        return "0"
    for digits in (0, 1):
        text = _signed(glass_c, digits)
        if float(text) != 0:
            return text
    return "just below 0" if glass_c < 0 else "just above 0"


def event_frost(weather: dict[str, Any]) -> Frost:
    """What a weather event's {"reading": ..., "glass": ...} does to the frost."""
    reading, glass = Reading.from_json(weather["reading"]), Glass.from_json(weather["glass"])
    return frost_of(reading.temperature_c, glass)


def event_words(weather: dict[str, Any]) -> tuple[str, str]:
    """A weather event's {"reading": ..., "glass": ...} (a session's, a snapshot's) in words:
    its reading's place, and `describe`'s line without its "weather: " (the HUD and the
    pages show them)."""
    reading, glass = Reading.from_json(weather["reading"]), Glass.from_json(weather["glass"])
    return reading.place, describe(reading, glass).removeprefix("weather: ")


def _signed(value: float, digits: int) -> str:
    """`value` to `digits` decimals, never "-0"."""
    text = f"{value:.{digits}f}"
    return text.lstrip("-") if float(text) == 0 else text
