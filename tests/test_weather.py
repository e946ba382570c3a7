"""The weather outside (issue 48): the glass model against hand-worked cases, the reading's
checks, and the client, the kept reading and the feed against a stand-in for Open-Meteo's
two APIs (support.weather_api): no network needed."""

from __future__ import annotations

import asyncio
import math
import re
import threading

import aiohttp
import pytest
import support.weather_api as weather_api
from support.cli import assert_refused_in_one_line, run_main
from support.weather_api import StandIn

from app.weather.client import MOST_BYTES, WeatherError, coordinates, current, find
from app.weather.feed import Asker, WeatherFeed, read_once
from app.weather.kept import kept
from sim.weather import Frost, Glass, Reading, describe, frost_of, glass_temperature
from sim.weather.glass import ICE, dew_point, frost_point, saturation

WAIT_S = 30.0  # bounds a failure only
STOCKHOLM = Reading("59.33,18.07", 59.33, 18.07, -25.0, 80.0, -27.6, 71, False,
                    "2026-01-10T23:00")


# ---- the glass model: hand-worked -------------------------------------------------------

@pytest.mark.parametrize("outside, glazing, glass", [
    (-25.0, "single", 20 - 5.8 * 0.13 * 45),  # 20 - 0.754 x 45 = -13.93
    (6.0, "single", 20 - 5.8 * 0.13 * 14),  # +9.44
    (20.0, "single", 20.0),  # no difference, no flow
    (-35.0, "double", 20 - 2.8 * 0.13 * 55)])  # -0.02: double glazing's 0 C
def test_the_glass_sits_between_the_room_and_the_night(outside, glazing, glass):
    assert glass_temperature(outside, 20.0, glazing) == pytest.approx(glass, abs=1e-9)


def test_single_glazing_freezes_below_about_minus_6_5_and_double_below_about_minus_35():
    assert glass_temperature(-6.4) > 0 > glass_temperature(-6.7)
    assert glass_temperature(-34.5, glazing="double") > 0 > glass_temperature(-35.5, glazing="double")
    assert round(glass_temperature(-25.0)) == -14 and round(glass_temperature(6.0)) == 9


def test_the_stated_room_has_a_dew_point_of_6_c_and_its_frost_point_solves_magnus_over_ice():
    assert dew_point(20.0, 40.0) == pytest.approx(6.0, abs=0.05)
    # The frost point by bisection on the saturation curve over ice (the obvious way).
    for room, rh in ((20.0, 40.0), (20.0, 10.0), (15.0, 5.0)):
        want, lo, hi = rh / 100 * saturation(room), -80.0, 30.0
        for _ in range(100):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if saturation(mid, ICE) < want else (lo, mid)
        assert frost_point(room, rh) == pytest.approx(lo, abs=1e-6)


def test_what_the_glass_does_to_the_frost():
    cold = frost_of(-25.0)
    assert (cold.state, cold.thaw, cold.supply) == ("grows", False, 1.0)
    assert cold.temperature == pytest.approx(-(20 - 0.754 * 45))  # the glass's 13.93 below 0
    assert frost_of(6.0) == Frost(pytest.approx(9.444), "melts", None, 1.0)
    assert frost_of(6.0).thaw and frost_of(-6.0).state == "melts"
    # A dry room: 10 % of 23.37 hPa is 2.337 hPa, which ice holds at 272.62 ln(2.337 / 6.112)
    # / (22.46 - ln(2.337 / 6.112)) = -11.2 C; glass at -4 C lies below 0 but above it.
    dry = Glass(room_humidity=10.0)
    assert frost_point(20.0, 10.0) == pytest.approx(-11.2, abs=0.05)
    assert frost_of(-12.0, dry).state == "fades" and frost_of(-12.0, dry).thaw
    far = frost_of(-40.0, dry)  # glass -25.2: 14.0 below the frost point
    assert far.state == "grows"
    assert far.temperature == pytest.approx(frost_point(20.0, 10.0) - glass_temperature(-40.0))
    # The supply: the room's vapour against the stated room's (10 % of 40 %: at its floor).
    assert far.supply == 0.25 and frost_of(-25.0, Glass(room_humidity=60.0)).supply == 1.5
    # Just below the onset it grows, at the knob's floor; at -80 C the knob's ceiling.
    assert frost_of(-6.7).temperature == 0.5 and frost_of(-80.0).temperature == 40.0


def test_the_line_says_what_was_read_and_what_it_does_in_ascii():
    assert describe(STOCKHOLM) == ("weather: -25.0 C, 80 %, dew point -27.6 C at 23:00: "
                                   "glass -14 C, frost grows")
    warm = Reading.from_json({**STOCKHOLM.as_json(), "temperature_c": 6.0, "dew_point_c": 2.0})
    assert describe(warm).endswith("dew point 2.0 C at 23:00: glass 9 C, frost melts")
    zero = Reading.from_json({**STOCKHOLM.as_json(), "temperature_c": -0.04, "dew_point_c": -0.01})
    assert describe(zero).startswith("weather: 0.0 C, 80 %, dew point 0.0 C")  # never "-0.0"
    assert describe(STOCKHOLM).isascii()


STATED = Glass()  # single glazing, the room at 20 C and 40 %


def outside_for(glass_c: float, glass: Glass = STATED) -> float:
    """By hand: the outside temperature that puts `glass`'s inner surface at `glass_c`
    (room - U R_si (room - outside) solved for outside)."""
    u = {"single": 5.8, "double": 2.8}[glass.glazing]
    return glass.room_c - (glass.room_c - glass_c) / (u * 0.13)


GLASS_SAID = re.compile(r".*: glass (just below |just above )?(-?\d+(?:\.\d)?) C, frost (\w+).*")


def test_the_glass_near_0_c_never_reads_across_0_from_what_the_frost_does():
    # Hand-worked: -7 C outside on single glazing is glass 20 - 0.754 x 27 = -0.358 C, below
    # the stated room's onset (0 C: its frost point, 5.6 C, lies above): it grows.
    def said(glass_c: float, glass: Glass = STATED) -> str:
        reading = Reading.from_json({**STOCKHOLM.as_json(), "temperature_c": outside_for(glass_c, glass)})
        return describe(reading, glass).split(": ", 2)[2]
    assert said(-0.358) == "glass -0.4 C, frost grows"
    assert said(0.396) == "glass 0.4 C, frost melts"
    assert said(-0.004) == "glass just below 0 C, frost grows"
    assert said(0.02) == "glass just above 0 C, frost melts"
    assert said(0.0) == "glass 0 C, frost melts"  # (0 C is the thaw's: at or above)
    assert said(-0.6) == "glass -1 C, frost grows" and said(0.6) == "glass 1 C, frost melts"
    # Swept: every glass from -2 to +2 C in steps of 0.001 C (single, double, a dry room's
    # fade), the printed temperature on the side of 0 C its state says.
    for glass in (STATED, Glass("double"), Glass(room_humidity=10.0)):
        for step in range(-2000, 2001):
            line = describe(Reading.from_json({**STOCKHOLM.as_json(), "temperature_c":
                                               outside_for(step / 1000, glass)}), glass)
            near, value, state = GLASS_SAID.fullmatch(line).groups()
            shown = float(value) * (-1 if near == "just below " else 1)
            g = frost_of(outside_for(step / 1000, glass), glass).glass_c
            assert (shown < 0 or near == "just below ") if state in ("grows", "fades") \
                else (shown > 0 or near == "just above " or g == 0), line


def test_a_reading_goes_to_json_and_back_and_a_bad_one_is_one_line():
    assert Reading.from_json(STOCKHOLM.as_json()) == STOCKHOLM
    full = Reading(**{**STOCKHOLM.as_json(), "wind_speed_kmh": 11.2, "apparent_c": -31.4,
                      "cloud_pct": 100.0})
    assert Reading.from_json(full.as_json()) == full
    for change, words in [({"temperature_c": "cold"}, "temperature_c"),
                          ({"humidity_pct": 120}, "humidity_pct"),
                          ({"time": "23:00"}, "YYYY-MM-DDTHH:MM"),
                          ({"is_day": 1}, "is_day"), ({"weather_code": 1.5}, "weather_code"),
                          ({"place": "a\nb"}, "place"), ({"latitude": math.nan}, "latitude"),
                          ({"pressure": 1013}, "'pressure'")]:
        with pytest.raises(ValueError) as err:
            Reading.from_json({**STOCKHOLM.as_json(), **change})
        assert words in str(err.value) and "\n" not in str(err.value)


# ---- the client against the stand-in ------------------------------------------------------

def ask(coroutine_of_session):
    """Run one request (a function of an aiohttp session) to its end."""
    async def run():
        async with aiohttp.ClientSession() as session:
            return await coroutine_of_session(session)
    return asyncio.run(run())


def test_the_current_conditions_read_from_the_forecast_api():
    with StandIn() as api:
        reading = ask(lambda s: current(s, api.url, coordinates("59.333, 18.0666")))
        path, query = api.asked[0]
    assert reading == Reading("59.33,18.07", 59.33, 18.07, -25.0, 80.0, -27.6, 71, False,
                              "2026-01-10T23:00", 11.2, -31.4, 100.0)
    assert path == "/v1/forecast" and (query["latitude"], query["longitude"]) == ("59.33", "18.07")
    assert query["current"].split(",")[:5] == ["temperature_2m", "relative_humidity_2m",
                                               "dew_point_2m", "weather_code", "is_day"]


def test_lat_lon_is_never_geocoded_and_a_name_is_with_its_first_match(tmp_path):
    with StandIn() as api:
        said: list[str] = []
        asker = Asker("59.33,18.07", said.append, api.url, api.url, tmp_path)
        assert asyncio.run(asker.ask()).temperature_c == -25.0
        assert api.paths() == ["/v1/forecast"]  # no /v1/search
        oslo = Asker("Oslo", said.append, api.url, api.url, tmp_path)
        assert asyncio.run(oslo.ask()).place == "Oslo, Norway"
        assert api.paths()[1:] == ["/v1/search", "/v1/forecast"]
        assert api.asked[1][1]["name"] == "Oslo"
        assert (api.asked[2][1]["latitude"], api.asked[2][1]["longitude"]) == ("59.91", "10.75")
        asyncio.run(oslo.ask())  # the place is looked up once a run
        assert api.paths()[3:] == ["/v1/forecast"]
    assert said == ["weather: Oslo, Norway (59.91, 10.75)"]


@pytest.mark.parametrize("mode, words", [
    ("429", "too many requests (HTTP 429)"), ("500", "HTTP 500"),
    ("slow", "did not answer within 0.5 s"), ("garbage", "not JSON"),
    ("missing", "lacks dew_point_2m")])
def test_each_failure_of_the_api_is_one_line_naming_its_cause(mode, words):
    with StandIn() as api:
        api.mode = mode
        with pytest.raises(WeatherError) as err:
            ask(lambda s: current(s, api.url, coordinates("59.33,18.07"), timeout_s=0.5))
    assert words in str(err.value) and "127.0.0.1" in str(err.value), err.value
    assert "\n" not in str(err.value)


def test_a_reply_in_pieces_is_read_to_its_end():
    # A forecast sent in three pieces, 0.3 s apart: the reading of a reply in one piece.
    with StandIn() as api:
        whole = ask(lambda s: current(s, api.url, coordinates("59.33,18.07")))
        api.mode = "pieces"
        pieces = ask(lambda s: current(s, api.url, coordinates("59.33,18.07")))
    assert pieces == whole and pieces.temperature_c == -25.0


@pytest.mark.parametrize("mode, size", [("huge", "5,000,000 bytes"),
                                        ("huge-chunked", "more than 1,048,576 bytes")])
def test_a_reply_over_the_limit_is_said_too_large(mode, size):
    # 5 MB of valid JSON, its length said before it comes or not (chunked).
    with StandIn() as api:
        api.mode = mode
        with pytest.raises(WeatherError) as err:
            ask(lambda s: current(s, api.url, coordinates("59.33,18.07")))
    assert re.fullmatch(rf"127\.0\.0\.1:\d+ answered {size}: too large for the API's JSON "
                        r"\(at most 1,048,576\)", str(err.value)), err.value


def test_a_place_not_found_and_an_api_not_reached_are_one_line_each():
    with StandIn() as api:
        none = r"^no place called 'Atlantis' \(127\.0\.0\.1:\d+ found none\)$"
        with pytest.raises(WeatherError, match=none):
            ask(lambda s: find(s, api.url, "Atlantis"))
        closed = api.url
    with pytest.raises(WeatherError, match=r"^cannot reach 127\.0\.0\.1:\d+: Connection refused$"):
        ask(lambda s: current(s, closed, coordinates("59.33,18.07")))


NUMBER_LIKE = ["91,10", "1e3,5", "nan,nan", "inf,0", " 91 , 0", "-inf,-inf", "0,1e3",
               "10,nan", "Infinity,0"]


def test_a_place_off_the_globe_is_refused_before_any_request():
    assert coordinates("Oslo") is None and coordinates("1,2,3") is None
    assert coordinates("Nan, Thailand") is None and coordinates("Paris, France") is None
    # Whatever Python reads as two numbers is coordinates, on the globe or refused.
    assert coordinates("1e1,5") == coordinates("10,5.0") == coordinates(" +10.0 , 5 ")
    assert coordinates("-33.87,151.21").longitude == 151.21  # (Sydney: east of 90)
    for text in NUMBER_LIKE:
        with pytest.raises(ValueError, match="latitude must be in"):
            coordinates(text)


@pytest.mark.parametrize("text", NUMBER_LIKE)
def test_a_place_that_reads_as_two_numbers_is_never_geocoded(text, monkeypatch):
    # frost render --weather TEXT: refused in one line at once, the geocoder never asked
    # (the command stands in for the render: it asks the weather as a render does).
    from app.cli import commands
    from app.weather.feed import first_event
    monkeypatch.setitem(commands.RUN, "render", lambda args, _params: len(first_event(args, print)))
    with StandIn() as api:
        status, err = run_main(["render", "--weather", text, "--weather-api", api.url,
                                "--geocoding-api", api.url])
        assert api.asked == []
    assert_refused_in_one_line(status, err, "latitude must be in [-90, 90]")


def test_a_place_geocoded_anywhere_on_the_globe_is_taken_and_one_off_it_refused():
    # Tokyo lies east of 90 degrees: a latitude's bound on its longitude would refuse it.
    with StandIn() as api:
        tokyo = ask(lambda s: find(s, api.url, "Tokyo"))
        sydney = ask(lambda s: find(s, api.url, "Sydney"))
        with pytest.raises(WeatherError, match="'Nowhere' lies off the globe"):
            ask(lambda s: find(s, api.url, "Nowhere"))  # latitude 95, longitude 10
    assert (tokyo.name, tokyo.latitude, tokyo.longitude) == ("Tokyo, Japan", 35.69, 139.69)
    assert (sydney.latitude, sydney.longitude) == (-33.87, 151.21)


# ---- the kept reading ------------------------------------------------------------------

def test_a_failure_goes_on_with_the_reading_kept_for_that_place_in_one_line(tmp_path):
    said: list[str] = []
    with StandIn() as api:
        assert asyncio.run(Asker("59.33,18.07", said.append, api.url, api.url, tmp_path).ask())
        api.mode = "500"
        again = Asker("59.33,18.07", said.append, api.url, api.url, tmp_path)
        assert asyncio.run(again.ask()) == kept("59.33,18.07", tmp_path)[0]
        assert asyncio.run(again.ask()) is None  # once a run: then the last reading stays
        elsewhere = Asker("60.00,18.07", said.append, api.url, api.url, tmp_path)
        assert asyncio.run(elsewhere.ask()) is None  # another place's reading is not this one's
    assert said[0].startswith("weather: 127.0.0.1:")
    assert "HTTP 500 Internal Server Error: going on with the reading kept from 20" in said[0]
    assert said[1].endswith("HTTP 500 Internal Server Error: the frost goes on with the last reading")
    assert said[2].endswith("HTTP 500 Internal Server Error: the frost grows by the preset's own "
                            "temperature")
    assert len(said) == 3


def test_a_batch_that_falls_back_on_the_kept_reading_says_so_in_one_line(tmp_path, monkeypatch):
    from types import SimpleNamespace

    from app.weather.feed import first_event
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    said: list[str] = []
    with StandIn() as api:
        args = SimpleNamespace(weather="59.33,18.07", weather_api=api.url, geocoding_api=api.url,
                               glazing="single", room_temperature=20.0, room_humidity=40.0)
        assert len(first_event(args, said.append)) == 1  # read and kept
        closed = api.url
    args.weather_api = closed  # nothing answers there now
    events = first_event(args, said.append)
    assert len(said) == 2 and events[0]["reading"]["temperature_c"] == -25.0
    # The failure, the kept reading's time and what it reads, on one line.
    assert re.fullmatch(r"weather: cannot reach 127\.0\.0\.1:\d+: Connection refused: going on with "
                        r"the reading kept from 20\S+: -25\.0 C, 80 %, .*glass -14 C, frost grows",
                        said[1]), said[1]


def test_a_kept_file_that_is_not_a_reading_is_said_and_ignored(tmp_path, caplog):
    (tmp_path / "weather.json").write_text("{not json", encoding="utf-8")
    assert kept("59.33,18.07", tmp_path) is None
    (tmp_path / "weather.json").write_text('{"asked": "59.33,18.07", "reading": {"place": 3}}',
                                           encoding="utf-8")
    assert kept("59.33,18.07", tmp_path) is None
    assert [r.getMessage().count("\n") for r in caplog.records] == [0, 0]


def test_a_batch_waits_at_most_its_limit_for_the_first_reading(tmp_path):
    said: list[str] = []
    with StandIn() as api:
        api.mode = "slow"
        assert read_once(Asker("59.33,18.07", said.append, api.url, api.url, tmp_path), 0.5) is None
    assert said == ["weather: no reading within 0.5 s: the frost grows by the preset's own "
                    "temperature"]


# ---- the feed ----------------------------------------------------------------------------

def test_the_feed_reads_at_the_start_again_when_asked_and_at_a_new_place(tmp_path):
    readings: list[Reading] = []
    came = threading.Event()

    def on_reading(reading: Reading) -> None:
        readings.append(reading)
        came.set()

    with StandIn() as api:
        feed = WeatherFeed.at_place("59.33,18.07", on_reading, print, api=api.url,
                                    geocoding_api=api.url, folder=tmp_path).start()
        try:
            assert came.wait(WAIT_S)
            came.clear()
            api.current["temperature_2m"] = 3.5
            feed.set_place(48.8566, 2.3522)  # the phone's place: asked at once
            assert came.wait(WAIT_S)
        finally:
            feed.stop()
        assert not feed._thread.is_alive()
        assert [(q["latitude"], q["longitude"]) for _p, q in api.asked] == [
            ("59.33", "18.07"), ("48.86", "2.35")]
    assert [(r.place, r.temperature_c) for r in readings] == [("59.33,18.07", -25.0),
                                                              ("48.86,2.35", 3.5)]


def moved_while_asking(api: StandIn, asker: Asker, latitude: float, longitude: float,
                       then: str = "ok"):
    """`asker.ask()`, the place moved while the stand-in holds its answer back (then
    answered in the mode `then`)."""
    async def run():
        api.mode = "slow"
        task = asyncio.create_task(asker.ask())
        assert await asyncio.to_thread(api.arrived.wait, WAIT_S)
        asker.move(latitude, longitude)  # (on the asking loop, as the feed's _move is)
        api.mode = then
        api.release()
        return await task
    api.arrived.clear()
    return asyncio.run(run())


def test_a_reading_is_kept_and_used_only_for_the_place_it_was_asked_for(tmp_path):
    said: list[str] = []
    with StandIn() as api:
        asker = Asker("59.33,18.07", said.append, api.url, api.url, tmp_path)
        assert moved_while_asking(api, asker, 48.8566, 2.3522) is None  # Stockholm's, dropped
        assert kept("48.86,2.35", tmp_path) is None and kept("59.33,18.07", tmp_path) is None
        api.mode = "500"
        assert asyncio.run(asker.ask()) is None  # nothing had: the preset's temperature
        api.mode = "ok"
        paris = asyncio.run(asker.ask())
        # A name moved from while it is looked up: its match is dropped, the move stands.
        named = Asker("Oslo", said.append, api.url, api.url, tmp_path)
        assert moved_while_asking(api, named, 35.6895, 139.69171) is None
        tokyo = asyncio.run(named.ask())
        # A failure at the place moved from is not said: the new place is asked at once.
        assert moved_while_asking(api, named, 59.33, 18.07, then="500") is None
        asked = [(q.get("name"), q.get("latitude"), q.get("longitude")) for _p, q in api.asked]
    assert (paris.place, paris.latitude, paris.longitude) == ("48.86,2.35", 48.86, 2.35)
    assert kept("48.86,2.35", tmp_path) is None  # (the file holds the last place's: Tokyo's)
    assert (tokyo.place, tokyo.latitude, tokyo.longitude) == ("35.69,139.69", 35.69, 139.69)
    assert kept("35.69,139.69", tmp_path)[0] == tokyo
    assert asked == [(None, "59.33", "18.07"), (None, "48.86", "2.35"), (None, "48.86", "2.35"),
                     ("Oslo", None, None), (None, "35.69", "139.69"), (None, "35.69", "139.69")]
    assert said == ["weather: 127.0.0.1:{} answered HTTP 500 Internal Server Error: the frost "
                    "grows by the preset's own temperature".format(api.url.rsplit(":", 1)[1])]


def test_a_failure_after_a_move_says_the_frost_goes_on_with_the_last_reading(tmp_path):
    said: list[str] = []
    with StandIn() as api:
        asker = Asker("59.33,18.07", said.append, api.url, api.url, tmp_path)
        assert asyncio.run(asker.ask()).place == "59.33,18.07"  # what the frost grows by
        asker.move(48.8566, 2.3522)
        api.mode = "500"
        assert asyncio.run(asker.ask()) is None  # (the frost keeps Stockholm's reading)
        api.mode = "ok"
        assert asyncio.run(asker.ask()).place == "48.86,2.35"
        api.mode = "500"
        assert asyncio.run(asker.ask()) is None
    assert [line.split("Error: ")[1] for line in said] == [
        "the frost goes on with the last reading, of 59.33,18.07",
        "the frost goes on with the last reading"]


def test_the_feed_refuses_to_ask_more_often_than_every_5_minutes():
    with pytest.raises(ValueError, match="at least 5 minutes"):
        WeatherFeed.at_place("59.33,18.07", print, print, every_min=4.9)


def test_a_stopped_feed_gives_up_a_slow_request_at_once(tmp_path):
    with StandIn() as api:
        api.mode = "slow"
        feed = WeatherFeed.at_place("59.33,18.07", print, print, api=api.url, folder=tmp_path).start()
        assert api.arrived.wait(WAIT_S)  # the request under way, its answer held back
        feed.stop(wait_s=WAIT_S)
        assert not feed._thread.is_alive() and not api.answered.is_set()


# ---- the command line ------------------------------------------------------------------

@pytest.mark.parametrize("argv, words", [
    (["render", "--weather", "91,10"], "latitude must be in [-90, 90]"),
    (["render", "--weather", ""], "must be LAT,LON or a place's name"),
    (["render", "--weather", "Oslo", "--weather-api", "ftp://mirror"], "must be an http:// or https:// URL"),
    (["render", "--weather", "Oslo", "--weather-api", "https://"], "https:// URL with a host"),
    (["render", "--weather", "Oslo", "--geocoding-api", "http://"], "'http://' must be an http://"),
    (["render", "--weather", "Oslo", "--weather-api", "https://api.open-meteo.com\t"],
     "must be an http:// or https:// URL"),  # (urlsplit drops the tab: a host, unprintable)
    (["render", "--weather", "Oslo", "--glazing", "triple"], "invalid choice: 'triple'"),
    (["render", "--weather", "Oslo", "--room-humidity", "0"], "room humidity '0' must be a number in [1, 1"),
    (["serve", "--weather", "Oslo", "--weather-every", "4"], "'4' must be a number in [5, 1440]"),
    (["render", "--weather-every", "15"], "unrecognized arguments: --weather-every")])
def test_a_bad_weather_option_is_refused_in_one_line(argv, words, monkeypatch):
    from app.cli import commands
    ran: list[str] = []  # (a command let through runs no render here: it says so)
    for command in ("render", "serve"):
        monkeypatch.setitem(commands.RUN, command, lambda args, _params: ran.append(args.command) or 0)
    status, err = run_main(argv)
    assert_refused_in_one_line(status, err, words)
    assert ran == []


@pytest.mark.parametrize("mode", ["huge", "huge-chunked"])
def test_a_reply_of_exactly_the_limit_is_read_and_one_byte_more_is_not(mode, monkeypatch):
    # MOST_BYTES (1 048 576) of valid JSON, its length said or chunked: read; one byte more
    # (the stand-in's padding one longer) is too large.
    with StandIn() as api:
        api.mode = mode
        monkeypatch.setattr(weather_api, "HUGE_BYTES", MOST_BYTES)
        reading = ask(lambda s: current(s, api.url, coordinates("59.33,18.07")))
        assert reading.temperature_c == -25.0
        monkeypatch.setattr(weather_api, "HUGE_BYTES", MOST_BYTES + 1)
        with pytest.raises(WeatherError, match="too large for the API's JSON"):
            ask(lambda s: current(s, api.url, coordinates("59.33,18.07")))


def test_a_place_rounded_to_0_is_named_without_a_minus_sign():
    # -0.001 rounds to -0.0 at 2 decimals: named and sent as 0.00, never "-0.00".
    place = coordinates("-0.001,-0.004")
    assert place.name == "0.00,0.00" and place.words() == "0.00,0.00 (0.00, 0.00)"
    assert math.copysign(1.0, place.latitude) == 1.0 == math.copysign(1.0, place.longitude)
