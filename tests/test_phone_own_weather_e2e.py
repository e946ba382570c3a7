"""The phone's own weather and photo (issue 57, items 4 and 6), with no server: the
installed page of `frost serve`, reloaded after the server stopped, grows its own frost;
its "Weather where I am" asks a stand-in forecast API on loopback (answering with CORS,
as Open-Meteo does) from the page itself, its photo stays on the phone. Headless Chromium
with a persistent profile (the service worker), geolocation emulated, the permission
refused then granted. Oracles: sim/weather's glass model for the same reading, the place
rounded by hand, Pillow's upright cover of the same photo (app/photos.py, app/images.py)."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from PIL import Image
from support.phone import PROBLEM, open_page, persistent, pixels, wait_for_shell
from support.photos import exif_photo
from support.serve import phone_serve
from support.weather_api import StandIn

from app.images import cover
from app.photos import upright_rgb
from sim.screen import HEIGHT, WIDTH
from sim.weather import Reading, describe, frost_of

pytestmark = [pytest.mark.browser, pytest.mark.slow,
              pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

ON_PHONE = "on this phone"
STOCKHOLM = {"latitude": 59.33459, "longitude": 18.06324}  # as a phone reports it
PLACE = ("59.3", "18.1")  # rounded to 0.1 degree, by hand
REFUSED = "the browser refused the location: allow it for this page in its settings"


def status(page) -> str:
    return page.evaluate("document.getElementById('status').textContent")


def alone_again(page, api: StandIn) -> None:
    """Reloaded (the server long gone): growing its own frost, told the stand-in's address
    (as the static site's config names its API)."""
    page.reload()
    page.wait_for_function(f"window.frost && frost.local && frost.frames > 0 && "
                           f"document.getElementById('status').textContent === '{ON_PHONE}'",
                           timeout=60_000)
    page.evaluate("(url) => { frost.site = { weather_api: url }; }", api.url)


@pytest.fixture(scope="module")
def phone(pw, tmp_path_factory, subprocesses):
    """(context, page, stand-in API): the page of `frost serve`, installed, reloaded once
    the server stopped, on a phone at STOCKHOLM that has not been given the location."""
    folder = tmp_path_factory.mktemp("own-weather")
    s = phone_serve(folder)
    ctx = persistent(pw, folder / "profile", geolocation=STOCKHOLM)
    try:
        with StandIn(-25.0) as api:
            page = open_page(ctx, s.local)
            wait_for_shell(page)
            s.stop()
            alone_again(page, api)
            yield ctx, page, api
    finally:
        ctx.close()
        s.stop()


def watch_worker(page) -> None:
    """The weather messages the page posts to its worker, kept in `window.toWorker`."""
    page.evaluate("""() => {
        window.toWorker = [];
        const w = frost.alone.worker, post = w.postMessage.bind(w);
        w.postMessage = (m, ...rest) => {
            if (m.type === 'weather') window.toWorker.push(m);
            return post(m, ...rest);
        };
    }""")


def start(page, spec: str) -> bool:
    """startWeather(`spec`, JavaScript) as a ?weather= link calls it; whether a reading came."""
    return page.evaluate(f"import('./web/weather_local.js').then((m) => m.startWeather({spec}))")


def reading_line(temperature_c: float) -> str:
    """sim/weather's line of the stand-in's reading at `temperature_c`, as the page says it."""
    r = Reading("59.3, 18.1", 59.3, 18.1, temperature_c, 80.0, -27.6, 71, False, "2026-01-10T23:00")
    return "59.3, 18.1: " + describe(r).removeprefix("weather: ")


def test_the_weather_where_the_phone_is_asked_from_the_page(phone):
    ctx, page, api = phone
    # Refused: one line, and nothing asked of anyone.
    watch_worker(page)
    page.click("#open")
    page.click("#weather-here")
    page.wait_for_function("(w) => document.getElementById('status').textContent === w", arg=REFUSED)
    assert api.asked == [] and page.evaluate("window.toWorker") == []

    # Granted, at -25 C: the page asks the forecast API itself, for the place rounded to 0.1
    # degree, and the glass is sim/weather's.
    ctx.grant_permissions(["geolocation"])
    page.click("#weather-here")
    page.wait_for_function("frost.local && frost.local.weather && frost.local.weather.outside === -25",
                           timeout=30_000)
    (path, query), = api.asked
    assert path == "/v1/forecast" and (query["latitude"], query["longitude"]) == PLACE, query
    cold = frost_of(-25.0)
    weather = page.evaluate("frost.local.weather")
    assert weather["state"] == cold.state == "grows"
    assert abs(weather["glass"] - cold.glass_c) < 1e-9
    page.wait_for_function("window.toWorker.length === 1")
    message, = page.evaluate("window.toWorker")
    assert message["type"] == "weather" and abs(message["temperature"] - cold.temperature) < 1e-9
    assert message["supply"] == cold.supply
    assert status(page) == f"{ON_PHONE} · {reading_line(-25.0)}"
    kept = json.loads(page.evaluate("localStorage.getItem('frost-weather')"))
    assert kept["place"] == {"latitude": 59.3, "longitude": 18.1}
    assert kept["reading"]["temperature_c"] == -25 and kept["at"] > 0
    assert page.evaluate("import('./web/weather_local.js').then((m) => m.READ_MS)") == 15 * 60 * 1000

    # The next reading (the 15 minutes' own, asked now), at +6 C: a thaw.
    api.current["temperature_2m"] = 6.0
    assert page.evaluate("frost.localWeather.read()") is True
    weather, warm = page.evaluate("frost.local.weather"), frost_of(6.0)
    assert weather["state"] == warm.state == "melts" and abs(weather["glass"] - warm.glass_c) < 1e-9
    assert page.evaluate("window.toWorker")[-1] == {"type": "weather", "temperature": None,
                                                    "supply": warm.supply}
    assert status(page) == f"{ON_PHONE} · {reading_line(6.0)}"

    # The API failing: one line, and the frost goes on with the kept reading.
    api.mode = "500"
    assert page.evaluate("frost.localWeather.read()") is True
    line = status(page)
    assert line.startswith(f"weather: {api.url.removeprefix('http://')} answered HTTP 500") and \
        "the frost goes on with the reading of 23:00" in line and "\n" not in line, line
    api.mode = "ok"

    # Offline after a reload: the kept place's reading, said as kept; a place never read says
    # why there is none. The place went nowhere but to the API.
    asked = len(api.asked)
    ctx.set_offline(True)
    try:
        alone_again(page, api)
        got = start(page, "{lat: 59.33, lon: 18.07}")
        assert got is True and page.evaluate("frost.local.weather.state") == "melts"
        assert "(kept on this phone)" in status(page) and status(page).startswith("weather: cannot reach")
        got = start(page, "{lat: 10, lon: 10}")
        assert got is False and status(page) == f"weather: cannot reach {api.url.removeprefix('http://')}"
        bad = start(page, "{lat: 95, lon: 0}")
        assert bad is False and status(page).startswith("weather: a place is \"here\" or a latitude")
    finally:
        ctx.set_offline(False)
    assert len(api.asked) == asked


def test_a_photo_stays_on_the_phone_upright_and_offline(phone, tmp_path):
    ctx, page, api = phone
    sideways = tmp_path / "sideways.jpg"  # a landscape JPEG whose EXIF turns it upright
    sideways.write_bytes(exif_photo(6))
    want = np.asarray(cover(upright_rgb(Image.open(sideways)), (WIDTH, HEIGHT))).astype(int)
    unturned = np.asarray(cover(Image.open(sideways).convert("RGB"), (WIDTH, HEIGHT))).astype(int)
    assert np.abs(want - unturned).mean() > 40  # (the oracle tells the two apart)

    sent: list[str] = []
    page.on("request", lambda r: r.method != "GET" and sent.append(f"{r.method} {r.url}"))
    page.set_input_files("#photo-file", str(sideways))
    page.wait_for_function("frost.shownBackdrop === 'your photo' && !frost.photo.sending", timeout=30_000)
    assert page.evaluate("frost.photo.last")["local"] is True

    def shows_the_photo() -> None:
        got = pixels(page).astype(int)  # (the pane drawn with its backdrop texture; no ice)
        assert np.percentile(np.abs(got - want), 99) <= 12, np.percentile(np.abs(got - want), 99)

    shows_the_photo()
    Image.fromarray(pixels(page)).save(tmp_path / "photo-on-the-phone.png")
    ctx.set_offline(True)
    try:
        alone_again(page, api)
        page.wait_for_function("frost.shownBackdrop === 'your photo'", timeout=30_000)
        shows_the_photo()
    finally:
        ctx.set_offline(False)
    assert sent == []  # the photo went nowhere
    Image.open(io.BytesIO(page.screenshot())).save(tmp_path / "page.png")
