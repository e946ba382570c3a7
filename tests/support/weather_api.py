"""A stand-in for Open-Meteo's two APIs (the forecast's /v1/forecast, the geocoding's
/v1/search) on 127.0.0.1, on a thread of its own: answers in the documented JSON shapes,
or as told (`mode`): "429", "500", "slow" (held `slow_s`, or until `release()`, then
answered as `mode` says by then), "garbage", "missing" (`missing` names the field left
out), "pieces" (the JSON in three pieces, each sent and flushed PIECE_GAP_S after the
one before), "huge" (a JSON body of HUGE_BYTES, its Content-Length said) or "huge-chunked"
(the same, chunked: no length said before it comes). Every request is kept (`asked`), so a
test sees what was sent. Every answer says `Access-Control-Allow-Origin: *`, as
Open-Meteo's do: a page of another origin (the phone's own weather) reads them."""

from __future__ import annotations

import asyncio
import contextlib
import json
import threading
from typing import Any

from aiohttp import web

# The places the stand-in geocoder knows, in the API's shape (a name it does not know: no
# "results", as the API answers).
PLACES = {"Oslo": {"id": 3143244, "name": "Oslo", "latitude": 59.91273, "longitude": 10.74609,
                   "elevation": 26.0, "country_code": "NO", "timezone": "Europe/Oslo",
                   "country": "Norway", "admin1": "Oslo"},
          "Tokyo": {"id": 1850147, "name": "Tokyo", "latitude": 35.6895, "longitude": 139.69171,
                    "elevation": 44.0, "country_code": "JP", "timezone": "Asia/Tokyo",
                    "country": "Japan", "admin1": "Tokyo"},
          "Sydney": {"id": 2147714, "name": "Sydney", "latitude": -33.86785, "longitude": 151.20732,
                     "elevation": 58.0, "country_code": "AU", "timezone": "Australia/Sydney",
                     "country": "Australia", "admin1": "New South Wales"},
          # (a match off the globe, which no real geocoder gives: the client refuses it)
          "Nowhere": {"id": 1, "name": "Nowhere", "latitude": 95.0, "longitude": 10.0}}

PIECE_GAP_S = 0.3  # between two pieces of a reply in pieces
HUGE_BYTES = 5_000_000


class StandIn:
    """Both APIs at `url`; `current` is what /v1/forecast answers under "current"."""

    def __init__(self, temperature_c: float = -25.0):
        self.current: dict[str, Any] = {
            "time": "2026-01-10T23:00", "interval": 900, "temperature_2m": temperature_c,
            "relative_humidity_2m": 80, "dew_point_2m": -27.6, "weather_code": 71, "is_day": 0,
            "wind_speed_10m": 11.2, "apparent_temperature": -31.4, "cloud_cover": 100}
        self.mode = "ok"
        self.missing = "dew_point_2m"
        self.slow_s = 30.0
        self.asked: list[tuple[str, dict[str, str]]] = []
        self.arrived = threading.Event()  # set at each request, before its answer
        self.answered = threading.Event()  # set at each answer
        self.url = ""
        self._loop: asyncio.AbstractEventLoop | None = None
        self._ready = threading.Event()
        self._stop: asyncio.Event | None = None
        self._go: asyncio.Event | None = None  # set: the slow answers held go out
        self._thread = threading.Thread(target=lambda: asyncio.run(self._main()), daemon=True)

    def __enter__(self) -> StandIn:
        self._thread.start()
        assert self._ready.wait(30), "the stand-in API did not start"
        return self

    def __exit__(self, *_exc) -> None:
        if self._loop is not None and self._stop is not None:
            stop = self._stop
            self._loop.call_soon_threadsafe(lambda: (self._go and self._go.set(), stop.set()))
        self._thread.join(30)

    def release(self) -> None:
        """The slow answers held so far go out now (later ones are held again)."""
        def go() -> None:
            if self._go is not None:
                self._go.set()
            self._go = asyncio.Event()
        if self._loop is not None:
            self._loop.call_soon_threadsafe(go)

    def paths(self) -> list[str]:
        return [path for path, _query in self.asked]

    async def _main(self) -> None:
        app = web.Application()
        app.on_response_prepare.append(_cors)
        app.router.add_get("/v1/forecast", self._forecast)
        app.router.add_get("/v1/search", self._search)
        runner = web.AppRunner(app)
        await runner.setup()
        site = web.TCPSite(runner, "127.0.0.1", 0)
        await site.start()
        port = runner.addresses[0][1]
        self.url = f"http://127.0.0.1:{port}"
        self._loop, self._stop, self._go = asyncio.get_running_loop(), asyncio.Event(), asyncio.Event()
        self._ready.set()
        await self._stop.wait()
        await runner.cleanup()

    async def _answer(self, request: web.Request, body: dict) -> web.StreamResponse:
        self.asked.append((request.path, dict(request.query)))
        self.arrived.set()
        try:
            go = self._go
            if self.mode == "slow" and go is not None:  # (until released or stopped)
                with contextlib.suppress(asyncio.TimeoutError):
                    await asyncio.wait_for(go.wait(), self.slow_s)
            # (then as the mode now says: a held answer may be released as a failure)
            if self.mode == "429":
                return web.json_response({"error": True, "reason": "Too many requests"}, status=429)
            if self.mode == "500":
                return web.Response(status=500, text="Internal Server Error")
            if self.mode == "garbage":
                return web.Response(text="<html>a captive portal</html>", content_type="text/html")
            if self.mode == "pieces":
                return await self._in_pieces(request, json.dumps(body).encode())
            if self.mode.startswith("huge"):
                return await self._huge(request, body)
            return web.json_response(body)
        finally:
            self.answered.set()

    async def _in_pieces(self, request: web.Request, data: bytes) -> web.StreamResponse:
        """`data` in three pieces, each flushed to the socket, PIECE_GAP_S apart."""
        reply = web.StreamResponse(headers={"Content-Type": "application/json"})
        reply.content_length = len(data)
        await reply.prepare(request)
        cuts = (0, len(data) // 3, 2 * len(data) // 3, len(data))
        for start, end in zip(cuts, cuts[1:], strict=False):
            if start:
                await asyncio.sleep(PIECE_GAP_S)
            await reply.write(data[start:end])  # (write drains: the piece is sent)
        await reply.write_eof()
        return reply

    async def _huge(self, request: web.Request, body: dict) -> web.StreamResponse:
        """`body` padded to HUGE_BYTES of valid JSON, its length said or chunked."""
        data = json.dumps(body).encode()
        data = data[:-1] + b', "padding": "' + b"x" * (HUGE_BYTES - len(data) - 15) + b'"}'
        reply = web.StreamResponse(headers={"Content-Type": "application/json"})
        if self.mode == "huge":
            reply.content_length = len(data)
        else:
            reply.enable_chunked_encoding()
        await reply.prepare(request)
        with contextlib.suppress(ConnectionError):  # (the client may stop reading)
            for start in range(0, len(data), 1 << 16):
                await reply.write(data[start:start + (1 << 16)])
            await reply.write_eof()
        return reply

    async def _forecast(self, request: web.Request) -> web.StreamResponse:
        current = dict(self.current)
        if self.mode == "missing":
            current.pop(self.missing, None)
        q = request.query
        return await self._answer(request, {
            "latitude": float(q.get("latitude", 0)), "longitude": float(q.get("longitude", 0)),
            "generationtime_ms": 0.05, "utc_offset_seconds": 3600, "timezone": "Europe/Stockholm",
            "current_units": {"temperature_2m": "°C"}, "current": current})

    async def _search(self, request: web.Request) -> web.StreamResponse:
        place = PLACES.get(request.query.get("name", ""))
        body: dict[str, Any] = {"generationtime_ms": 0.3}
        if place is not None:
            body["results"] = [place]
        return await self._answer(request, body)


async def _cors(_request: web.Request, response: web.StreamResponse) -> None:
    response.headers["Access-Control-Allow-Origin"] = "*"
