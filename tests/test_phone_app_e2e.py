"""The page as a phone app, end to end (`frost serve` in a subprocess, the page in headless
Chromium on emulated phones): the pane covers the screen and a tap lands on the pane px
under it (the oracle: the touch the session file records, against the cover maths worked
here by hand), or whole and letterboxed when the menu says so; tilt (a DeviceOrientation
override over CDP) turns this page's light alone; the screen's wake lock follows
visibility and the connection; a tap's first frost buzzes unless switched off. And the
tilt maths (app/web/tilt.js) against hand-worked cases."""

from __future__ import annotations

import io
import json
import math
import time
from urllib.request import urlopen

import numpy as np
import pytest
from PIL import Image
from support.phone import BACKDROP, PHONE, grown, open_page, pause_and_settle, pixels, synced

from bench.page import Page, browser_problem, hello
from sim import Params

PROBLEM = browser_problem()
pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

PANE = (760, 1280)
WHOLE_PANE = "localStorage.setItem('frost.fit', 'pane')"
# navigator.vibrate as a recorder (a headless page has no motor to ask).
VIBRATE = ("Object.defineProperty(Navigator.prototype, 'vibrate', {configurable: true,"
           " value: function (ms) { (window.buzzes ||= []).push(ms); return true; }})")


@pytest.fixture
def phones(browser, serve):
    """Opens pages on emulated phones (`viewport` CSS px, 3 device px each), an init
    script run before the page's own if given; closed before the server stops."""
    contexts = []

    def open_(url: str, viewport=(390, 844), init: str | None = None):
        context = browser.new_context(**{**PHONE, "viewport": {"width": viewport[0], "height": viewport[1]}})
        contexts.append(context)
        if init:
            context.add_init_script(init)
        return open_page(context, url)

    yield open_
    for context in contexts:
        context.close()


def cover(w: int, h: int, whole: bool = False) -> tuple[float, float, float]:
    """(scale, x, y): a pane px's size on a w x h device-px canvas and where the pane's
    corner lies, worked by hand: covering (or, `whole`, fitting) and centred."""
    scale = (min if whole else max)(w / PANE[0], h / PANE[1])
    return scale, (w - PANE[0] * scale) / 2, (h - PANE[1] * scale) / 2


def screen(page) -> np.ndarray:
    """What the screen shows, device px, H x W x 3."""
    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB")).astype(int)


def session_touches(tmp_path) -> list[tuple[float, float]]:
    files = sorted(tmp_path.glob("session-*.json"))
    assert files
    events = json.loads(files[-1].read_text(encoding="utf-8"))["events"]
    return [(e["x"], e["y"]) for e in events if e["kind"] == "touch"]


@pytest.mark.parametrize("viewport, whole", [((390, 844), False), ((390, 844), True), ((844, 390), False)],
                         ids=["portrait-fill", "portrait-whole-pane", "landscape-fill"])
def test_the_pane_covers_the_screen_and_a_tap_lands_under_the_finger(serve, phones, tmp_path, viewport,
                                                                     whole):
    s = serve()
    page = phones(s.local, viewport, WHOLE_PANE if whole else None)
    w, h = viewport[0] * 3, viewport[1] * 3
    scale, x0, y0 = cover(w, h, whole)
    shot = screen(page)
    assert shot.shape == (h, w, 3)
    black = shot.max(axis=2) < 8  # the backdrop (dusk) has no px this dark
    for cy, cx in ((2, 2), (2, w - 3), (h - 3, 2), (h - 3, w - 3)):  # the screen's corners
        px, py = (cx + 0.5 - x0) / scale, (cy + 0.5 - y0) / scale
        on_pane = 0 <= px < PANE[0] and 0 <= py < PANE[1]
        assert on_pane == (not whole)
        if on_pane:  # the backdrop's px there (linear filtering: within a few levels)
            assert np.abs(shot[cy, cx] - BACKDROP[int(py), int(px)]).max() <= 12, (cx, cy)
        else:
            assert black[cy, cx], (cx, cy)
    if whole:  # the letterbox: the bars above and below and nothing else
        assert abs(black.mean() - (1 - PANE[1] * scale / h)) < 0.005
    else:
        assert black.mean() == 0
    # Taps at screen points (CSS px) off the centre, one near a corner of the screen.
    taps = [(viewport[0] * 0.3, viewport[1] * 0.6), (14, viewport[1] - 14)]
    if whole:
        taps[1] = (viewport[0] - 12, (y0 + 40 * scale) / 3)  # on the pane, near its top (below the menu)
    for x, y in taps:
        page.touchscreen.tap(x, y)
        page.wait_for_timeout(400)
    page.wait_for_function("frost.frostLatencies.length >= 2", timeout=30_000)
    page.context.close()
    s.stop()
    got = session_touches(tmp_path)
    assert len(got) == 2, got
    for (x, y), (gx, gy) in zip(taps, got, strict=True):
        # The tap's device px centre, through the crop, in pane px. The page's canvas has a
        # px for each pane px (the screen has more) and whole, even sizes: stretched over
        # the screen by less than a px, the pane centred to half a px. So the touch is
        # within a pane px of the point worked by hand.
        ex, ey = (x * 3 - x0) / scale, (y * 3 - y0) / scale
        assert abs(gx - ex) <= 1.0 and abs(gy - ey) <= 1.0, ((gx, gy), (ex, ey))


def test_a_tap_by_each_corner_of_the_screen_is_a_touch_there_in_meta(serve, browser):
    """A 390x844 phone at 1 device px a CSS px: a tap 10 px in from each corner of the
    screen is a touch that `/meta` states at the pane px under it (the top right one fell
    in the menu button's square and reached nothing)."""
    s = serve()
    meta = f"http://127.0.0.1:{s.port}/meta"
    context = browser.new_context(**{**PHONE, "device_scale_factor": 1})
    corners = [(10, 10), (380, 10), (10, 834), (380, 834)]
    try:
        page = open_page(context, s.local)
        for i, (x, y) in enumerate(corners):
            page.touchscreen.tap(x, y)
            deadline = time.monotonic() + 30
            while len(touches := json.loads(urlopen(meta, timeout=10).read())["touches"]) <= i:
                assert time.monotonic() < deadline, f"no touch for the tap at {(x, y)}: {touches}"
                page.wait_for_timeout(100)
    finally:
        context.close()
    scale, x0, y0 = cover(390, 844)
    assert len(touches) == 4, touches
    for (x, y), (_tick, gx, gy) in zip(corners, touches, strict=True):
        # (within a pane px: the canvas's pane is centred to the whole px)
        ex, ey = (x - x0) / scale, (y - y0) / scale
        assert abs(gx - ex) <= 1.0 and abs(gy - ey) <= 1.0, ((gx, gy), (ex, ey))


def test_the_menu_remembers_whole_pane(serve, phones):
    s = serve()
    page = phones(s.local)
    assert abs(page.evaluate("frost.paneCss().h") - 844) < 0.01  # the screen's height
    page.click("#open")
    page.check("#whole")
    page.wait_for_function("Math.abs(frost.paneCss().w - 390) < 0.01")  # the screen's width
    page.reload()
    synced(page, "frost.frames > 0")
    assert page.is_checked("#whole")
    assert abs(page.evaluate("frost.paneCss()")["w"] - 390) < 0.01
    assert (screen(page).max(axis=2) < 8).mean() > 0.15  # the bars


def test_the_screenshot_saves_what_the_screen_shows(serve, phones):
    """In fill mode the menu's screenshot is the part of the pane on the screen, in pane px,
    its place on the pane in the metadata."""
    s = serve()
    page = phones(s.local)
    png = bytes(page.evaluate("async () => Array.from(await frost.screenshotPng())"))
    with Image.open(io.BytesIO(png)) as im:
        shot, text = np.asarray(im.convert("RGB")), dict(im.text)
    scale, x0, _ = cover(1170, 2532)
    left = math.floor(-x0 / scale)  # 84.2 pane px cropped each side
    assert shot.shape == (1280, PANE[0] - 2 * left, 3)
    assert json.loads(text["view"])["crop"] == [left, 0, PANE[0] - 2 * left, 1280]
    assert {"parameters", "seed", "tick", "touches", "Software", "Creation Time", "view"} == set(text)
    assert np.array_equal(shot, pixels(page)[:, left:PANE[0] - left])


def _tilt(cdp, beta: float, gamma: float = 0.0) -> None:
    cdp.send("DeviceOrientation.setDeviceOrientationOverride", {"alpha": 0, "beta": beta, "gamma": gamma})


def test_tilt_turns_this_pages_light_alone(serve, phones):
    s = serve()
    a, b = phones(s.local), phones(s.local)
    for x, y in ((0.3, 0.4), (0.6, 0.6)):
        a.touchscreen.tap(390 * x, 844 * y)
    grown(a, 62)
    pause_and_settle([a, b])
    light = a.evaluate("frost.renderer.light")
    before_a, before_b = pixels(a), pixels(b)
    cdp = a.context.new_cdp_session(a)
    _tilt(cdp, 50)  # the rest pose (a phone held up)
    a.wait_for_function("frost.phone.tilt.rest && frost.phone.tilt.rest.beta === 50")
    _tilt(cdp, 5)  # its top lowered 45 degrees
    a.wait_for_function("frost.phone.tilt.drawn[1] === -45 && !frost.renderer.damage.any", timeout=30_000)
    turned = a.evaluate("frost.renderer.light")
    # The light turned 45 degrees about the screen's x axis toward its bottom (+y), the
    # server's kept as it was.
    x, y, z = (c / math.hypot(*light) for c in light)
    k = math.sqrt(0.5)  # cos 45 = sin 45
    assert np.allclose(turned, [x, y * k + z * k, -y * k + z * k], atol=1e-12)
    assert turned[1] > 0 > light[1]
    assert a.evaluate("frost.serverLight") == light
    after_a, after_b = pixels(a), pixels(b)
    ice = np.abs(before_a - BACKDROP).max(axis=2) > 0
    changed = np.abs(after_a.astype(int) - before_a).max(axis=2) > 0
    assert ice.mean() > 0.01
    assert changed[ice].mean() > 0.5, changed[ice].mean()
    # Clear glass: a px and its 8 neighbours all the backdrop's (the edge of thin ice may
    # shade to the backdrop's colour in one light and not in another).
    near = np.pad(ice, 1)
    near = np.any([near[1 + dy:near.shape[0] - 1 + dy, 1 + dx:near.shape[1] - 1 + dx]
                   for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
    assert not changed[~near].any()  # clear glass unchanged
    a.evaluate("frost.renderer.damageAll()")  # the ice's tiles alone drew what a whole frame draws
    assert np.array_equal(pixels(a), after_a)
    assert np.array_equal(after_b, before_b)  # the other page keeps its light
    assert b.evaluate("frost.renderer.light") == light
    # Back to the rest pose: the light comes back to the server's, the frame as before.
    _tilt(cdp, 50)
    a.wait_for_function("frost.phone.tilt.drawn[1] === 0 && !frost.renderer.damage.any", timeout=30_000)
    assert np.array_equal(pixels(a), before_a)


def test_the_tilt_switch_turns_it_off_and_a_plain_http_page_says_why(serve, phones, browser):
    s = serve()
    page = phones(s.local)
    cdp = page.context.new_cdp_session(page)
    page.click("#open")
    page.uncheck("#tilt")
    _tilt(cdp, 10)
    _tilt(cdp, 40)
    page.wait_for_timeout(500)
    assert page.evaluate("frost.renderer.light") == page.evaluate("frost.serverLight")
    assert page.is_hidden("#tilt-why")
    page.reload()  # remembered
    synced(page)
    assert not page.is_checked("#tilt")
    # A page on a plain HTTP address that is not this machine's (http://frost.test) is no
    # secure context: no tilt, and the menu says why.
    with Page(hello(Params.preset("fern")), [], viewport=(390, 844), scale=3, browser=browser,
              touch=True) as p:
        assert p.page.evaluate("window.isSecureContext") is False
        p.page.click("#open")
        assert p.page.is_disabled("#tilt") and not p.page.is_checked("#tilt")
        assert "HTTPS" in p.page.inner_text("#tilt-why")
        cdp = p.context.new_cdp_session(p.page)
        _tilt(cdp, 10)
        _tilt(cdp, 50)
        p.page.wait_for_timeout(300)
        assert p.page.evaluate("frost.renderer.light") == p.page.evaluate("frost.serverLight")


def test_tilt_maths_against_hand_worked_cases(browser):
    with Page(hello(Params.preset("fern")), [], viewport=(390, 844), scale=3, browser=browser) as p:
        got = p.page.evaluate("""async () => {
            const t = await import("./web/tilt.js");
            const rest = { beta: 0, gamma: 0 };
            const f = new t.LowPass(40);
            f.step([0], 0);
            const lp = [f.step([1], 40)[0], f.step([1], 40)[0]];
            return {
              up: t.screenTilt(30, 0, rest, 0), left: t.screenTilt(0, 20, rest, 0),
              landUp: t.screenTilt(30, 0, rest, 90), landGamma: t.screenTilt(0, 20, rest, 90),
              wrap: t.screenTilt(-170, 0, { beta: 170, gamma: 0 }, 0),
              cone: t.screenTilt(60, 0, rest, 0), both: t.screenTilt(45, 45, rest, 0),
              upright: t.screenTilt(90, 30, { beta: 90, gamma: 0 }, 0),
              back: t.screenTilt(60, 0, { beta: 90, gamma: 0 }, 0),
              upVector: t.upVector(90, 0),
              right30: t.tiltLight([0, 0, 1], [30, 0]), up30: t.tiltLight([0, 0, 2], [0, 30]),
              flat: t.tiltLight([0, 0, 1], [0, 90]), lp };
        }""")
    close = lambda a, b: np.allclose(a, b, atol=1e-12)  # noqa: E731
    assert close(got["up"], [0, 30])          # top lifted: the light toward the top
    assert close(got["left"], [-20, 0])       # right edge down (gamma +): toward the left
    assert close(got["landUp"], [-30, 0])     # screen turned 90 (top to the left): the top is left
    assert close(got["landGamma"], [0, -20])  # and the phone's right edge the screen's top
    assert close(got["wrap"], [0, 20])        # -170 is 20 past 170
    assert close(got["cone"], [0, 45])        # 60 degrees: held to 45
    # top up 45 and right edge down 45: up is (-1/2, 1/sqrt 2, 1/2) on the phone, 60 degrees
    # from the rest's (0, 0, 1) about (-1/sqrt 2, -1/2, 0): held to 45, split 1 : sqrt 2
    assert close(got["both"], [-45 / math.sqrt(3), 45 * math.sqrt(2 / 3)])
    # held upright, a turn about the vertical (gamma, at beta 90) moves nothing (beta and
    # gamma taken as angles, it read as a tilt of 30, and gamma is unsteady there)
    assert close(got["upright"], [0, 0])
    assert close(got["back"], [0, -30])       # upright, the top tipped 30 away: toward the bottom
    assert close(got["upVector"], [0, 1, math.cos(math.pi / 2)])
    h = math.sqrt(3) / 2
    assert close(got["right30"], [0.5, 0, h]) and close(got["up30"], [0, -0.5, h])
    assert close(got["flat"], [0, -math.sin(math.radians(75)), math.cos(math.radians(75))])
    assert close(got["lp"], [1 - math.exp(-1), 1 - math.exp(-2)])


def test_the_tilt_snaps_to_its_target_only_once_within_a_quarter_step(browser):
    """The drawn tilt follows the low-pass (each step of TAU * ln 10 ms leaves a tenth of
    the way) and takes the target exactly only once it is within STEP_DEG / 4 of it: 0.1
    degree off is drawn as it is, 0.01 off snaps to the target; then nothing changes."""
    with Page(hello(Params.preset("fern")), [], browser=browser) as p:
        got = p.page.evaluate("""async () => {
            const t = await import("./web/tilt.js");
            const tilt = new t.Tilt({});
            let target = [0, 0];
            tilt.target = () => target;
            const step = t.TAU_MS * Math.log(10), base = [0, 0, 1], out = [];
            tilt.light(base, 0);  // the filter starts at rest
            target = [1, 0];
            for (let k = 1; k <= 3; k++) {
              const { changed } = tilt.light(base, k * step);
              out.push([changed, [...tilt.drawn]]);
            }
            return { out, step: t.STEP_DEG }; }""")
    assert got["step"] / 4 == 0.05  # (the cases below lie either side of it)
    (changed1, drawn1), (changed2, drawn2), (changed3, drawn3) = got["out"]
    assert changed1 and np.allclose(drawn1, [0.9, 0], atol=1e-9)  # 0.1 off: as filtered
    assert changed2 and drawn2 == [1, 0]  # 0.01 off: the target itself
    assert not changed3 and drawn3 == [1, 0]


def test_the_screen_stays_on_while_visible_and_connected(serve, phones):
    s = serve()
    page = phones(s.local)
    page.wait_for_function("frost.phone.awake.held", timeout=30_000)
    hide = ("v => { Object.defineProperty(document, 'visibilityState', {configurable: true, get: () => v});"
            " document.dispatchEvent(new Event('visibilitychange')); }")
    page.evaluate("window.lock = frost.phone.awake.sentinel")
    page.evaluate(hide, "hidden")
    page.wait_for_function("!frost.phone.awake.held && window.lock.released", timeout=30_000)
    page.evaluate(hide, "visible")  # back to the front: asked again
    page.wait_for_function("frost.phone.awake.held && frost.phone.awake.sentinel !== window.lock",
                           timeout=30_000)
    assert page.evaluate("frost.phone.awake.requests") == 2
    page.evaluate("window.lock = frost.phone.awake.sentinel")
    s.stop()  # disconnected: released
    page.wait_for_function("!frost.connected && !frost.phone.awake.held && window.lock.released",
                           timeout=30_000)


def test_a_taps_first_frost_buzzes_unless_switched_off(serve, phones):
    s = serve()
    page = phones(s.local, init=VIBRATE)
    page.touchscreen.tap(120, 300)
    page.wait_for_function("frost.frostLatencies.length === 1", timeout=30_000)
    page.wait_for_function("window.buzzes && window.buzzes.length === 1")
    assert page.evaluate("window.buzzes") == [12]
    page.click("#open")
    page.uncheck("#buzz")
    page.click("#open")
    page.touchscreen.tap(280, 600)
    page.wait_for_function("frost.frostLatencies.length === 2", timeout=30_000)
    page.wait_for_timeout(300)
    assert page.evaluate("window.buzzes.length") == 1
    page.reload()  # remembered
    synced(page)
    assert not page.is_checked("#buzz")


# iOS's DeviceOrientationEvent.requestPermission as a stub: counts its calls and answers
# window.answer (a refusal at first, as iOS answers a page that asks without a tap).
ASK = ("window.answer = 'denied'; window.asked = 0; DeviceOrientationEvent.requestPermission ="
       " async () => { window.asked += 1; return window.answer; }")


def test_where_the_browser_asks_the_switch_asks(serve, phones):
    """iOS grants motion sensors only from a tap: tried at load and refused, the switch
    stays off without a word; turned on, it asks again, and a refusal is said; granted, the
    tilt moves the light."""
    s = serve()
    page = phones(s.local, init=ASK)
    page.wait_for_function("window.asked === 1")
    assert not page.evaluate("frost.phone.tilt.on")
    page.click("#open")
    assert not page.is_checked("#tilt") and page.is_hidden("#tilt-why")
    page.click("#tilt")  # a tap: asked, refused
    page.wait_for_function("window.asked === 2")
    page.wait_for_function("document.getElementById('tilt-why').textContent.includes('refused')")
    assert not page.is_checked("#tilt") and not page.evaluate("frost.phone.tilt.on")
    page.evaluate("window.answer = 'granted'")
    page.click("#tilt")
    page.wait_for_function("window.asked === 3 && frost.phone.tilt.on")
    assert page.is_checked("#tilt") and page.is_hidden("#tilt-why")
    cdp = page.context.new_cdp_session(page)
    _tilt(cdp, 50)
    page.wait_for_function("frost.phone.tilt.rest && frost.phone.tilt.rest.beta === 50")
    _tilt(cdp, 80)
    page.wait_for_function("frost.phone.tilt.drawn[1] === 30")
    assert page.evaluate("frost.renderer.light") != page.evaluate("frost.serverLight")


def test_the_menu_and_the_status_line_keep_clear_of_notches(serve, phones):
    """Safe-area insets as a notched phone's (Chromium's override over CDP): the menu's
    button below the notch and inside a side inset, the status line above the home bar."""
    s = serve()
    page = phones(s.local)
    page.evaluate("document.getElementById('status').textContent = 'reconnecting'")
    box = "id => document.getElementById(id).getBoundingClientRect().toJSON()"
    bare = page.evaluate(box, "menu"), page.evaluate(box, "status")
    assert bare[0]["top"] == 8 and bare[0]["right"] == 390 - 8 and bare[1]["bottom"] == 844 - 12
    cdp = page.context.new_cdp_session(page)
    insets = {"top": 47, "bottom": 34, "left": 0, "right": 30}
    cdp.send("Emulation.setSafeAreaInsetsOverride", {"insets": insets})
    page.wait_for_function("document.getElementById('menu').getBoundingClientRect().top === 47")
    menu, status = page.evaluate(box, "menu"), page.evaluate(box, "status")
    assert menu["right"] == 390 - 30 and status["bottom"] == 844 - 34 - 12 and status["height"] > 0


def test_a_deep_link_sets_the_servers_preset_as_the_menu_does(serve, phones):
    """`?preset=c-2` on frost serve's page sets the server's preset, as the menu's choice
    does (its /meta's parameters are then c-2's); a name that is no preset is one line in
    that page's status line and changes nothing."""
    s = serve()
    page = phones(s.local + "?preset=c-2")
    page.wait_for_function("frost.hello.preset === 'c-2'", timeout=60_000)
    with urlopen(s.local + "meta", timeout=10) as r:
        assert json.loads(r.read())["parameters"] == json.loads(json.dumps(Params.preset("c-2").as_dict()))
    other = phones(s.local + "?preset=zzz")
    other.wait_for_function("document.getElementById('status').textContent !== ''", timeout=30_000)
    line = other.evaluate("document.getElementById('status').textContent")
    assert line.startswith("?preset=zzz is no preset: one of ") and "c-2" in line, line
    assert other.evaluate("frost.hello.preset") == "c-2"
