"""The page as a phone app (`python -m bench page --phone-app`): through `frost serve` on
loopback (started here, on a free port), pages on emulated phones in headless Chromium:

- the black (letterbox) share of the screen at three phone sizes, portrait, with the pane
  filling the screen (the default) and whole (the menu's "whole pane");
- tilt (DeviceOrientation overridden over CDP): the share of ice px whose shade changes
  for a 45 degree tilt each way, the clear glass px that change (none expected), and the
  light's lag behind the sensor (ms from the reading's change to the first frame whose
  light has turned 90 % of a 45 degree step);
- with `out`: screenshots of the page (CSS px, .webp) at the three sizes and one landscape,
  one with the menu open.
"""

from __future__ import annotations

import io
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np
from PIL import Image

from app.backdrops import DEFAULT_BACKDROP, load_backdrop
from bench.serve_process import ServeProcess

# (CSS width, height, device px a CSS px): an iPhone 12-15, a small Android, a Pixel 6-8.
PHONES = ((390, 844, 3.0), (360, 800, 3.0), (412, 915, 2.625))
LANDSCAPE = (844, 390, 3.0)
# Where the bench taps (pane px): frost across the pane's middle, as a user might.
TAPS = ((380, 640), (230, 470), (540, 820), (170, 900), (600, 420), (380, 1040), (380, 250))
GROW_S = 5.0
STEPS = 10  # tilt steps timed


@contextmanager
def serving(preset: str = "fern"):
    """`frost serve` on a free port; yields the page's URL."""
    with tempfile.TemporaryDirectory() as tmp:
        server = ServeProcess("--port", "0", "--preset", preset, "--seed", "5", "--session-dir",
                              tmp, cwd=tmp).drain()
        try:
            yield server.url
        finally:
            server.stop()


def open_phone(browser, url: str, width: int, height: int, scale: float):
    context = browser.new_context(viewport={"width": width, "height": height}, device_scale_factor=scale,
                                  has_touch=True, is_mobile=True)
    page = context.new_page()
    page.goto(url)
    page.wait_for_function("window.frost && frost.synced && frost.frames > 0 && frost.shownBackdrop",
                           timeout=60_000)
    page.wait_for_timeout(300)
    return page


def black_share(page) -> float:
    """The share of the screen's device px that are black (the backdrop has none)."""
    shot = np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB"))
    return float((shot.max(axis=2) < 8).mean())


def frame(page) -> np.ndarray:
    import base64

    raw = base64.b64decode(page.evaluate("frost.framePixels()"))
    return np.frombuffer(raw, np.uint8).reshape(1280, 760, 4)[:, :, :3].astype(int)


def tilt(cdp, beta: float, gamma: float = 0.0) -> None:
    cdp.send("DeviceOrientation.setDeviceOrientationOverride", {"alpha": 0, "beta": beta, "gamma": gamma})


def settle(page, beta: float, gamma: float) -> None:
    """Wait for the sensor's reading (beta, gamma) and the light drawn at the tilt the page's
    maths makes of it (tilt.js's screenTilt: a turn of gamma at a pose of beta tilts the
    screen less than gamma), every tile drawn."""
    page.wait_for_function(
        f"(t => t.reading && t.reading.beta === {beta} && t.reading.gamma === {gamma}"
        " && t.drawn[0] === t.target()[0] && t.drawn[1] === t.target()[1])(frost.phone.tilt)"
        " && !frost.renderer.damage.any", timeout=30_000)


def shading(page, cdp, backdrop: np.ndarray) -> list[tuple[str, float, int, float]]:
    """(tilt, share of ice px changed, clear glass px changed, share of the pane iced) for
    45 degrees each way."""
    rest = 50.0
    tilt(cdp, rest)
    page.wait_for_function(f"frost.phone.tilt.rest && frost.phone.tilt.rest.beta === {rest}")
    settle(page, rest, 0)
    before = frame(page)
    ice = np.abs(before - backdrop).max(axis=2) > 0
    pad = np.pad(ice, 1)
    near = np.any([pad[1 + dy:pad.shape[0] - 1 + dy, 1 + dx:pad.shape[1] - 1 + dx]
                   for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
    out = []
    ways = (("top lifted", rest + 45, 0), ("top lowered", rest - 45, 0),
            ("left lifted", rest, 45), ("right lifted", rest, -45))
    for name, beta, gamma in ways:
        tilt(cdp, beta, gamma)
        settle(page, beta, gamma)
        changed = np.abs(frame(page) - before).max(axis=2) > 0
        out.append((name, float(changed[ice].mean()), int(changed[~near].sum()), float(ice.mean())))
        tilt(cdp, rest)
        settle(page, rest, 0)
    return out


def lag(page, cdp) -> tuple[np.ndarray, np.ndarray]:
    """Ms from each 45 degree step of the sensor to the first frame drawn with 90 % of it,
    and the frames that took."""
    lags: list[float] = []
    frames: list[int] = []
    rest = 50.0
    tilt(cdp, rest)
    page.wait_for_function(f"frost.phone.tilt.rest && frost.phone.tilt.rest.beta === {rest}")
    settle(page, rest, 0)
    for i in range(STEPS):
        up = 45.0 if i % 2 == 0 else 0.0
        page.evaluate("frost.phone.trace = []")
        tilt(cdp, rest + up)
        settle(page, rest + up, 0)
        trace, t0 = page.evaluate("[frost.phone.trace, frost.phone.tilt.reading.t]")
        page.evaluate("frost.phone.trace = null")
        start = 45.0 - up
        after = [(t, u) for t, _, u in trace if t >= t0]
        hit = next(k for k, (t, u) in enumerate(after) if abs(u - start) >= 0.9 * 45)
        lags.append(after[hit][0] - t0)
        frames.append(hit + 1)
    return np.asarray(lags), np.asarray(frames)


def print_lag(what: str, lags: np.ndarray, frames: np.ndarray) -> None:
    print(f"  {what}: median {np.median(lags):.0f} ms, p95 {np.percentile(lags, 95):.0f} ms, "
          f"max {lags.max():.0f} ms, {np.median(frames):.0f} frames (median)")


def run(out: str | None, angle: str, launch) -> int:
    """The measures, printed; `launch(playwright, angle)` starts the browser (bench.page's,
    which runs this: passed in, not imported back)."""
    from playwright.sync_api import sync_playwright

    backdrop = load_backdrop(DEFAULT_BACKDROP).astype(int)
    with serving() as url, sync_playwright() as pw:
        browser = launch(pw, angle)
        first = open_phone(browser, url, *PHONES[0])
        tau = first.evaluate("import('./web/tilt.js').then((t) => t.TAU_MS)")
        cdp = first.context.new_cdp_session(first)
        print(f"the page's WebGL: {angle}")
        print(f"the light's lag behind a 45 degree step of the sensor, to 90 % ({STEPS} steps; "
              f"the low-pass alone: {tau * np.log(10):.0f} ms):")
        print_lag("clear glass (frames as cheap as the screen's rate)", *lag(first, cdp))
        r = first.evaluate("frost.paneCss()")
        for x, y in TAPS:
            first.touchscreen.tap(r["x"] + x * r["sx"], r["y"] + y * r["sy"])
            first.wait_for_timeout(150)
        first.wait_for_timeout(GROW_S * 1000)
        first.click("#open")
        first.click("#pause")
        first.click("#open")
        first.wait_for_timeout(1000)
        print("black (letterbox) share of the screen, portrait:")
        shots = {}
        for width, height, scale in PHONES:
            shares = []
            for fit in ("fill", "pane"):
                page = open_phone(browser, url, width, height, scale)
                if fit == "pane":
                    page.evaluate("frost.fit = 'pane'; frost.dirty = true")
                    page.wait_for_function("!frost.dirty")
                else:
                    shots[f"phone-{width}x{height}"] = page.screenshot(scale="css")
                shares.append(black_share(page))
                page.context.close()
            print(f"  {width}x{height} ({scale:g} device px a CSS px): filling {shares[0]:.2%}, "
                  f"whole pane {shares[1]:.2%}")
        page = open_phone(browser, url, *LANDSCAPE)
        shots[f"phone-{LANDSCAPE[0]}x{LANDSCAPE[1]}"] = page.screenshot(scale="css")
        print(f"  landscape {LANDSCAPE[0]}x{LANDSCAPE[1]}: filling {black_share(page):.2%}")
        page.context.close()
        first.click("#open")
        first.wait_for_timeout(300)
        shots["phone-menu"] = first.screenshot(scale="css")
        first.click("#open")

        print("tilt 45 degrees from the rest pose (390x844, paused frost):")
        for name, share, clear, iced in shading(first, cdp, backdrop):
            print(f"  {name}: {share:.1%} of the ice px ({iced:.1%} of the pane) change shade; "
                  f"clear glass px changed: {clear}")
        times = np.asarray(first.evaluate("frost.frameTimes(10)"))
        print_lag(f"the frost above (whole frames {np.median(times):.0f} ms, median of 10)", *lag(first, cdp))
        browser.close()
    if out:
        folder = Path(out)
        folder.mkdir(parents=True, exist_ok=True)
        for name, png in shots.items():
            Image.open(io.BytesIO(png)).convert("RGB").save(folder / f"{name}.webp", quality=80, method=6)
        print(f"screenshots: {', '.join(f'{n}.webp' for n in shots)} in {folder}")
    return 0
