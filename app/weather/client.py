"""Open-Meteo's two APIs, asked with aiohttp: the geocoding API turns a place's name into
its first match's coordinates, the forecast API gives the current conditions there as a
`sim.weather.Reading`. Every failure is a `WeatherError` whose message is one line that
names the cause (the host unreachable or slow, an HTTP error, a reply that is not the
API's JSON, a field missing, no such place). `LAT,LON` is never sent to the geocoder."""

from __future__ import annotations

import asyncio
import json
import math
import os
import socket
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any
from urllib.parse import urlsplit

from sim.io.files import one_line
from sim.weather import Reading
from sim.weather.reading import short

if TYPE_CHECKING:
    import aiohttp

TIMEOUT_S = 5.0  # one request's limit: a slow API is a failure, never a wait
# The current values asked for; the first five are required, the rest optional.
CURRENT = ("temperature_2m", "relative_humidity_2m", "dew_point_2m", "weather_code", "is_day",
           "wind_speed_10m", "apparent_temperature", "cloud_cover")
REQUIRED = CURRENT[:5]
# The reading's field each optional value fills.
OPTIONAL = {"wind_speed_10m": "wind_speed_kmh", "apparent_temperature": "apparent_c",
            "cloud_cover": "cloud_pct"}
DIGITS = 2  # decimals of the coordinates sent (about a kilometre)
MOST_BYTES = 1 << 20  # a reply longer than this is not the API's


class WeatherError(Exception):
    """A reading that could not be had; its message is one line naming the cause."""

    def __init__(self, message: str):
        super().__init__(one_line(message))


@dataclass(frozen=True)
class Place:
    """Where to read the weather: a name to print and the coordinates sent."""

    name: str
    latitude: float
    longitude: float

    def words(self) -> str:
        """e.g. `Oslo, Norway (59.91, 10.75)`."""
        return f"{self.name} ({self.latitude:.2f}, {self.longitude:.2f})"


def coordinates(text: str) -> Place | None:
    """The place `text` names as `LAT,LON` (rounded to DIGITS decimals), None when it is
    not two numbers; ValueError when it is, but off the globe. Whatever reads as two numbers
    with a comma between ("1e3,5", "nan,nan", "inf,0", " 91 , 0") is a place by coordinates,
    never a name for the geocoder."""
    parts = text.split(",")
    if len(parts) != 2:
        return None
    try:
        lat, lon = float(parts[0]), float(parts[1])
    except ValueError:
        return None
    if not (-90 <= lat <= 90 and -180 <= lon <= 180):  # (NaN is in neither)
        raise ValueError(f"{text.strip()!r}: a latitude must be in [-90, 90] and a "
                         "longitude in [-180, 180]")
    return at(lat, lon)


def at(latitude: float, longitude: float, name: str | None = None) -> Place:
    """The place at (latitude, longitude), rounded as they are sent."""
    lat, lon = round(latitude, DIGITS) + 0.0, round(longitude, DIGITS) + 0.0
    return Place(name or f"{lat:.2f},{lon:.2f}", lat, lon)


async def find(session: aiohttp.ClientSession, api: str, name: str,
               timeout_s: float = TIMEOUT_S) -> Place:
    """The geocoding API's first match for `name` (named with its country)."""
    data = await _json(session, f"{api.rstrip('/')}/v1/search",
                       {"name": name, "count": "1", "language": "en", "format": "json"}, timeout_s)
    results = data.get("results") if isinstance(data, dict) else None
    if not results:
        if isinstance(data, dict) and ("results" in data or "generationtime_ms" in data):
            raise WeatherError(f"no place called {name!r} ({_host(api)} found none)")
        raise WeatherError(f"{_host(api)} answered JSON that is not the geocoding API's: {short(data)}")
    first: Any = results[0] if isinstance(results, list) else None
    try:
        label = ", ".join(str(first[k]) for k in ("name", "country") if first.get(k))
        lat, lon = float(first["latitude"]), float(first["longitude"])
    except (TypeError, KeyError, ValueError, AttributeError):
        raise WeatherError(f"{_host(api)}'s match for {name!r} holds no name and coordinates: "
                           f"{short(first)}") from None
    if not (math.isfinite(lat) and math.isfinite(lon) and abs(lat) <= 90 and abs(lon) <= 180):
        raise WeatherError(f"{_host(api)}'s match for {name!r} lies off the globe: {short(first)}")
    return at(lat, lon, label[:200] or name)


async def current(session: aiohttp.ClientSession, api: str, place: Place,
                  timeout_s: float = TIMEOUT_S) -> Reading:
    """The forecast API's current conditions at `place` (times in the place's own zone)."""
    data = await _json(session, f"{api.rstrip('/')}/v1/forecast",
                       {"latitude": f"{place.latitude:.{DIGITS}f}",
                        "longitude": f"{place.longitude:.{DIGITS}f}",
                        "current": ",".join(CURRENT), "timezone": "auto"}, timeout_s)
    now = data.get("current") if isinstance(data, dict) else None
    if not isinstance(now, dict):
        raise WeatherError(f"{_host(api)} answered JSON without 'current': {short(data)}")
    missing = [k for k in ("time", *REQUIRED) if now.get(k) is None]
    if missing:
        raise WeatherError(f"{_host(api)}'s reading lacks {', '.join(missing)}")
    try:
        return Reading(place.name, place.latitude, place.longitude, _number(now["temperature_2m"]),
                       _number(now["relative_humidity_2m"]), _number(now["dew_point_2m"]),
                       _whole(now["weather_code"]), _flag(now["is_day"]), now["time"],
                       *(_optional(now.get(k)) for k in OPTIONAL))
    except (TypeError, ValueError) as err:
        raise WeatherError(f"{_host(api)}'s reading is not the forecast's: {err}") from None


async def _json(session: aiohttp.ClientSession, url: str, query: dict[str, str],
                timeout_s: float) -> Any:
    """The JSON `url` answers `query` with; WeatherError for any failure."""
    import aiohttp  # (here: a run without --weather never loads it)

    host = _host(url)
    try:
        async with session.get(url, params=query,
                               timeout=aiohttp.ClientTimeout(total=timeout_s)) as reply:
            if reply.status == 429:
                raise WeatherError(f"{host} refused: too many requests (HTTP 429)")
            if reply.status != 200:
                raise WeatherError(f"{host} answered HTTP {reply.status} {reply.reason or ''}".rstrip())
            body = await _body(reply, host)
    except asyncio.TimeoutError:
        raise WeatherError(f"{host} did not answer within {timeout_s:g} s") from None
    except aiohttp.ClientConnectorError as err:  # (refused, no route, a name not found)
        raise WeatherError(f"cannot reach {host}: {_reason(err.os_error)}") from None
    except aiohttp.ClientError as err:
        raise WeatherError(f"cannot read {host}'s answer: {err or type(err).__name__}") from None
    except ValueError as err:  # (a URL aiohttp cannot ask)
        raise WeatherError(f"cannot ask {url}: {err}") from None
    try:
        return json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        raise WeatherError(f"{host} answered something that is not JSON: {short(body)}") from None


async def _body(reply: aiohttp.ClientResponse, host: str) -> bytes:
    """The reply's whole body, read as its pieces arrive (a network may split it anywhere),
    to its end; WeatherError when it is longer than MOST_BYTES (said before reading when its
    Content-Length says so)."""
    if reply.content_length is not None and reply.content_length > MOST_BYTES:
        raise _too_large(host, reply.content_length)
    body = bytearray()
    while len(body) <= MOST_BYTES:
        piece = await reply.content.read(MOST_BYTES + 1 - len(body))
        if not piece:  # (the end)
            return bytes(body)
        body += piece
    raise _too_large(host)


def _too_large(host: str, length: int | None = None) -> WeatherError:
    size = f"{length:,} bytes" if length is not None else f"more than {MOST_BYTES:,} bytes"
    return WeatherError(f"{host} answered {size}: too large for the API's JSON "
                        f"(at most {MOST_BYTES:,})")


def _reason(err: OSError) -> str:
    """An OSError's cause in words ("Connection refused"), without its details."""
    if isinstance(err.errno, int) and err.errno > 0 and not isinstance(err, socket.gaierror):
        return os.strerror(err.errno)
    return err.strerror or str(err) or type(err).__name__


def _host(url: str) -> str:
    return urlsplit(url).netloc or url


def _number(v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{short(v)} is not a number")
    return float(v)


def _whole(v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
            or v != int(v):
        raise ValueError(f"{short(v)} is not a weather code")
    return int(v)


def _flag(v: Any) -> bool:
    if v not in (0, 1) or isinstance(v, float):
        raise ValueError(f"is_day {short(v)} is neither 0 nor 1")
    return bool(v)


def _optional(v: Any) -> float | None:
    return None if v is None else _number(v)
