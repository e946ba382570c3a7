"""The phone's "Weather where I am" (docs/protocol.md, A place for the weather):
`POST /weather` with the page's place, rounded to 0.1 degree, moves the server's weather
feed (the feed's `weather`, --weather's) there; every page then follows that place's
reading (the state's `weather`).

Its Origin is checked and its refusals are JSON as every POST's (app/serve/posts.py); each
remote address may send one place every MIN_GAP_S (each place is a request to the weather
API). The body is a small JSON object, read to its Content-Length (at most MAX_BYTES). The
server keeps the rounded place alone: the feed's session event and its kept reading.
"""

from __future__ import annotations

import asyncio
import json
import logging
import math
from dataclasses import dataclass

from aiohttp import web

from app.serve.appkeys import FEED
from app.serve.posts import Gaps, head_refusal, refusal, unread

log = logging.getLogger("app.serve")

PATH = "/weather"
MIN_GAP_S = 5.0  # s between two places of one remote address
MAX_BYTES = 1024  # {"latitude": -89.123456789, "longitude": ...} is under 100
STEP = 0.1  # degrees a place is rounded to (about 10 km): no closer is sent on or kept
NO_WEATHER = "this server follows no weather: start frost serve with --weather PLACE"


@dataclass
class PlaceDesk(Gaps):
    """What the route keeps: when each remote address last sent a place, the places taken."""

    gap: float = MIN_GAP_S
    taken: int = 0


def rounded(value: float) -> float:
    """`value` to STEP degrees, without float noise (59.34 -> 59.3, not 59.300000000000004)."""
    return round(round(value / STEP) * STEP, 1)


def parse_place(body: bytes) -> tuple[float, float]:
    """(latitude, longitude) of a request's body, each rounded to STEP; ValueError in one
    line naming what is wrong."""
    try:
        data = json.loads(body)
    except (ValueError, RecursionError):
        raise ValueError('the body is not JSON: send {"latitude": N, "longitude": N}') from None
    if not isinstance(data, dict):
        raise ValueError('the body must be a JSON object {"latitude": N, "longitude": N}')
    return (_degrees(data, "latitude", 90.0), _degrees(data, "longitude", 180.0))


def _degrees(data: dict, key: str, most: float) -> float:
    """data[key], a number of degrees within +-`most`, rounded to STEP."""
    value = data.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{key} must be a number of degrees, not {json.dumps(value)[:30]}")
    if not math.isfinite(value) or abs(value) > most:
        raise ValueError(f"{key} {value:g} is not within -{most:g} and {most:g} degrees")
    return rounded(value)


async def place(request: web.Request) -> web.Response:
    """POST /weather: the body {"latitude": N, "longitude": N}; 202 {"latitude": N,
    "longitude": N} (rounded: what the server asks the weather of; the reading comes to
    every page in a state message), else a 4xx/5xx {"error": one line}."""
    desk: PlaceDesk = request.app[PLACES]
    refused = head_refusal(request, "a place", MAX_BYTES,
                           lambda n: f"the body is {n:,} bytes; a place takes at most {MAX_BYTES}")
    if refused is not None:
        return refused
    length = request.content_length or 0
    feed = request.app[FEED]
    if feed.weather is None:
        return unread(503, NO_WEATHER)
    if feed.ending:
        return unread(503, "frost serve is ending: the place was not taken")
    now = asyncio.get_running_loop().time()
    remote = request.remote or "?"
    soon = desk.too_soon(remote, now, "place")
    if soon is not None:
        return soon
    desk.last[remote] = now
    try:
        latitude, longitude = parse_place(await request.content.readexactly(length))
    except (asyncio.IncompleteReadError, ConnectionError):
        return refusal(400, "the body stopped before its Content-Length")
    except ValueError as err:
        return refusal(400, str(err))
    desk.taken += 1
    log.info("serve: a page moves the weather to its place")
    feed.weather.set_place(latitude, longitude)
    return web.json_response({"latitude": latitude, "longitude": longitude}, status=202,
                             headers={"Cache-Control": "no-store"})


PLACES = web.AppKey("places", PlaceDesk)


def routes_for(app: web.Application) -> None:
    """POST /weather on `app`."""
    app[PLACES] = PlaceDesk()
    app.router.add_post(PATH, place)
