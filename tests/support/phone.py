"""The phone page in headless Chromium (Playwright): an emulated phone, a page opened and
synced, its pixels, a tap, its ticks; the installed app's profile and its worker."""

from __future__ import annotations

import base64
import json
import os
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from app.backdrops import load_backdrop
from bench.chromium import ANGLE, browser_problem, chromium_options, launch
from bench.serve_process import ServeProcess
from sim.screen import HEIGHT, WIDTH

PROBLEM = browser_problem()
BACKDROP = load_backdrop("dusk").astype(int)
# A phone's browser context. Its service worker is blocked: a page's first visit installs the
# worker, which fetches and caches the whole shell again (0.6-0.9 s of CPU a page, on the two
# cores the suite shares), and a test's server is a new origin, so every page is a first
# visit. The worker is the subject of the installed app's tests (`persistent` profiles allow
# it) and of test_phone_install_e2e's first visit, where it takes over a page growing frost.
PHONE = {"viewport": {"width": 390, "height": 844}, "device_scale_factor": 3,
         "has_touch": True, "is_mobile": True, "service_workers": "block"}
WITH_WORKER = {**PHONE, "service_workers": "allow"}
# The tests' Chromium puts its frames together on the CPU (Skia) rather than on the GPU
# process's rasteriser (what frost.framePixels reads, the page's WebGL, is drawn as before),
# and draws its WebGL with the system's OpenGL through EGL (ANGLE's GL backend: Mesa's
# llvmpipe here, the desktop renderer's rasteriser). On the two cores the suite shares, a page
# growing frost takes 0.49 of a core against 0.67 on SwiftShader, and a page opens for 1.07 s
# of CPU against 1.30. SwiftShader is kept where it is the subject: tests/test_page.py's
# browser (the page against the desktop across two rasterisers) and the benchmarks, which
# keep Chromium's own compositing too. Where the system's OpenGL cannot draw headless
# Chromium's WebGL, FROST_TEST_ANGLE=swiftshader draws every test's on SwiftShader.
TEST_ANGLE = os.environ.get("FROST_TEST_ANGLE", "gl-egl")
if TEST_ANGLE not in ANGLE:
    raise ValueError(f"FROST_TEST_ANGLE={TEST_ANGLE!r}: one of {', '.join(ANGLE)}")
TEST_ARGS = ["--disable-gpu-compositing"]


def launch_browser(pw, angle: str = TEST_ANGLE):
    """Headless Chromium for a test (bench.chromium.launch, with TEST_ARGS)."""
    return launch(pw, angle, TEST_ARGS)


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


def grown(page, ticks: int) -> int:
    """Wait until the page holds `ticks` more of the server's ticks (frost grown for a
    while, 25 ticks a second, however slowly a loaded machine steps them); that tick."""
    tick = page.evaluate("frost.tick") + ticks
    page.wait_for_function(f"frost.tick >= {tick}", timeout=120_000)
    return tick


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


def token_needed(s: ServeProcess, paths) -> None:
    """Each of `paths` on server `s` is refused (403) without its token and served with it."""
    bare = f"http://127.0.0.1:{s.port}/"
    for path in paths:
        with pytest.raises(urllib.error.HTTPError) as err:
            urllib.request.urlopen(bare + path, timeout=10)
        assert err.value.code == 403, path
        with urllib.request.urlopen(f"{bare}{path}?token={s.token}", timeout=10) as r:
            assert r.status == 200, path


def persistent(pw, profile: Path, **context):
    """Chromium with a profile kept in `profile` (not incognito), as a phone with its
    service worker (`context`: more of launch_persistent_context's options; `args` are added
    to the WebGL ones)."""
    options = chromium_options(pw, [*ANGLE[TEST_ANGLE], *TEST_ARGS, *context.pop("args", [])])
    return pw.chromium.launch_persistent_context(str(profile), **options, **{**WITH_WORKER, **context})


def cached_shells(page) -> list[str]:
    return page.evaluate("caches.keys().then((k) => k.filter((n) => n.startsWith('frost-shell-')))")


def wait_for_shell(page, digest: str | None = None) -> None:
    """Until a worker controls the page and its cache (of `digest`, if given) is the only one."""
    page.wait_for_function("navigator.serviceWorker.controller !== null", timeout=30_000)
    want = [f"frost-shell-{digest}"] if digest else None
    for _ in range(300):
        names = cached_shells(page)
        if (names == want) if want else len(names) == 1:
            return
        page.wait_for_timeout(100)
    raise AssertionError(f"the shell's cache is {names}, not {want}")


def worker_shell(s: ServeProcess) -> dict:
    """The first line of the server's worker: {"hash": ..., "files": [...]}."""
    query = f"?token={s.token}" if s.token else ""
    with urllib.request.urlopen(f"http://127.0.0.1:{s.port}/sw.js{query}", timeout=10) as r:
        return json.loads(r.read().decode().split("\n", 1)[0][len("const SHELL = "):-1])
