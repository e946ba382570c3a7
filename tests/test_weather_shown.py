"""The weather outside, shown (issue 48, item 3): the pages' hello and state carry it (its
place and reading in words), and the lock screen draws the temperature outside under its
clock, on the pages (the clock box's message) and in a replay. Oracles: the reading worked
by hand (-25 C outside single glazing: glass 20 - 5.8 x 0.13 x 45 = -13.9 C, "-14"), and
the clock box drawn directly with that line (`clock_patch`)."""

from __future__ import annotations

import io
import json
from datetime import datetime

import numpy as np
import pytest
from PIL import Image
from support.feed import ByHand, Wire

from app.backdrops import LIVE, read_backdrop
from app.lockscreen import CLOCK_BOX, DEFAULT_MINUTE, clock_patch
from sim import Params
from sim.io.session import SessionLog
from sim.weather import Glass, Reading

STATIC = np.asarray(read_backdrop(LIVE))
X0, Y0, X1, Y1 = CLOCK_BOX


def stockholm(celsius: float) -> Reading:
    return Reading(place="Stockholm, Sweden", latitude=59.3, longitude=18.1,
                   temperature_c=celsius, humidity_pct=80.0, dew_point_c=-27.6, weather_code=3,
                   is_day=False, time="2026-11-26T23:00")


def texts(page) -> list[dict]:
    return [json.loads(m) for m, _end in page.queue if isinstance(m, str)]


def clock_pictures(page) -> list[np.ndarray]:
    from app.serve.protocol import CLOCK, decode_clock, message_type

    return [np.asarray(Image.open(io.BytesIO(decode_clock(m)["png"])).convert("RGB"))
            for m, _end in page.queue if isinstance(m, bytes) and message_type(m) == CLOCK]


def test_the_pages_are_told_the_weather_and_its_temperature_under_the_clock():
    from app.serve.feed import Feed
    from app.serve.pages import ConnectedPage
    from app.simthread.thread import SimThread

    params = Params.preset("window")  # (the weather sets the window frost's temperature)
    thread = SimThread(params, 1)
    thread.clock = lambda: datetime(2026, 11, 26, 9, 41, 5)
    feed = Feed(params, 1, backdrop=LIVE, thread=thread)
    page = ConnectedPage(Wire(), "page", feed.ask_redraw)
    page.waiting = False  # (live: it gets what is broadcast)
    feed.pages.add(page)
    by_hand = ByHand(thread)
    try:
        by_hand.tick(feed, 2)
        assert json.loads(feed.hello())["weather"] is None
        assert np.array_equal(clock_pictures(page)[-1], clock_patch(STATIC, DEFAULT_MINUTE))
        thread.show_weather(stockholm(-25.0), Glass())
        by_hand.tick(feed, 2)
    finally:
        by_hand.stop()
    told = {"place": "Stockholm, Sweden", "temperature_c": -25.0,
            "reading": "-25.0 C, 80 %, dew point -27.6 C at 23:00: glass -14 C, frost grows"}
    states = [t for t in texts(page) if t["type"] == "state" and "weather" in t]
    assert [s["weather"] for s in states] == [told]  # (once: at the change)
    assert json.loads(feed.hello())["weather"] == told  # a page that joins late
    # the clock box again, the temperature under the time
    assert np.array_equal(clock_pictures(page)[-1],
                          clock_patch(STATIC, DEFAULT_MINUTE, "-25 °C outside"))


@pytest.mark.gl
def test_a_replay_shows_the_temperature_outside_from_the_weather_events_tick(gl_ctx):
    from app.tools.replay import replay_offscreen

    event = {"tick": 20, "kind": "weather", "reading": stockholm(-12.4).as_json(),
             "glass": Glass().as_json()}
    log_ = SessionLog.from_json({
        "format": "frost-session", "version": 12, "seed": 2,
        "params": Params.preset("window").as_dict(), "steps": 30, "events": [event],
        "view": {"light": [0.4, 0.5, 1.0], "features": True, "bumps": True,
                 "background": LIVE}})
    shown = {}
    for ticks in (19, 21):
        offscreen = replay_offscreen(gl_ctx, log_, ticks)
        shown[ticks] = offscreen.frame()[Y0:Y1, X0:X1]
        offscreen.release()
    # (the window's first film dims the glass a little: the box is the drawn one but for it)
    bare = clock_patch(STATIC, DEFAULT_MINUTE).astype(int)
    told = clock_patch(STATIC, DEFAULT_MINUTE, "-12 °C outside").astype(int)

    def off(ticks: int, want: np.ndarray) -> float:
        return float(np.abs(shown[ticks].astype(int) - want).mean())

    assert off(19, bare) < off(19, told) / 5
    assert off(21, told) < off(21, bare) / 5
