"""The phone page through the shaping proxy (`python -m bench page --network`): `frost serve`
on loopback, the proxy in front of it, the page on an emulated phone in headless Chromium.
The proxy forwards bytes unchanged, so the page's requests name the proxy's address in
Host and Origin (127.0.0.1, the proxy's port), which a loopback server accepts: the page
loads, its socket opens and syncs, a ping's pong takes at least the link's round trip less
its jitter, a tap draws growth, and every byte went through the proxy. No speed is held,
only that lower bound."""

from __future__ import annotations

import pytest
from support.phone import launch_browser

from bench.chromium import browser_problem
from bench.network import PINGS, Phone, css_point, served
from bench.shaper import PROFILES

PROBLEM = browser_problem()
pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]


@pytest.mark.usefixtures("subprocesses")
def test_the_page_works_through_the_shaper():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw, served("fern", PROFILES["4g"]) as s:
        assert s.shaper is not None and f":{s.shaper.port}/" in s.url and s.url != s.server
        browser = launch_browser(pw)
        try:
            with Phone(browser, cpu_slowdown=2) as phone:
                page = phone.page
                phone.open(s.url)
                socket = page.evaluate("frost.socket.url")
                assert socket.startswith(f"ws://127.0.0.1:{s.shaper.port}/ws")
                # A ping's pong crossed the link both ways: at least twice its delay less
                # its jitter (a lower bound: load only adds).
                link = PROFILES["4g"]
                pings = page.evaluate(PINGS, 5)
                assert len(pings) == 5 and min(pings) >= 2e3 * (link.delay - link.jitter)
                page.touchscreen.tap(*css_point(page, 380, 640))
                page.wait_for_function("frost.latencies.length >= 1", timeout=120_000)
                meta = page.evaluate("fetch('meta').then((r) => r.status)")
                assert meta == 200
                assert page.evaluate("frost.hellos") == 1  # never refused, never reconnected
                assert page.evaluate("__probe.ticks.length") > 0  # the probe saw the messages
        finally:
            browser.close()
        shaper = s.shaper.shaper
        assert shaper.down_bytes > page_bytes_floor() and shaper.up_bytes > 0


def page_bytes_floor() -> int:
    """The page's own files alone weigh more than this (its HTML and modules)."""
    from app.resources import WEB_DIR

    return sum(f.stat().st_size for f in WEB_DIR.glob("*.js"))


def command_line(browser) -> list[str]:
    """The switches `browser` was started with, as it reports them (chrome://version)."""
    page = browser.new_page()
    try:
        page.goto("chrome://version")
        return page.evaluate("document.getElementById('command_line').textContent").split()
    finally:
        page.close()


def popups(browser) -> list[str]:
    """The address bar popups (WebUI pages) the browser holds once a new window is open."""
    context = browser.new_context()
    try:
        context.new_page().goto("about:blank")
        session = browser.new_browser_cdp_session()
        targets = session.send("Target.getTargets")["targetInfos"]
        session.detach()
        return [t["url"] for t in targets if "omnibox-popup" in t["url"]]
    finally:
        context.close()


def test_the_bench_browser_keeps_playwrights_switches_and_has_no_address_bar_popup():
    """Chromium keeps only the last --disable-features: the bench's browser is given one,
    with every name Playwright's own had (read here from a browser started as Playwright
    starts it) and the two popups' features, and it renders no popup."""
    from playwright.sync_api import sync_playwright

    from bench.chromium import CHROMIUM, QUIET_FEATURES

    def disabled(switches: list[str]) -> list[list[str]]:
        return [s.split("=", 1)[1].split(",") for s in switches if s.startswith("--disable-features=")]

    with sync_playwright() as pw:
        plain = pw.chromium.launch(executable_path=CHROMIUM, headless=True)
        try:
            (playwrights,) = disabled(command_line(plain))
        finally:
            plain.close()
        browser = launch_browser(pw)
        try:
            (ours,) = disabled(command_line(browser))
            assert set(playwrights) | set(QUIET_FEATURES) == set(ours)
            assert popups(browser) == []
        finally:
            browser.close()


@pytest.mark.usefixtures("subprocesses")
def test_the_page_asks_for_its_shaders_with_its_modules_and_once():
    """Each shader file programs.js loads is asked for by index.html's preload, while the
    modules load (initiator "link", not main.js's fetch), and once: its fetch takes the
    preloaded response (a mismatched preload is fetched twice)."""
    import json
    import re

    from playwright.sync_api import sync_playwright

    from app.resources import WEB_DIR

    shaders = json.loads(re.search(r"export const SHADERS = (\[.*?\]);",
                                   (WEB_DIR / "programs.js").read_text(encoding="utf-8"), re.S).group(1))
    with sync_playwright() as pw, served("fern") as s:
        browser = launch_browser(pw)
        try:
            with Phone(browser) as phone:
                phone.open(s.url)
                entries = phone.page.evaluate(
                    "performance.getEntriesByType('resource').map((e) => [e.name, e.initiatorType])")
        finally:
            browser.close()
    asked: dict[str, list[str]] = {}
    for url, initiator in entries:
        found = re.search(r"/shaders/([^/?]+)", url)
        if found:
            asked.setdefault(found.group(1), []).append(initiator)
    assert asked == {name: ["link"] for name in shaders}
