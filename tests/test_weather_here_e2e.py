"""The phone's "Weather where I am" end to end: `frost serve` in a subprocess, pages in
headless Chromium with Playwright's geolocation emulation (the permission granted or
not). Oracles: the place the server moved its weather to (rounded by hand), the status
line's words, and that a page that may not ask sends nothing."""

from __future__ import annotations

import socket
import time
from pathlib import Path

import pytest
from support.https import browser_problem, trusting_chromium, trusting_home
from support.phone import PHONE, open_page
from support.serve import lan_serve

PROBLEM = browser_problem()
pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

STOCKHOLM = {"latitude": 59.33459, "longitude": 18.06324}  # as a phone reports it


class Phones:
    """Pages of the LAN server `s`'s HTTPS address in a Chromium that trusts its authority
    (a secure context, as on a phone that installed it: the Geolocation API is there), the
    address's name resolved to this machine."""

    def __init__(self, pw, s, config: Path, home: Path):
        """`config`: the server's config folder (its authority's certificate)."""
        self.s, self.name = s, socket.gethostname().lower()
        cafile = config / "frost" / "ca.crt"
        self.browser = trusting_chromium(pw, trusting_home(home, cafile), self.name)

    def open(self, granted: bool, where=STOCKHOLM):
        """A page on an emulated phone at `where`, the location permission `granted` or not."""
        context = self.browser.new_context(**PHONE, geolocation=where,
                                           permissions=["geolocation"] if granted else [])
        page = open_page(context, f"https://{self.name}:{self.s.https_port}/?token={self.s.token}")
        assert page.evaluate("window.isSecureContext") is True
        return page

    def close(self) -> None:
        self.browser.close()


def tap_weather_here(page) -> dict:
    """The menu's "Weather where I am" tapped; how it went (frost.weather.last)."""
    watch_status(page)
    page.click("#open")
    page.click("#weather-here")
    page.wait_for_function("frost.weather.last && !frost.weather.asking", timeout=30_000)
    return page.evaluate("frost.weather.last")


def tap_until_taken(page, within: float = 30.0) -> dict:
    """The menu's button tapped until the server takes the place (it takes one every few
    seconds from an address: a 429 says to try again), at most `within` s."""
    end = time.monotonic() + within
    while True:
        page.click("#open")  # (closed again: the next tap opens it)
        last = tap_weather_here(page)
        if last["status"] != 429 or time.monotonic() > end:
            return last


def status_starts(page, words: str) -> None:
    """Wait until the page's status line starts with `words` (at most 30 s)."""
    page.wait_for_function("(words) => document.getElementById('status').textContent"
                           ".startsWith(words)", arg=words, timeout=30_000)


def watch_status(page) -> None:
    """Keep each text the status line shows from now on (`window.said`): a notice goes
    after a few seconds, and the test reads what was said whenever it comes to it."""
    page.evaluate("""() => {
        window.said = [];
        const line = document.getElementById('status');
        new MutationObserver(() => window.said.push(line.textContent))
            .observe(line, { childList: true, characterData: true, subtree: true });
    }""")


def said(page) -> list[str]:
    return page.evaluate("window.said")


@pytest.mark.usefixtures("subprocesses")
def test_a_place_refused_by_the_browser_or_the_server_says_why(pw, tmp_path):
    s = lan_serve(tmp_path / "config")  # (no --weather: the server refuses a place)
    phones = Phones(pw, s, tmp_path / "config", tmp_path / "home")
    try:
        page = phones.open(granted=False)
        last = tap_weather_here(page)
        assert last["status"] == 0 and "refused the location" in last["error"]
        assert any("refused the location" in text for text in said(page))
        page = phones.open(granted=True)
        last = tap_weather_here(page)
        assert last["status"] == 503 and "--weather" in last["error"]
        assert any(text.startswith("weather refused: this server follows no weather")
                   for text in said(page))
    finally:
        phones.close()
        s.stop()


@pytest.mark.slow
@pytest.mark.usefixtures("subprocesses")
def test_the_place_of_a_phone_moves_everyones_weather_and_is_kept_rounded_alone(pw, browser,
                                                                               tmp_path):
    """A phone at Stockholm taps "Weather where I am": the weather API is asked at 59.3,
    18.1 (rounded to 0.1 degree by hand), every page's status line and state follow the new
    reading, and neither the session nor the config folder hold the place any closer. An
    API failing at the new place is said on every page, and the frost keeps its reading."""
    import json

    from support.weather_api import StandIn

    config, sessions = tmp_path / "config", tmp_path / "sessions"
    with StandIn(temperature_c=-25.0) as api:
        s = lan_serve(config, "--preset", "window", "--session-dir", str(sessions),
                      "--weather", "59.91,10.75", "--weather-api", api.url,
                      "--geocoding-api", api.url)
        phones = Phones(pw, s, config, tmp_path / "home")
        try:
            other = phones.open(granted=False)  # (a page that never asks)
            other.wait_for_function("frost.hello.weather && frost.hello.weather.temperature_c === -25",
                                    timeout=30_000)
            # (once the reading's own line, a notice for a few seconds, has gone)
            status_starts(other, "59.91,10.75: -25.0 C, 80 %")
            page = phones.open(granted=True)
            sent: list = []
            page.on("request", lambda r: r.method == "POST" and sent.append(r.post_data))
            # The API fails at the new place: every page is told, the frost goes on at -25.
            api.mode = "500"
            watch_status(other)
            assert tap_weather_here(page)["status"] == 202
            for p in (page, other):
                p.wait_for_function("window.said.some((text) => text.includes('HTTP 500'))",
                                    timeout=30_000)
                assert p.evaluate("frost.hello.weather.temperature_c") == -25
            api.mode, api.current["temperature_2m"] = "ok", 6.0
            last = tap_until_taken(page)
            assert last == {"status": 202, "latitude": 59.3, "longitude": 18.1}
            assert len(sent) >= 2  # (each tap's body: the rounded place, nothing more)
            assert all(json.loads(body) == {"latitude": 59.3, "longitude": 18.1} for body in sent)
            for p in (page, other):
                p.wait_for_function("frost.hello.weather.temperature_c === 6", timeout=30_000)
                status_starts(p, "59.30,18.10: 6.0 C, 80 %")
            forecasts = [q for path, q in api.asked if path == "/v1/forecast"]
            assert (forecasts[-1]["latitude"], forecasts[-1]["longitude"]) in {
                ("59.3", "18.1"), ("59.30", "18.10")}
        finally:
            phones.close()
            s.stop()
    # What was kept: the rounded place in the session's weather events and with the reading
    # in the config folder; the phone's own figures nowhere.
    [session] = sessions.glob("*.json")
    events = [e for e in json.loads(session.read_text(encoding="utf-8"))["events"]
              if e["kind"] == "weather"]
    assert [(e["reading"]["latitude"], e["reading"]["longitude"]) for e in events][-1] == (59.3, 18.1)
    for path in [*sessions.rglob("*"), *config.rglob("*")]:
        if path.is_file():
            data = path.read_bytes()
            assert b"59.33" not in data and b"18.06" not in data, path


def test_a_plain_http_page_says_it_needs_the_https_page(browser):
    """A page on a plain HTTP address that is not this machine's (http://frost.test) is no
    secure context: the tap asks nothing and sends nothing, and says why."""
    from bench.page import Page, hello
    from sim import Params

    with Page(hello(Params.preset("fern")), [], viewport=(390, 844), scale=3, browser=browser,
              touch=True) as p:
        asked = []
        p.page.on("request", lambda r: r.method == "POST" and asked.append(r.url))
        assert p.page.evaluate("window.isSecureContext") is False
        last = tap_weather_here(p.page)
        assert last["status"] == 0 and "needs the HTTPS page" in last["error"]
        assert any("needs the HTTPS page" in text for text in said(p.page))
        assert asked == []
