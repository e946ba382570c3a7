"""The lock screen's live clock end to end: `frost serve --clock-start` (the hidden test
hook: the clock reads a given time and runs on in real time) and a page in headless
Chromium. The oracle is the clock function drawn directly at each minute over the lock
screen's static parts (`app.lockscreen.with_clock`): away from the ice the page's pane is
the backdrop exactly."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from datetime import datetime, timedelta

import numpy as np
import pytest
from PIL import Image
from support.phone import PROBLEM, grown, pause_and_settle, pixels, tap

from app.backdrops import LIVE, load_backdrop, read_backdrop
from app.lockscreen import CLOCK_BOX, MINUTE_FORMAT, with_clock

pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

STATIC = np.asarray(read_backdrop(LIVE))
X0, Y0, X1, Y1 = CLOCK_BOX


def shown_minute(page, other: str | None = None) -> str:
    """The minute the page's backdrop holds, once it holds one (other than `other`): in
    the backdrop texture, which pixels() draws the pane with (no frame waited for)."""
    page.wait_for_function(f"frost.clock.shown && frost.clock.shown !== {json.dumps(other)}",
                           timeout=90_000)
    return page.evaluate("frost.clock.shown")


def test_the_page_shows_each_minute_from_the_clock_box_alone(serve, phones, tmp_path):  # noqa: F811
    s = serve("--background", "lockscreen", "--clock-start", "2026-11-26T15:41:45")
    page = phones(s.local)
    tap(page, 380, 1180)  # frost far below the clock (and a session to replay)
    grown(page, 25)
    pause_and_settle([page])  # (the clock runs on)
    first = shown_minute(page)
    before = pixels(page)
    # The pane away from the ice is the server's backdrop at that minute, pixel for pixel.
    clear = np.ones(STATIC.shape[:2], bool)
    clear[1000:] = False
    assert np.array_equal(before[clear], with_clock(STATIC, first)[clear])
    second = shown_minute(page, first)
    turned = datetime.strptime(first, MINUTE_FORMAT) + timedelta(minutes=1)
    assert second == turned.strftime(MINUTE_FORMAT)
    after = pixels(page)
    assert np.array_equal(after[clear], with_clock(STATIC, second)[clear])
    assert not np.array_equal(before[Y0:Y1, X0:X1], after[Y0:Y1, X0:X1])
    outside = np.ones(STATIC.shape[:2], bool)
    outside[Y0:Y1, X0:X1] = False
    assert np.array_equal(before[outside], after[outside])  # (the ice too: paused)
    # Each minute came as the clock box's pixels only: far less than the whole backdrop.
    received, sent = page.evaluate("[frost.clock.received, frost.clock.bytes]")
    whole = io.BytesIO()
    Image.fromarray(load_backdrop(LIVE)).save(whole, "PNG")
    assert received >= 2 and sent / received < len(whole.getvalue()) / 2
    print(f"benchmark: clock message {sent / received / 1000:.1f} kB a minute "
          f"(the whole backdrop's PNG {len(whole.getvalue()) / 1000:.1f} kB)")

    # The session the server wrote replays to the minute the page showed last.
    page.context.close()
    out = s.stop()
    sessions = sorted(tmp_path.glob("session-*.json"))
    assert sessions, out
    recorded = json.loads(sessions[-1].read_text(encoding="utf-8"))
    minutes = [e["minute"] for e in recorded["events"] if e["kind"] == "clock"]
    assert recorded["version"] >= 10 and minutes[-2:] == [first, second]
    png = tmp_path / "replay.png"
    subprocess.run([sys.executable, "-m", "app", "replay", str(sessions[-1]), "--out", str(png)],
                   cwd=tmp_path, check=True, capture_output=True, timeout=300)
    replayed = np.asarray(Image.open(png).convert("RGB"))
    assert np.array_equal(replayed[Y0:Y1, X0:X1], with_clock(STATIC, second)[Y0:Y1, X0:X1])


def test_a_clock_message_is_applied_over_the_lock_screen_alone_and_never_an_older_minute(browser):
    """The page's clock (lockclock.js) with a renderer that records what it is given: a minute
    received while another backdrop is shown is not written into it (it is once the lock
    screen is back); of two minutes received together, the newer is shown even when the
    older's picture is decoded last, and the older is never written."""
    from app.serve.protocol import clock_message
    from bench.page import Page, hello
    from sim import Params

    def message(minute: str, shade: int) -> list[int]:
        png = io.BytesIO()
        Image.new("RGB", (4, 3), (shade, shade, shade)).save(png, "PNG")
        return list(clock_message((10, 20, 14, 23), minute, png.getvalue()))

    early, late = message("2026-11-26T15:41", 50), message("2026-11-26T15:42", 200)
    with Page(hello(Params.preset("fern")), [], browser=browser) as page:
        got = page.page.evaluate("""async ([early, late]) => {
            const { Clock } = await import('./web/lockclock.js');
            const written = [];
            const renderer = { setBackgroundRect: (x, y, image) => written.push([x, y, image.width]) };
            const state = { renderer, shownBackdrop: 'dusk' };
            const clock = new Clock();
            const bytes = (m) => new Uint8Array(m).buffer;
            await clock.receive(bytes(early), state);
            const overDusk = [written.length, clock.shown];
            state.shownBackdrop = 'lockscreen';
            clock.showOn(state);
            const back = [written.length, clock.shown];
            // The older minute's picture decoded last: its decoding waits for the newer's.
            const decode = globalThis.createImageBitmap;
            let newerDone;
            const newer = new Promise((resolve) => { newerDone = resolve; });
            let calls = 0;
            globalThis.createImageBitmap = async (...args) => {
              const first = calls++ === 0;
              const image = await decode(...args);
              if (first) await newer; else newerDone();
              return image;
            };
            written.length = 0;
            try {
              await Promise.all([clock.receive(bytes(early), state), clock.receive(bytes(late), state)]);
            } finally { globalThis.createImageBitmap = decode; }
            return { overDusk, back, shown: clock.shown, written: written.length }; }""", [early, late])
    assert got["overDusk"] == [0, None]
    assert got["back"] == [1, "2026-11-26T15:41"]
    assert got["shown"] == "2026-11-26T15:42" and got["written"] == 1

