"""The static site of `frost web` (issue 57, items 1 and 5), end to end: built once for the
module with `frost web`, its parent folder served by a plain static server (the standard
library's, in a thread: no frost serve anywhere) so that the site lies under /frost/, and
opened by a 390x844 touch phone in headless Chromium. It grows its own frost at once and
asks no server anything; a tap grows frost; the deep links open it on a preset and hand
the weather on; the frosted window by a stand-in's weather frosts the pane at -25 C and
leaves it clear at +6 C; Chromium finds it installable; with the static server stopped it
opens from its worker's cache and grows frost; a site built again replaces it after one
reload, every file at once."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support.phone import BACKDROP, PHONE, PROBLEM, css_point, persistent, pixels, wait_for_shell
from support.static_site import SUB, StaticServer
from support.weather_api import StandIn

from app.cli.commands import main as frost
from app.resources import WEB_DIR
from app.tools.web_site import build

pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built by `frost web` into ROOT/frost, ROOT served, its weather API a
    stand-in's (at -25 C): (the server, the stand-in)."""
    root = tmp_path_factory.mktemp("static")
    with StandIn(-25.0) as api:
        assert frost(["web", str(root / SUB), "--weather-api", api.url]) == 0
        server = StaticServer(root)
        yield server, api
        server.stop()


def status(page) -> str:
    return page.evaluate("document.getElementById('status').textContent")


def watched(context, url: str):
    """A page of `url` whose failed requests and console errors are listed in `page.bad`."""
    page = context.new_page()
    page.bad = []
    page.on("console", lambda m: m.type == "error" and page.bad.append(m.text))
    page.on("response", lambda r: r.status >= 400 and page.bad.append(f"{r.status} {r.url}"))
    page.on("requestfailed", lambda r: page.bad.append(f"failed {r.url}"))
    page.goto(url)
    return page


def growing(page, ticks: int = 5) -> int:
    """Wait until the phone's own frost has ticked `ticks` (however slowly a loaded machine
    steps it); its tick."""
    page.wait_for_function(f"window.frost && frost.local && frost.local.tick >= {ticks} && frost.frames > 0",
                           timeout=60_000)
    return page.evaluate("frost.local.tick")


def tap_grows(page) -> None:
    """A tap at the pane's centre grows frost: crystals beyond the one seed it plants."""
    before = page.evaluate("frost.local.crystals")
    page.touchscreen.tap(*css_point(page, 380, 640))
    page.wait_for_function(f"frost.local.crystals >= {before} + 20", timeout=60_000)


def test_the_site_grows_frost_at_once_and_asks_no_server(site, browser, tmp_path):
    server, api = site
    context = browser.new_context(**PHONE)
    try:
        del server.paths[:]
        page = watched(context, server.url)
        growing(page)
        assert page.evaluate("frost.site.static") is True
        assert status(page) == ""  # (not "not reachable": nothing was tried)
        tap_grows(page)
        page.screenshot(path=str(tmp_path / "site.png"))
        assert page.bad == []
        asked = {p.split("?")[0] for p in server.paths}
        assert all(p.startswith(f"/{SUB}/") for p in asked), asked
        # no socket, no /meta, no /app.json: nothing a server of ours would answer
        assert not asked & {f"/{SUB}/{name}" for name in ("ws", "meta", "app.json", "photo", "weather")}
        assert page.evaluate("frost.hellos") == 0 and page.evaluate("frost.hello.local") is True
        assert api.asked == []  # (no weather unless asked)
    finally:
        context.close()


def test_deep_links_open_the_site_on_a_preset_and_the_weather_given(site, browser, tmp_path):
    """?preset=c-2 opens c-2; ?weather=LAT,LON reads the weather there from the site's API
    (the place rounded to 0.1 degree), ?weather=here where the phone is; bad values are one
    line in the status line, and the rest opens as without them."""
    server, api = site
    context = browser.new_context(**PHONE, geolocation={"latitude": 48.8566, "longitude": 2.3522},
                                  permissions=["geolocation"])
    try:
        page = watched(context, server.url + "?preset=c-2&weather=59.33,18.07")
        growing(page)
        shown = "[frost.hello.preset, document.getElementById('preset').value]"
        assert page.evaluate(shown) == ["c-2", "c-2"]
        page.wait_for_function("frost.local.weather && frost.local.weather.outside === -25", timeout=60_000)
        here = watched(context, server.url + "?weather=here")
        growing(here)
        here.wait_for_function("frost.local.weather && frost.local.weather.outside === -25", timeout=60_000)
        assert here.evaluate("frost.hello.preset") == "fern"
        asked = [(q["latitude"], q["longitude"]) for path, q in api.asked if path == "/v1/forecast"]
        assert asked == [("59.3", "18.1"), ("48.9", "2.4")]
        assert page.bad == [] and here.bad == []
        bad = watched(context, server.url + "?preset=nope&weather=91,18")
        growing(bad)
        bad.wait_for_function("document.getElementById('status').textContent !== ''", timeout=30_000)
        line = status(bad)
        assert "?preset=nope is no preset: one of " in line and "c-2" in line, line
        assert "?weather=91,18 is not a place" in line and "\n" not in line, line
        bad.screenshot(path=str(tmp_path / "bad-links.png"))
        assert bad.evaluate("frost.hello.preset") == "fern"  # (the rest opens as without them)
        assert len(api.asked) == 2  # (no weather asked for the bad place)
    finally:
        context.close()


# The frosted window by a night's weather (issue 57's Done when): the window preset, the
# weather at Stockholm (the stand-in at -25 C, then +6 C), 900 ticks. The frosted share is
# counted as tests/test_weather_render.py counts `frost render`'s: the pane's px where a
# channel differs by more than 12 from the bare pane, the dusk backdrop (which the page
# draws exactly where there is no ice), over the whole pane and over the part of it that
# the screen shows (the phone's narrower screen cuts off its sides), each held alike.
# `frost render --preset window --seed 2 --ticks 900 --weather 59.33,18.07` at -25 C covers
# 24.5 % so (docs/looks.md's 24 %; seeds 0 and 1: 26.5 and 27.9 %), and 0.0 % at +6 C; the
# page's seed is its own, so its share is held to the 12-40 %. The two pages grow
# at once (36 s at 25 ticks a second, about 12 s of CPU in all); the ticks' speed is
# printed, not held (bench/ holds it).
WINDOW_TICKS = 900
COLD_SHARE, WARM_SHARE = (0.12, 0.40), 0.02


def frosted(pane: np.ndarray) -> np.ndarray:
    """Where the pane is frosted (a mask of its px)."""
    return (np.abs(pane.astype(int) - BACKDROP) > 12).any(axis=2)


def on_screen(page) -> tuple[slice, slice]:
    """The rows and columns of the pane that the phone's screen shows (the pane covers the
    screen, its sides cut off on a phone narrower than it)."""
    r, (w, h) = page.evaluate("frost.paneCss()"), (PHONE["viewport"]["width"], PHONE["viewport"]["height"])
    return (slice(max(0, round(-r["y"] / r["sy"])), round((h - r["y"]) / r["sy"])),
            slice(max(0, round(-r["x"] / r["sx"])), round((w - r["x"]) / r["sx"])))


def pause_at(page, tick: int) -> int:
    """Pause the page's own frost once it has stepped `tick` ticks (as its menu's pause
    does: at the next tick or two, the stats coming every 5) and its frames have drawn
    them; the tick it stopped at."""
    page.wait_for_function(f"frost.local && frost.local.tick >= {tick} && "
                           "(frost.alone.send({type: 'pause'}), true)", timeout=240_000, polling=10)
    page.wait_for_function("frost.alone.stats.paused", timeout=30_000)
    page.wait_for_function("new Promise((done) => requestAnimationFrame(() => "
                           "requestAnimationFrame(() => done(true))))")
    return page.evaluate("frost.local.tick")


@pytest.mark.slow
def test_the_window_frosts_by_the_weather_read_on_the_page(site, browser, tmp_path):
    """?preset=window&weather=59.33,18.07: at -25 C the page's own frosted window covers
    12-40 % of the pane in 900 ticks, at +6 C (a second page, at the same time) at most 2 %."""
    server, api = site
    cold_ctx, warm_ctx = browser.new_context(**PHONE), browser.new_context(**PHONE)
    link = server.url + "?preset=window&weather=59.33,18.07"
    try:
        cold = watched(cold_ctx, link)
        cold.wait_for_function("frost.local && frost.local.weather && frost.local.weather.outside === -25",
                               timeout=60_000)
        api.current["temperature_2m"] = 6.0  # (the cold page read its weather: the warm one reads this)
        warm = watched(warm_ctx, link)
        warm.wait_for_function("frost.local && frost.local.weather && frost.local.weather.outside === 6",
                               timeout=60_000)
        read_at = [p.evaluate("frost.local.tick") for p in (cold, warm)]
        assert [p.evaluate("frost.hello.preset") for p in (cold, warm)] == ["window", "window"]
        assert warm.evaluate("frost.local.weather.state") == "melts"
        stopped = [pause_at(p, WINDOW_TICKS) for p in (cold, warm)]
        shares, screens = [], []
        for name, page in (("cold", cold), ("warm", warm)):
            pane = pixels(page)
            ice = frosted(pane)
            shares.append(float(ice.mean()))
            screens.append(float(ice[on_screen(page)].mean()))
            Image.fromarray(pane).save(tmp_path / f"window-{name}.png")
        p99 = [p.evaluate("frost.local.tickP99Ms") for p in (cold, warm)]
        print(f"the frosted window on the page: -25 C {shares[0]:.1%} of the pane ({screens[0]:.1%} "
              f"of what the screen shows), +6 C {shares[1]:.1%} ({screens[1]:.1%}) at ticks {stopped} "
              f"(the weather read at ticks {read_at}); frost.local.tickP99Ms {p99}")
        assert COLD_SHARE[0] <= min(shares[0], screens[0]) and max(shares[0], screens[0]) <= COLD_SHARE[1], \
            (shares, screens)
        assert max(shares[1], screens[1]) <= WARM_SHARE, (shares, screens)
        assert cold.bad == [] and warm.bad == []
    finally:
        api.current["temperature_2m"] = -25.0
        cold_ctx.close()
        warm_ctx.close()


MARKED = "globalThis.frostMarks = [...(globalThis.frostMarks || []), '{name}:{mark}'];\n"


def marked_web(folder: Path, mark: str) -> Path:
    """A copy of the page's folder whose every module, stylesheet and page says `mark`."""
    web = folder / "web"
    shutil.copytree(WEB_DIR, web, ignore=shutil.ignore_patterns("__pycache__"))
    for js in web.glob("*.js"):
        if js.name != "sw.js":
            js.write_text(js.read_text(encoding="utf-8") + MARKED.format(name=js.name, mark=mark),
                          encoding="utf-8")
    css = web / "page.css"
    css.write_text(css.read_text(encoding="utf-8") + f'\n:root {{ --frost-mark: "{mark}"; }}\n',
                   encoding="utf-8")
    page = web / "index.html"
    page.write_text(page.read_text(encoding="utf-8").replace(
        "<title>", f'<meta name="frost-mark" content="{mark}">\n<title>'), encoding="utf-8")
    return web


def versions(page) -> dict[str, str | None]:
    """Which build each module, the stylesheet and the page the page runs came from."""
    return page.evaluate("""() => {
        const found = {};
        for (const m of globalThis.frostMarks || []) {
            const [name, v] = m.split(':');
            found[name] = v;
        }
        found.css = getComputedStyle(document.documentElement).getPropertyValue('--frost-mark')
            .trim().replaceAll('"', '') || null;
        found.html = document.querySelector('meta[name=frost-mark]')?.content || null;
        return found;
    }""")


def build_hash(root: Path) -> str:
    return json.loads((root / SUB / "version.json").read_text(encoding="utf-8"))["build"]


def test_the_site_installs_opens_offline_and_a_new_build_replaces_it_whole(pw, tmp_path):
    """In a persistent profile (the worker and the installability check need one), on a
    site of its own (it is rebuilt): installable; the server stopped, a reload opens it
    from the cache and a tap grows frost; built again with every module changed, one
    reload runs the new build, every file of it, and so does a reload offline after."""
    root = tmp_path / "static"
    old = marked_web(tmp_path / "a", "A")
    build(root / SUB, "https://a.test", "https://a.test", web_dir=old)
    server = StaticServer(root)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = watched(ctx, server.url)
        growing(page)
        shell = versions(page)
        assert {"main.js", "alone.js", "links.js", "css", "html"} <= set(shell), shell
        assert set(shell.values()) == {"A"}, shell
        assert page.evaluate("frost.site.weather_api") == "https://a.test"  # (site.js: the build's own)
        wait_for_shell(page, build_hash(root))
        cdp = ctx.new_cdp_session(page)
        assert cdp.send("Page.getInstallabilityErrors")["installabilityErrors"] == []
        cdp.detach()
        server.stop()
        page.reload()  # no server at all: the page, its modules, shaders and simulation from the cache
        growing(page)
        assert versions(page) == shell
        tap_grows(page)
        new = marked_web(tmp_path / "b", "B")
        build(root / SUB, "https://b.test", "https://b.test", web_dir=new)
        server.start()
        page.reload()  # one reload: the new build, whole
        growing(page)
        assert versions(page) == dict.fromkeys(shell, "B")
        assert page.evaluate("frost.site.weather_api") == "https://b.test"
        wait_for_shell(page, build_hash(root))  # the new worker's cache replaced A's
        server.stop()
        page.reload()  # and what opens without the server is B, whole
        growing(page)
        assert versions(page) == dict.fromkeys(shell, "B")
        tap_grows(page)
    finally:
        ctx.close()
        if server.http:
            server.http.server_close()

