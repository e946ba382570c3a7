"""The phone alone (issue 49): the installed page of `frost serve --preset fern`, reloaded
after the server stopped, grows its own frost in a Web Worker. Headless Chromium with a
persistent profile (the service worker needs one): a tap grows frost, `window.frost.local`
states the worker's figures as plain data, the menu works on the local frost, a server
answering again is offered and joined, a storm of taps and bad touches leave it ticking."""

from __future__ import annotations

import io
import json
import socket
import time

import numpy as np
import pytest
from PIL import Image
from support.phone import (
    PROBLEM,
    css_point,
    launch_browser,
    open_page,
    persistent,
    pixels,
    synced,
    wait_for_shell,
)

pytestmark = [pytest.mark.browser, pytest.mark.slow,
              pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

ON_PHONE = "on this phone"
# Said for a few seconds once a join shows the server's frost (alone.js's KEPT).
KEPT = "your frost waits on this phone (the menu saves it)"
PHONE_SIZE = (390, 844)  # support.phone.PHONE's viewport, CSS px
# sim/'s crystals after 100 ticks of one touch at the pane's centre, seeds 1-3 (fern): the
# median, and the factor the phone's may differ by (the "Done when").
SIM_MEDIAN, FACTOR = 366, 1.5


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def status(page) -> str:
    return page.evaluate("document.getElementById('status').textContent")


def local_tick(page) -> int:
    return page.evaluate("frost.local.tick")


def ticks_later(page, n: int) -> int:
    """Wait until the phone's frost is `n` ticks on (however slowly a loaded machine steps)."""
    tick = local_tick(page) + n
    page.wait_for_function(f"frost.local && frost.local.tick >= {tick}", timeout=120_000)
    return local_tick(page)


@pytest.fixture
def alone(pw, serve, tmp_path):
    """A page of `frost serve --preset fern` on a port of its own, installed (its worker's
    shell cached), reloaded after the server stopped: growing its own frost. (page, the
    port, a function starting the server again on that port)."""
    port = str(free_port())
    s = serve("--port", port, folder=tmp_path)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = open_page(ctx, s.local)
        wait_for_shell(page)
        s.stop()
        page.reload()
        page.wait_for_function(f"window.frost && frost.local && frost.synced && frost.frames > 0 && "
                               f"document.getElementById('status').textContent === '{ON_PHONE}'",
                               timeout=60_000)
        assert page.evaluate("frost.error") is None
        assert page.evaluate("navigator.serviceWorker.controller !== null")  # (its worker's page)
        yield page, lambda: serve("--port", port, folder=tmp_path)
    finally:
        ctx.close()


def test_the_phone_alone_grows_frost_at_a_tap(alone):
    page, _ = alone
    assert page.evaluate("frost.hello.local") is True and page.evaluate("frost.hello.preset") == "fern"
    before = pixels(page)
    t0 = local_tick(page)
    page.touchscreen.tap(*css_point(page, 380, 640))  # 195,422 CSS px on the 390x844 screen
    page.wait_for_function(f"frost.local.tick >= {t0 + 100}", timeout=120_000)
    crystals = page.evaluate("frost.local.crystals")
    # (the stats come every 5 ticks, the tap lands a tick or two late: a few ticks either side)
    assert SIM_MEDIAN / FACTOR <= crystals <= SIM_MEDIAN * FACTOR, crystals
    page.wait_for_timeout(500)  # (a frame or two to draw the last ticks)
    after = pixels(page)
    box = (slice(640 - 80, 640 + 80), slice(380 - 80, 380 + 80))
    changed = np.abs(after[box].astype(int) - before[box].astype(int)).max(axis=2) > 8
    assert changed.mean() >= 0.05, changed.mean()

    local = page.evaluate("""() => {
        const l = frost.local, own = Object.getOwnPropertyDescriptors(l);
        return {json: JSON.parse(JSON.stringify(l)), proto: Object.getPrototypeOf(l) === Object.prototype,
                getters: Object.values(own).filter((d) => d.get || d.set).length,
                clear: typeof l.clear};
    }""")
    assert local["proto"] and local["getters"] == 0 and local["clear"] == "function"
    assert sorted(local["json"]) == ["crystals", "tick", "tickP99Ms", "ticksPerSecond"], local
    for key in ("tick", "crystals", "ticksPerSecond", "tickP99Ms"):
        assert isinstance(local["json"][key], (int, float)), (key, local)
    assert local["json"]["crystals"] >= crystals and local["json"]["tickP99Ms"] > 0
    page.evaluate("frost.local.clear()")
    page.wait_for_function("frost.local.crystals === 0", timeout=30_000)
    tick = ticks_later(page, 25)  # nothing pending grows back
    assert page.evaluate("frost.local.crystals") == 0, tick


def test_the_menu_works_on_the_local_frost(alone, tmp_path):
    page, _ = alone
    page.click("#open")
    # the phone grows every preset, the frosted window too (app/web/local/pane.js)
    assert page.locator("#preset option[value=window]").evaluate("o => o.disabled") is False
    assert "needs frost serve" not in page.locator("#preset option[value=window]").inner_text()
    page.select_option("#preset", "c-2")
    page.wait_for_function("frost.hello.preset === 'c-2' && frost.hello.look === 'paper'", timeout=30_000)
    page.select_option("#look", "glass")
    page.wait_for_function("frost.hello.look === 'glass'", timeout=30_000)
    page.click("#pause")
    page.wait_for_function("frost.hello.paused === true", timeout=30_000)
    held = local_tick(page)
    page.wait_for_timeout(1000)
    assert local_tick(page) == held
    page.click("#pause")
    ticks_later(page, 10)
    page.click("#open")
    page.touchscreen.tap(*css_point(page, 380, 640))
    page.wait_for_function("frost.local.crystals > 20", timeout=120_000)
    page.click("#open")
    # the backdrops the phone keeps: the lock screen too (the page draws its clock box)
    backdrops = page.eval_on_selector_all("#backdrop option", "os => os.map((o) => o.value)")
    assert backdrops == ["dusk", "lockscreen"]
    page.check("#warm")  # the warm finger: a tap melts
    page.click("#open")
    page.touchscreen.tap(*css_point(page, 380, 640))
    session_when(page, "s.events.some((e) => e.kind === 'melt')")
    page.click("#open")
    page.uncheck("#warm")
    page.click("#clear")
    page.wait_for_function("frost.local.crystals === 0", timeout=30_000)
    png = page.evaluate("frost.screenshotPng().then((b) => Array.from(b))")
    text = Image.open(io.BytesIO(bytes(png))).text
    assert text["source"] == "phone" and json.loads(text["parameters"])["look"] == "glass", text
    with page.expect_download() as got:
        page.click("#session")
    session = json.loads(got.value.path().read_text(encoding="utf-8"))
    kinds = [e["kind"] for e in session["events"]]
    assert session["source"] == "phone" and kinds == ["params", "params", "touch", "melt", "clear"], kinds
    from sim.io.session import SessionLog  # (what frost replay reads)

    assert SessionLog.from_json(session).source == "phone"


def test_a_server_back_is_offered_and_joined(alone):
    page, start_again = alone
    page.touchscreen.tap(*css_point(page, 380, 640))
    page.wait_for_function("frost.local.crystals > 0", timeout=120_000)
    assert page.locator("#join").is_hidden()
    start_again()
    page.wait_for_function("!document.getElementById('join').hidden", timeout=30_000)
    # offered, not forced: the phone's frost goes on until the user joins
    ticks_later(page, 10)
    assert page.evaluate("frost.hello.local") is True and status(page) == ON_PHONE
    page.click("#join")
    synced(page, "frost.frames > 0 && frost.hello && !frost.hello.local")
    assert page.evaluate("frost.local") is None and status(page) in ("", KEPT)
    assert page.locator("#join").is_hidden()


def phone_session(page) -> dict:
    """The phone's own session as Save session downloads it (asked of its worker)."""
    return page.evaluate("frost.alone.ask('session')")


def session_when(page, holds: str, timeout_s: float = 30) -> dict:
    """The phone's session once `holds` (a JavaScript expression of it, `s`) is true.
    (wait_for_function does not wait for a promise: a pending one is truthy.)"""
    deadline = time.monotonic() + timeout_s
    while True:
        session = page.evaluate(f"frost.alone.ask('session').then((s) => ({holds}) ? s : null)")
        if session:
            return session
        if time.monotonic() > deadline:
            raise AssertionError(f"the phone's session never held {holds}: {phone_session(page)}")
        page.wait_for_timeout(100)


def near_taps_changed(page, bare, taps) -> float:
    """The share of the pane's pixels within 60 px of `taps` that differ from `bare`."""
    now = pixels(page)
    shares = []
    for x, y in taps:
        box = (slice(y - 60, y + 60), slice(x - 60, x + 60))
        shares.append((np.abs(now[box].astype(int) - bare[box].astype(int)).max(axis=2) > 8).mean())
    return min(shares)


def test_joining_keeps_the_phones_frost_and_it_goes_on_when_the_server_goes(alone, tmp_path):
    """Issue 56 item 9: the offer says the phone's frost stays; after joining, its session
    is still the phone's to save; with no server again, the phone's frost goes on from where
    it was (its crystals, its events), not from a blank pane."""
    page, start_again = alone
    bare = pixels(page)
    taps = [(380, 640), (250, 420), (520, 880)]
    for x, y in taps:
        page.touchscreen.tap(*css_point(page, x, y))
    page.wait_for_function("frost.local.crystals > 60", timeout=120_000)
    s = start_again()
    page.wait_for_function("!document.getElementById('join').hidden", timeout=30_000)
    offer = page.locator("#join").inner_text()
    assert "your frost stays on this phone" in offer, offer
    before = phone_session(page)
    assert [e["kind"] for e in before["events"]] == ["touch"] * 3, before["events"]
    crystals = page.evaluate("frost.local.crystals")
    page.evaluate("""() => { const line = document.getElementById('status'); window.said = [];
        new MutationObserver(() => said.push(line.textContent)).observe(line, {childList: true,
            characterData: true, subtree: true}); }""")
    page.click("#join")
    synced(page, "frost.frames > 0 && frost.hello && !frost.hello.local")
    assert page.evaluate("frost.local") is None
    assert KEPT in page.evaluate("said"), page.evaluate("said")

    # joined: the phone's session is kept, and saved from the menu
    page.click("#open")
    assert page.locator("#session").is_visible()
    with page.expect_download() as got:
        page.click("#session")
    saved = json.loads(got.value.path().read_text(encoding="utf-8"))
    page.click("#open")
    assert saved["source"] == "phone" and saved["seed"] == before["seed"]
    assert saved["events"] == before["events"], saved["events"]
    assert saved["steps"] >= before["steps"]
    page.wait_for_timeout(1000)  # held: it does not tick meanwhile
    assert phone_session(page)["steps"] == saved["steps"]

    # the server goes: the phone's frost goes on from where it was
    s.stop()
    page.wait_for_function(f"frost.local && frost.hello.local && frost.synced && "
                           f"document.getElementById('status').textContent === '{ON_PHONE}'",
                           timeout=60_000)
    assert page.evaluate("frost.local.crystals") >= crystals
    after = phone_session(page)
    assert after["seed"] == before["seed"] and after["events"] == before["events"]
    assert after["steps"] >= saved["steps"]
    ticks_later(page, 10)
    page.wait_for_timeout(500)  # (a frame or two drawn)
    assert near_taps_changed(page, bare, taps) >= 0.05
    page.touchscreen.tap(*css_point(page, 300, 300))
    last = session_when(page, "s.events.length === 4")["events"][-1]
    assert last["kind"] == "touch" and last["tick"] > before["events"][-1]["tick"], last
    assert page.evaluate("frost.error") is None


def test_the_join_button_takes_no_part_of_the_panes_taps(alone):
    """Issue 56 item 10: with the join offered, taps across the pane's bottom and beside the
    button plant frost on the phone (each a touch of its session where it was tapped), and
    a tap on the button joins, planting nothing."""
    page, start_again = alone
    start_again()
    page.wait_for_function("!document.getElementById('join').hidden", timeout=30_000)
    box = page.locator("#join").bounding_box()
    width, height = PHONE_SIZE
    spots = [(x, y) for y in (height - 100, height - 58, height - 20) for x in (60, width / 2, width - 60)]
    middle = (box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    spots += [(box["x"] - 12, middle[1]), (middle[0], box["y"] + box["height"] + 12)]  # beside it
    under = page.evaluate("(spots) => spots.map(([x, y]) => document.elementFromPoint(x, y).id)", spots)
    assert under == ["frost"] * len(spots), list(zip(spots, under, strict=True))
    for x, y in spots:
        page.touchscreen.tap(x, y)
    session = session_when(page, f"s.events.length >= {len(spots)}")
    pane = page.evaluate("frost.paneCss()")
    want = [((x - pane["x"]) / pane["sx"], (y - pane["y"]) / pane["sy"]) for x, y in spots]
    got = [(e["x"], e["y"]) for e in session["events"] if e["kind"] == "touch"]
    assert len(got) == len(want), (got, want)
    assert all(abs(a - c) < 1 and abs(b - d) < 1 for (a, b), (c, d) in zip(got, want, strict=True)), got
    page.touchscreen.tap(*middle)
    synced(page, "frost.frames > 0 && frost.hello && !frost.hello.local")
    assert len(phone_session(page)["events"]) == len(spots)


def test_a_storm_of_taps_and_bad_touches_leave_it_ticking(alone):
    page, _ = alone
    # Touches that are no touches: not numbers (NaN is sent as null), off the pane.
    page.evaluate("""() => { for (const [x, y] of [[NaN, 5], [5, Infinity], [760, 10], [-1, 10], [10, 1280]])
        frost.alone.socket.send(JSON.stringify({type: 'touch', phase: 'down', id: 0, x, y})); }""")
    ticks_later(page, 25)
    assert page.evaluate("frost.local.crystals") == 0
    # 2 000 taps in 10 s, 20 every 100 ms, through the page's socket stand-in
    page.evaluate("""() => new Promise((done) => { let n = 0;
        const burst = () => { for (let k = 0; k < 20; k++, n++)
            frost.alone.socket.send(JSON.stringify({type: 'touch', phase: 'down', id: k,
                x: 20 + (n * 37) % 720, y: 20 + (n * 91) % 1240}));
          if (n < 2000) setTimeout(burst, 100); else done(); };
        burst(); })""")
    start = local_tick(page)
    after = ticks_later(page, 50)  # it goes on ticking after the storm
    assert after >= start + 50
    stats = page.evaluate("frost.alone.stats")
    assert stats["crystals"] > 2000 and stats["dropped"] <= 2000, stats
    assert page.evaluate("frost.error") is None



def test_a_page_that_never_cached_its_simulation_waits_for_the_server(pw, serve, tmp_path):
    """No service worker (its cache is what the phone's frost loads from): with the server
    gone the worker cannot load, and the page says the server is not reachable and syncs by
    itself when it is back, as before."""
    from support.phone import PHONE


    port = str(free_port())
    s = serve("--port", port, folder=tmp_path)
    b = launch_browser(pw)
    try:
        page = b.new_context(**{**PHONE, "service_workers": "block"}).new_page()
        page.goto(s.local)
        synced(page, "frost.frames > 0")
        s.stop()
        page.wait_for_function("frost.alone.failed !== null", timeout=60_000)
        page.wait_for_function("document.getElementById('status').textContent"
                               ".startsWith('frost serve is not reachable')", timeout=30_000)
        assert page.evaluate("frost.local") is None
        serve("--port", port, folder=tmp_path)
        synced(page, "frost.frames > 0 && frost.hellos === 2")
        assert status(page) == ""
    finally:
        b.close()
