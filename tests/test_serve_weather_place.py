"""The phone's place for the weather (app/serve/weather.py, the guard's body in
app/serve/guard.py): `POST /weather` to a server listening as `frost serve` does, as raw
HTTP requests. Oracles: the place the weather feed is moved to (a stand-in feed that
records it), rounded by hand, and the status line and JSON of each answer."""

from __future__ import annotations

import asyncio
import json

import pytest
from support.photos import answer, post_head, upload

from app.serve import guard, weather
from app.serve.feed import Feed
from app.serve.listen import listen
from app.serve.server import make_app
from sim import Params


class Places:
    """A stand-in weather feed: the places it was moved to."""

    def __init__(self):
        self.moves: list[tuple[float, float]] = []

    def set_place(self, latitude: float, longitude: float) -> None:
        self.moves.append((latitude, longitude))


def run(test, places: Places | None, gap: float | None = 0, token: str | None = None):
    """`test(port)` against a server listening as `frost serve` does, moving `places` (None:
    a server that follows no weather); `gap`: the seconds between two places of an address
    (None: the server's own)."""
    async def main():
        feed = Feed(Params.preset("c-2"), seed=1)
        feed.weather = places  # type: ignore[assignment]  # (a stand-in)
        app = make_app(feed, token)
        if gap is not None:
            app[weather.PLACES].gap = gap
        runner = await listen(app, "127.0.0.1", 0, token)
        assert runner is not None
        try:
            await test(runner.addresses[0][1])
        finally:
            await runner.cleanup()
    asyncio.run(main())


def send(port: int, body, **kw):
    """POST /weather of `body` (JSON-encoded unless bytes)."""
    data = body if isinstance(body, bytes) else json.dumps(body).encode()
    return upload(port, data, path=kw.pop("path", "/weather"), **kw)


def error_line(body: bytes) -> str:
    text = json.loads(body)["error"]
    assert isinstance(text, str) and text and "\n" not in text and len(text) < 200, text
    return text


def test_a_place_is_rounded_to_a_tenth_of_a_degree_and_moves_the_weather():
    places = Places()

    async def test(port):
        # Stockholm's centre, as a phone reports it; a place just south-west of (0, 0)
        status, headers, body = await send(port, {"latitude": 59.33459, "longitude": 18.06324})
        assert status == 202, body
        assert json.loads(body) == {"latitude": 59.3, "longitude": 18.1}
        assert headers["cache-control"] == "no-store"
        status, _, body = await send(port, {"latitude": -0.04, "longitude": -179.96, "accuracy": 20})
        assert status == 202, body
        assert json.loads(body) == {"latitude": 0.0, "longitude": -180.0}
        assert places.moves == [(59.3, 18.1), (0.0, -180.0)]
    run(test, places)


@pytest.mark.parametrize(("body", "says"), [
    (b"latitude=59.3", "not JSON"), (b"[59.3, 18.1]", "JSON object"),
    ({"latitude": 59.3}, "longitude must be a number"),
    ({"latitude": "59.3", "longitude": 18.1}, "latitude must be a number"),
    ({"latitude": True, "longitude": 18.1}, "latitude must be a number"),
    (b'{"latitude": NaN, "longitude": 18.1}', "latitude nan is not within"),
    # (the values --weather refuses as coordinates off the globe, as a page could send them)
    ({"latitude": 1e3, "longitude": 5}, "latitude 1000 is not within -90 and 90"),
    (b'{"latitude": NaN, "longitude": NaN}', "latitude nan is not within"),
    (b'{"latitude": Infinity, "longitude": 0}', "latitude inf is not within"),
    (b'{"latitude": 1e999, "longitude": 0}', "latitude inf is not within"),
    ({"latitude": 10, "longitude": float("-inf")}, "longitude -inf is not within"),
    ({"latitude": " 91 ", "longitude": 0}, "latitude must be a number of degrees, not \" 91 \""),
    ({"latitude": 90.5, "longitude": 18.1}, "latitude 90.5 is not within -90 and 90"),
    ({"latitude": 59.3, "longitude": -181}, "longitude -181 is not within -180 and 180"),
    (b"[" * 500 + b"]" * 500, "JSON object")])
def test_a_bad_place_is_told_in_one_line_and_moves_nothing(body, says):
    places = Places()

    async def test(port):
        status, headers, answer = await send(port, body)
        assert status == 400 and headers["content-type"].startswith("application/json")
        assert says in error_line(answer)
        assert places.moves == []
    run(test, places)


@pytest.mark.parametrize("origin", [None, "http://evil.example", "https://127.0.0.1:{port}"])
def test_a_place_from_another_origin_or_none_is_refused(origin):
    places = Places()

    async def test(port):
        given = None if origin is None else origin.format(port=port)
        status, _, body = await send(port, {"latitude": 1, "longitude": 2}, origin=given)
        assert status == 403 and error_line(body) and places.moves == []
        # (from the page's own origin it is taken: the Origin alone refused it)
        assert (await send(port, {"latitude": 1, "longitude": 2}))[0] == 202
    run(test, places)


def test_a_place_without_the_token_is_refused_in_json():
    places = Places()

    async def test(port):
        status, headers, body = await send(port, {"latitude": 1, "longitude": 2})
        assert status == 403 and headers["content-type"].startswith("application/json")
        assert "needs the token" in error_line(body) and places.moves == []
        status, _, _ = await send(port, {"latitude": 1, "longitude": 2}, path="/weather?token=t0ken")
        assert status == 202 and places.moves == [(1.0, 2.0)]
    run(test, places, token="t0ken")


def test_one_place_every_few_seconds_from_an_address():
    places = Places()

    async def test(port):
        answers = await asyncio.gather(*(send(port, {"latitude": i, "longitude": 0}) for i in range(4)))
        assert sorted(a[0] for a in answers) == [202, 429, 429, 429]
        for status, headers, body in answers:
            if status == 429:
                assert 1 <= int(headers["retry-after"]) <= 5
                assert "one place every 5 s" in error_line(body)
        assert len(places.moves) == 1
    run(test, places, gap=None)


def test_a_server_that_follows_no_weather_says_so():
    async def test(port):
        status, _, body = await send(port, {"latitude": 1, "longitude": 2})
        assert status == 503 and "--weather" in error_line(body)
    run(test, None)


def test_a_long_body_or_none_counted_is_refused_before_it_is_read():
    places = Places()

    async def test(port):
        status, _, body = await send(port, b" " * (weather.MAX_BYTES + 1))
        assert status == 413 and "at most 1024" in error_line(body)
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(post_head(port, None, path="/weather") + b"0\r\n\r\n")
        status, _, body = await answer(reader)
        assert status == 411 and "Content-Length" in error_line(body)
        writer.close()
        assert places.moves == []
    run(test, places)


def test_the_guard_passes_a_places_body_as_a_body():
    """The connection guard reads POST /weather's Content-Length bytes as its body (not as
    the next request's head, which would be timed as one)."""
    head = post_head(8025, 40, path="/weather?token=t")
    assert guard.body_length(head.removesuffix(b"\r\n\r\n")) == 40
    assert guard.body_length(post_head(8025, 40, path="/meta").removesuffix(b"\r\n\r\n")) == 0
