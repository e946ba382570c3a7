"""The phone page in WebKit, the engine of every browser on an iPhone: WebKitWebDriver and
WebKitGTK's MiniBrowser under Xvfb (support.webkit), one session for the module. A click
on `frost serve`'s page grows frost (the page's own height grid, and the pixels WebKit
shows); with the server stopped, the reloaded page (its service worker's) grows its own
frost, and its tick figures read sensibly on WebKit's clock, coarsened to 1 ms as Safari's
is. The static site of `frost web` on a plain static server: ?preset=window grows the
frosted window at once, and with the server stopped the reloaded site (its service
worker's) grows frost under a click."""

from __future__ import annotations

import base64
import math

import numpy as np
import pytest
from PIL import Image
from support.static_site import SUB, StaticServer
from support.weather_api import StandIn
from support.webkit import webkit_problem

from app.backdrops import load_backdrop
from app.tools.web_site import build
from sim.screen import HEIGHT, WIDTH

pytestmark = pytest.mark.skipif(webkit_problem() is not None, reason=str(webkit_problem()))

ON_PHONE = "on this phone"
STATUS = "document.getElementById('status').textContent"
# sim/'s crystals after 100 ticks of one touch at the pane's centre, seeds 1-3 (fern): the
# median, and the factor the phone's may differ by (as tests/test_phone_alone_e2e.py's).
SIM_MEDIAN, FACTOR = 366, 1.5
TAP = (380, 640)  # the pane's px (its centre)
# The page's ice where its height grid holds it: vertices above zero within `r` px of (x, y)
# (pane px) and beyond.
ICED = """((x, y, r) => {
  const h = frost.renderer.heights, [cols] = h.gridSize, s = h.spacing;
  let near = 0, far = 0;
  h.grid.forEach((v, i) => {
    if (v <= 0) return;
    if (Math.hypot((i % cols) * s - x, Math.floor(i / cols) * s - y) <= r) near += 1; else far += 1;
  });
  return [near, far];
})"""


def viewport_point(webkit, x: float, y: float) -> tuple[float, float]:
    """CSS px of the viewport of the pane's px (x, y)."""
    r = webkit.js("frost.paneCss()")
    return r["x"] + x * r["sx"], r["y"] + y * r["sy"]


def boxes(shot: np.ndarray, at: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The screenshot's 80 x 80 CSS px around `at`, and 60 x 60 at the left, an eighth
    down (far from it: some 550 pane px from the pane's centre, away from the menu's button)."""
    cx, cy = round(at[0]), round(at[1])
    top = shot.shape[0] // 8
    return (shot[cy - 40:cy + 40, cx - 40:cx + 40].astype(int),
            shot[top:top + 60, 5:65].astype(int))


def frost_under(before: np.ndarray, after: np.ndarray, at) -> None:
    """Frost grew in the screenshots around `at`, and nothing changed far from it."""
    near0, far0 = boxes(before, at)
    near1, far1 = boxes(after, at)
    changed = np.abs(near1 - near0).max(axis=2) > 40
    assert changed.mean() > 0.05, f"no frost grew under the click: {changed.mean():.3f}"
    assert np.abs(far1 - far0).max() == 0, "the pane changed far from the click"


def test_a_click_grows_frost_on_the_served_page(serve, webkit):
    s = serve()
    webkit.open(s.local)
    webkit.wait_for("window.frost && (frost.error || (frost.synced && frost.frames > 0 && "
                    "frost.shownBackdrop))", what="window.frost && [frost.synced, frost.frames]")
    assert webkit.js("frost.error") is None
    assert webkit.js("frost.hello.local") is not True  # the server's frost, not the phone's
    assert webkit.js(f"{ICED}({TAP[0]}, {TAP[1]}, 500)") == [0, 0]  # a blank pane
    at = viewport_point(webkit, *TAP)
    before = webkit.screenshot()
    tick = webkit.js("frost.tick")
    webkit.click(*at)
    webkit.wait_for(f"frost.tick >= {tick + 50}", timeout=120)  # two seconds of frost
    near, far = webkit.js(f"{ICED}({TAP[0]}, {TAP[1]}, 500)")
    assert near >= 50 and far == 0, (near, far)
    webkit.wait_for("new Promise((done) => requestAnimationFrame(() => "
                    "requestAnimationFrame(() => done(true))))")  # (the last ticks drawn)
    frost_under(before, webkit.screenshot(), at)


def test_with_the_server_gone_the_reloaded_page_grows_its_own_frost(serve, webkit):
    s = serve()
    webkit.open(s.local)
    webkit.wait_for("window.frost && frost.synced && frost.frames > 0")
    # its service worker in control, the shell cached
    webkit.wait_for("navigator.serviceWorker.controller !== null && caches.keys().then((k) => "
                    "k.some((n) => n.startsWith('frost-shell-')))", timeout=60)
    s.stop()
    webkit.reload()  # no server: the page, its modules, its worker's from the cache
    webkit.wait_for(f"window.frost && frost.local && frost.frames > 0 && {STATUS} === {ON_PHONE!r}",
                    what=f"window.frost && [{STATUS}, frost.error, frost.frames]")
    assert webkit.js("frost.error") is None and webkit.js("frost.hello.local") is True
    assert webkit.js("frost.local.crystals") == 0
    at = viewport_point(webkit, *TAP)
    before = webkit.screenshot()
    tick = webkit.js("frost.local.tick")
    webkit.click(*at)
    webkit.wait_for(f"frost.local.tick >= {tick + 100}", timeout=120)
    local = webkit.js("frost.local")
    stats = webkit.js("frost.alone.stats")
    # (the stats come every 5 ticks, the click lands a tick or two late: a few ticks either side)
    assert SIM_MEDIAN / FACTOR <= local["crystals"] <= SIM_MEDIAN * FACTOR, local
    # The tick figures on a clock of whole milliseconds (WebKit's, as Safari's): durations
    # in whole ms (but for the doubles' rounding), and the frost's ticks take some (a p99 of
    # 0 would say the clock read nothing).
    p99, median = local["tickP99Ms"], stats["tickMedianMs"]
    assert 0 < p99 < math.inf and abs(p99 - round(p99)) < 1e-6 and 0 <= median <= p99, stats
    assert local["ticksPerSecond"] > 0, local
    webkit.wait_for("new Promise((done) => requestAnimationFrame(() => "
                    "requestAnimationFrame(() => done(true))))")
    frost_under(before, webkit.screenshot(), at)
    print(f"benchmark: WebKit, the phone's own frost: {local['ticksPerSecond']} ticks/s, "
          f"tick p99 {p99} ms, median {median} ms, {local['crystals']} crystals at tick {local['tick']}")


DUSK = load_backdrop("dusk").astype(int)  # the bare pane (the window preset's backdrop)


def frosted(webkit) -> float:
    """The share of the pane's px that differ from the bare pane by more than 12 in a
    channel (as tests/test_site_e2e.py counts the frosted window), read from the page's
    WebGL (frost.framePixels)."""
    raw = base64.b64decode(webkit.js("frost.framePixels()"))
    pane = np.frombuffer(raw, np.uint8).reshape(HEIGHT, WIDTH, 4)[:, :, :3].astype(int)
    return float((np.abs(pane - DUSK) > 12).any(axis=2).mean())


def test_the_static_site_grows_the_frosted_window_and_opens_offline(webkit, tmp_path):
    """The site of `frost web` on a plain static server (support.static_site), the forecast
    API a stand-in at -25 C: ?preset=window&weather=59.33,18.07 reads the weather on the page
    and grows the frosted window at once (its crystals and frosted share rise over 100
    ticks); with the server stopped, the site reloaded (its service worker's) grows frost under a
    click. The click is the fern's (the site's own preset), whose frost grows only where a
    touch puts it: the window's fronds grow everywhere by themselves."""
    root = tmp_path / "static"
    with StandIn(-25.0) as api:  # the forecast API, answering the page itself (with CORS)
        build(root / SUB, api.url, api.url)
        server = StaticServer(root)
        try:
            grows_the_window_by_the_weather(webkit, server, api, tmp_path)
        finally:
            server.stop()
    webkit.reload()  # no server: the site from its worker's cache
    webkit.wait_for("window.frost && frost.local && frost.local.tick >= 5 && frost.frames > 0",
                    timeout=120, what=f"window.frost && [{STATUS}, frost.error, frost.local]")
    assert webkit.js("frost.error") is None and webkit.js("frost.hello.preset") == "fern"
    assert webkit.js("navigator.serviceWorker.controller !== null")
    at = viewport_point(webkit, *TAP)
    before, crystals = webkit.screenshot(), webkit.js("frost.local.crystals")
    webkit.click(*at)
    webkit.wait_for(f"frost.local.crystals >= {crystals + 20}", timeout=120)
    webkit.wait_for("new Promise((done) => requestAnimationFrame(() => "
                    "requestAnimationFrame(() => done(true))))")
    after = webkit.screenshot()
    Image.fromarray(after).save(tmp_path / "webkit-offline-click.png")
    frost_under(before, after, at)
    print(f"WebKit offline: {crystals} crystals before the click, {webkit.js('frost.local')}")


def grows_the_window_by_the_weather(webkit, server, api, tmp_path) -> None:
    """?preset=window&weather=59.33,18.07 on the static site: the page reads the stand-in's
    -25 C itself and the window grows by it (crystals and frosted share rising over 100
    ticks); then the plain site (the fern) with its service worker in control."""
    webkit.open(server.url + "?preset=window&weather=59.33,18.07")
    webkit.wait_for("window.frost && frost.local && frost.local.tick >= 25 && frost.frames > 0 "
                    "&& frost.local.weather && frost.local.weather.outside === -25",
                    timeout=120, what=f"window.frost && [{STATUS}, frost.error, frost.local]")
    assert webkit.js("frost.error") is None and webkit.js("frost.site.static") is True
    assert webkit.js("frost.hello.preset") == "window"
    weather = webkit.js("frost.local.weather")
    assert weather["state"] == "grows" and weather["outside"] == -25.0, weather
    asked = [(q["latitude"], q["longitude"]) for path, q in api.asked if path == "/v1/forecast"]
    assert asked == [("59.3", "18.1")], api.asked  # (the place rounded to 0.1 degree)

    first = webkit.js("frost.local")
    share = frosted(webkit)
    webkit.wait_for(f"frost.local.tick >= {first['tick'] + 100}", timeout=120)
    later = webkit.js("frost.local")
    share_later = frosted(webkit)
    Image.fromarray(webkit.screenshot()).save(tmp_path / "webkit-window.png")
    print(f"WebKit, the frosted window on the static site: {first['crystals']} crystals, "
          f"{share:.1%} frosted at tick {first['tick']}; {later['crystals']}, {share_later:.1%} "
          f"at tick {later['tick']}; tick p99 {later['tickP99Ms']} ms")
    assert first["crystals"] > 0 and later["crystals"] > first["crystals"] + 100, (first, later)
    assert share_later > share + 0.01, (share, share_later)
    # its service worker in control, the shell cached
    webkit.wait_for("navigator.serviceWorker.controller !== null && caches.keys().then((k) => "
                    "k.some((n) => n.startsWith('frost-shell-')))", timeout=60)
    webkit.open(server.url)  # (the fern: its frost grows only where a click puts it)
    webkit.wait_for("window.frost && frost.local && frost.frames > 0")
