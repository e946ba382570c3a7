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
