"""The phone end to end: `frost serve` in a subprocess, the page in headless Chromium (the
system's, driven by Playwright) on an emulated phone (390x844 CSS px, 3 device px each,
touch). The desktop renderer (`frost replay` of the session the server wrote) is the
oracle for what the page draws."""

from __future__ import annotations

import base64
import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.backdrops import load_backdrop
from bench.page import browser_problem, compare
from sim.screen import HEIGHT, WIDTH

PROBLEM = browser_problem()
pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

ROOT = Path(__file__).resolve().parent.parent
BACKDROP = load_backdrop("dusk").astype(int)
PHONE = {"viewport": {"width": 390, "height": 844}, "device_scale_factor": 3,
         "has_touch": True, "is_mobile": True}


class Serve:
    """`frost serve` on a free port (its own choice: --port 0), stopped with SIGINT."""

    def __init__(self, tmp: Path, *args: str):
        self.tmp = tmp
        cmd = [sys.executable, "-m", "app", "serve", "--port", "0", "--session-dir", str(tmp),
               "--preset", "fern", "--seed", "5", *args]
        self.proc = subprocess.Popen(cmd, cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})
        self.output: list[str] = []
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            line = self.proc.stdout.readline()
            if not line:
                break
            self.output.append(line)
            found = re.search(r"open (http://\S+)", line)
            if found:
                self.url = found.group(1)
                break
        else:
            line = ""
        if not getattr(self, "url", None):
            self.proc.kill()
            raise AssertionError("frost serve did not start:\n" + "".join(self.output))
        self.port = int(re.search(r":(\d+)/", self.url).group(1))
        token = re.search(r"token=([\w-]+)", self.url)
        self.token = token.group(1) if token else None
        # The address a page on this machine opens (a LAN URL names another interface).
        self.local = f"http://127.0.0.1:{self.port}/" + (f"?token={self.token}" if self.token else "")

    def stop(self) -> str:
        """Stop as Ctrl-C does; everything it printed."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            rest, _ = self.proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rest, _ = self.proc.communicate()
        return "".join(self.output) + (rest or "")


@pytest.fixture
def phones(browser, serve):
    """Opens pages on emulated phones; closes them before the server stops (`serve` is
    torn down after this)."""
    contexts = []

    def open_(url: str):
        context = browser.new_context(**PHONE)
        contexts.append(context)
        return open_page(context, url)

    yield open_
    for context in contexts:
        context.close()


def open_page(context, url: str):
    """A page of `url`, synced and drawn, having logged no error and failed no request
    (a browser asks for /favicon.ico unless the page names its icon)."""
    page = context.new_page()
    failed: list[str] = []
    page.on("console", lambda m: m.type == "error" and failed.append(m.text))
    page.on("response", lambda r: r.status >= 400 and failed.append(f"{r.status} {r.url}"))
    page.goto(url)
    synced(page, "frost.frames > 0 && frost.shownBackdrop")
    page.wait_for_timeout(300)
    assert failed == []
    return page


def synced(page, also: str = "true", timeout: float = 60_000) -> None:
    """Wait until the page has synced with the server and `also` (a JS expression) holds,
    or has said an error (failing on it). A page that never does fails saying what it was
    doing: its address, its status line, its socket's counts. (A loaded machine running
    the whole suite took over 30 s once to sync a second page.)"""
    from playwright.sync_api import TimeoutError as Timeout

    try:
        page.wait_for_function(f"window.frost && (frost.error || (frost.synced && ({also})))",
                               timeout=timeout)
    except Timeout:
        seen = page.evaluate("""() => ({url: location.href, status:
            (document.getElementById('status') || {}).textContent, frost: window.frost &&
            {connected: frost.connected, hellos: frost.hellos, messages: frost.messages,
             synced: frost.synced, frames: frost.frames, lost: frost.lost,
             backdrop: frost.backdrop, shown: frost.shownBackdrop}})""")
        raise AssertionError(f"the page never synced ({also}): {seen}") from None
    assert page.evaluate("window.frost.error") is None


def pixels(page) -> np.ndarray:
    """The page's pane, 1280 x 760 x 3, top row first."""
    raw = base64.b64decode(page.evaluate("frost.framePixels()"))
    return np.frombuffer(raw, np.uint8).reshape(HEIGHT, WIDTH, 4)[:, :, :3].copy()


def css_point(page, x: float, y: float) -> tuple[float, float]:
    """CSS px of the pane's px (x, y)."""
    r = page.evaluate("frost.paneCss()")
    return r["x"] + x * r["sx"], r["y"] + y * r["sy"]


def tap(page, x: float, y: float) -> None:
    page.touchscreen.tap(*css_point(page, x, y))


def server_tick(page, stamp: float) -> int:
    """The server's tick now, asked through the page's socket (a ping and its pong)."""
    page.evaluate(f"frost.socket.send(JSON.stringify({{type: 'ping', t: {stamp}}}))")
    page.wait_for_function(f"frost.pong && frost.pong.t === {stamp}", timeout=30_000)
    return page.evaluate("frost.pong.tick")


def grown(page, ticks: int) -> int:
    """Wait until the page holds `ticks` more of the server's ticks (frost grown for a
    while, 25 ticks a second, however slowly a loaded machine steps them); that tick."""
    tick = page.evaluate("frost.tick") + ticks
    page.wait_for_function(f"frost.tick >= {tick}", timeout=120_000)
    return tick


def keeps_pace(page, seconds: float) -> tuple[int, int]:
    """(ticks the page drew, ticks the server stepped) over `seconds`."""
    page0, server0 = page.evaluate("frost.tick"), server_tick(page, 1)
    page.wait_for_timeout(seconds * 1000)
    server1 = server_tick(page, 2)
    return page.evaluate("frost.tick") - page0, server1 - server0


def pause_and_settle(pages) -> int:
    """Pause the server (from the first page's menu) and wait until every page holds the
    same last tick; that tick."""
    first = pages[0]
    first.click("#open")
    first.click("#pause")
    first.click("#open")
    for page in pages:
        page.wait_for_function("frost.hello && frost.hello.paused", timeout=30_000)
    last = None
    for _ in range(50):  # the ticks already on their way arrive within a few frames
        ticks = [p.evaluate("frost.tick") for p in pages]
        if len(set(ticks)) == 1 and ticks[0] == last:
            return ticks[0]
        last = ticks[0] if len(set(ticks)) == 1 else None
        time.sleep(0.2)
    raise AssertionError(f"the pages never agreed on a tick: {ticks}")


def test_a_tap_grows_frost_in_the_page(serve, phones):
    s = serve()
    page = phones(s.local)
    x, y = 380, 640
    cx, cy = css_point(page, x, y)
    box = {"x": cx - 40, "y": cy - 40, "width": 80, "height": 80}
    far = {"x": 5, "y": css_point(page, 0, 100)[1], "width": 60, "height": 60}
    before = [np.asarray(Image.open(io.BytesIO(page.screenshot(clip=c))).convert("RGB"), float)
              for c in (box, far)]
    tick = page.evaluate("frost.tick")
    tap(page, x, y)
    page.wait_for_function(f"frost.tick >= {tick + 50}", timeout=30_000)  # two seconds of frost
    after = [np.asarray(Image.open(io.BytesIO(page.screenshot(clip=c))).convert("RGB"), float)
             for c in (box, far)]
    near = np.abs(after[0] - before[0]).max(axis=2)
    assert (near > 40).mean() > 0.05, "no frost grew under the finger"
    assert np.abs(after[1] - before[1]).max() == 0, "frost grew far from the finger"


def test_two_pages_see_the_same_frost_and_a_late_one_gets_it_whole(serve, phones):
    s = serve()
    a, b = phones(s.local), phones(s.local)
    tap(a, 200, 400)
    tap(b, 560, 900)
    grown(a, 50)
    tick = pause_and_settle([a, b])
    pa, pb = pixels(a), pixels(b)
    assert np.array_equal(pa, pb)
    frosted = np.abs(pa.astype(int) - BACKDROP).max(axis=2) > 40
    for x, y in ((200, 400), (560, 900)):  # each page's touch grew, in both
        assert frosted[y - 30:y + 30, x - 30:x + 30].mean() > 0.05, (x, y)
    late = phones(s.local)
    assert late.evaluate("frost.tick") == tick
    # The snapshot draws the live ice anew: the same frost up to which of two overlapping
    # triangles the depth test keeps.
    got = compare(pa, pixels(late))
    assert got["within8"] > 0.999 and got["mad"] < 0.2, got


def token_needed(s: Serve, paths) -> None:
    """Each of `paths` on server `s` is refused (403) without its token and served with it."""
    bare = f"http://127.0.0.1:{s.port}/"
    for path in paths:
        with pytest.raises(urllib.error.HTTPError) as err:
            urllib.request.urlopen(bare + path, timeout=10)
        assert err.value.code == 403, path
        with urllib.request.urlopen(f"{bare}{path}?token={s.token}", timeout=10) as r:
            assert r.status == 200, path


def test_a_request_without_the_token_is_refused(serve, phones, browser):
    s = serve("--host", "0.0.0.0")
    assert s.token
    token_needed(s, ("", "web/main.js", "shaders/ice.frag", "backdrops/dusk.png"))
    page = phones(s.local)  # with the token the page runs
    assert page.evaluate("frost.connected")
    wrong = browser.new_context(**PHONE)
    try:
        assert wrong.new_page().goto(f"http://127.0.0.1:{s.port}/?token=x{s.token}").status == 403
    finally:
        wrong.close()


def test_a_flood_of_bad_messages_closes_that_page_alone(serve, phones):
    """Malformed and oversized messages close the sender's socket (it reconnects and
    resyncs); the server keeps ticking for the other page, and nothing changed."""
    s = serve()
    bad, good = phones(s.local), phones(s.local)
    page0, server0 = good.evaluate("frost.tick"), server_tick(good, 1)
    floods = ["'{bad'", "'x'.repeat(5000)", "JSON.stringify({type: 'touch', x: NaN, y: 1})",
              "JSON.stringify({type: 'nope'})", "new Uint8Array(64)",
              "JSON.stringify({type: 'touch', x: 1, y: 2, id: 99})"]
    for flood in floods:
        bad.wait_for_function("frost.synced", timeout=30_000)
        hellos = bad.evaluate("frost.hellos")
        bad.evaluate(f"for (let i = 0; i < 50; i++) frost.socket.send({flood})")
        bad.wait_for_function(f"frost.hellos > {hellos}", timeout=30_000)  # closed, back
    drawn, stepped = good.evaluate("frost.tick") - page0, server_tick(good, 2) - server0
    assert stepped > 25 and drawn > 0.8 * stepped, (drawn, stepped)  # the server ticked, the page kept up
    # No touch landed: the frost is the bare backdrop still.
    assert np.array_equal(pixels(good).astype(int), BACKDROP)


def _stalled_socket(port: int, token: str | None) -> socket.socket:
    """A WebSocket that connects and then never reads (a tiny receive window)."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect(("127.0.0.1", port))
    key = base64.b64encode(os.urandom(16)).decode()
    query = f"?token={token}" if token else ""
    sock.sendall((f"GET /ws{query} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                  f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                  "Sec-WebSocket-Version: 13\r\n\r\n").encode())
    return sock


def test_a_page_that_stops_reading_does_not_stall_the_others(serve, phones):
    s = serve("--preset", "window")  # ice all over the pane: the most bytes a tick
    stalled = [_stalled_socket(s.port, s.token) for _ in range(3)]
    try:
        page = phones(s.local)
        drawn, stepped = keeps_pace(page, 4)
        assert stepped > 25 and drawn > 0.8 * stepped, (drawn, stepped)
    finally:
        for sock in stalled:
            sock.close()


def test_the_session_replays_to_the_pages_frame(serve, phones, tmp_path):
    """What the page drew at the end is what the desktop renderer draws replaying the
    session `frost serve` wrote (the same ticks, touches and melts)."""
    s = serve()
    page = phones(s.local)
    tap(page, 380, 500)
    grown(page, 15)
    page.touchscreen.tap(*css_point(page, 200, 900))
    grown(page, 38)
    tick = pause_and_settle([page])
    shown = pixels(page)
    page.context.close()
    out = s.stop()
    sessions = sorted(tmp_path.glob("session-*.json"))
    assert sessions, out
    assert json.loads(sessions[-1].read_text(encoding="utf-8"))["steps"] == tick
    png = tmp_path / "replay.png"
    subprocess.run([sys.executable, "-m", "app", "replay", str(sessions[-1]), "--out", str(png)],
                   cwd=tmp_path, check=True, capture_output=True, timeout=120)
    desktop = np.asarray(Image.open(png).convert("RGB"))
    frost = np.abs(desktop.astype(int) - BACKDROP).max(axis=2) > 8
    assert frost.sum() > 2000  # the two touches grew
    got = compare(desktop[frost][None], shown[frost][None])  # where there is frost
    print(f"benchmark: replay vs page over {frost.sum()} frosted px: {got}")
    assert got["within8"] > 0.99 and got["mad"] < 1.0, got
    assert compare(desktop, shown)["within8"] > 0.999
