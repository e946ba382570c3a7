"""The lock screen on the phone's own frost (issue 57, item 4): with no server the page
draws the lock screen's clock box itself (app/web/lockclock.js, as app/lockscreen.py's
clock_patch does on the desktop): the date, the time and, after the page's own weather
reading, the temperature outside under the time. The installed page of `frost serve`,
reloaded after the server stopped, on the lock screen backdrop; a stand-in forecast API at
-7 C. Oracles: the words as app/lockscreen.py writes them (outside_line), the clock's
local time, and the outside line's band of the pane and of a screenshot's crop: bare
before the reading, drawn after it, the pane beyond the box unchanged."""

from __future__ import annotations

import io
from datetime import datetime

import numpy as np
import pytest
from PIL import Image
from support.phone import PROBLEM, open_page, persistent, pixels, wait_for_shell
from support.serve import phone_serve
from support.weather_api import StandIn

from app.lockscreen import CLOCK_BOX, outside_line

pytestmark = [pytest.mark.browser, pytest.mark.slow,
              pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

ON_PHONE = "on this phone"
X0, Y0, X1, Y1 = CLOCK_BOX
BAND = (Y0 + 276, Y0 + 312)  # the outside line's rows (its centre 294 px into the box, 36 px high)
WHITE = 235  # a figure's pixel: every channel at least this (the lock screen's sky is darker)


def band_figures(shot: np.ndarray) -> int:
    """White pixels of the outside line's band of the clock box (pane px)."""
    band = shot[BAND[0]:BAND[1], X0:X1]
    return int((band.min(axis=2) >= WHITE).sum())


def screenshot_box(page, out) -> np.ndarray:
    """The screenshot's crop of the clock box (CSS px of the pane's box), kept in `out`."""
    r = page.evaluate("frost.paneCss()")
    clip = {"x": r["x"] + X0 * r["sx"], "y": r["y"] + Y0 * r["sy"],
            "width": (X1 - X0) * r["sx"], "height": (Y1 - Y0) * r["sy"]}
    png = page.screenshot(clip=clip)
    out.write_bytes(png)
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


@pytest.mark.usefixtures("subprocesses")
def test_the_phones_own_lock_screen_shows_the_time_and_the_temperature_outside(pw, tmp_path):
    s = phone_serve(tmp_path)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        with StandIn(-7.0) as api:
            page = open_page(ctx, s.local)
            wait_for_shell(page)
            s.stop()
            page.reload()
            page.wait_for_function(f"window.frost && frost.local && frost.frames > 0 && "
                                   f"document.getElementById('status').textContent === '{ON_PHONE}'",
                                   timeout=60_000)
            page.evaluate("(url) => { frost.site = { weather_api: url }; }", api.url)
            # The lock screen, from the menu, as on frost serve's page.
            page.click("#open")
            backdrops = page.eval_on_selector_all("#backdrop option", "os => os.map((o) => o.value)")
            assert "lockscreen" in backdrops
            page.select_option("#backdrop", "lockscreen")
            page.click("#pause")
            page.click("#open")
            page.wait_for_function("frost.hello.paused === true && frost.shownBackdrop === 'lockscreen' "
                                   "&& frost.clock.drawn !== null", timeout=30_000)
            drawn = page.evaluate("frost.clock.drawn")
            now = datetime.now()
            assert drawn["outside"] == "" and drawn["date"] == f"{now:%A} {now.day} {now:%B}", drawn
            minutes = int(drawn["time"][:2]) * 60 + int(drawn["time"][3:])
            assert abs(minutes - (now.hour * 60 + now.minute)) <= 1, drawn
            before = pixels(page)
            bare_crop = screenshot_box(page, tmp_path / "box-before.png")
            # The time and the date drawn in the box; the band under them bare.
            assert (before[Y0:Y1, X0:X1].min(axis=2) >= WHITE).sum() > 2000
            assert band_figures(before) == 0
            # The page's own reading at -7 C: under the time, the temperature outside.
            assert page.evaluate("import('./web/weather_local.js').then((m) => "
                                 "m.startWeather({latitude: 59.33, longitude: 18.07}))")
            page.wait_for_function(f"frost.clock.drawn && frost.clock.drawn.outside === "
                                   f"'{outside_line({'reading': {'temperature_c': -7.0}})}'", timeout=30_000)
            assert page.evaluate("frost.clock.drawn.outside").startswith("-7 ")
            page.wait_for_timeout(500)  # (the box drawn into the frame)
            after = pixels(page)
            crop = screenshot_box(page, tmp_path / "box-after.png")
            page.screenshot(path=tmp_path / "phone.png")
            assert band_figures(after) > 150
            # Outside the box the backdrop is as it was (paused: the ice too).
            away = np.ones(after.shape[:2], bool)
            away[Y0:Y1, X0:X1] = False
            assert np.array_equal(before[away], after[away])
            # The screenshot shows it too: its band of the box drawn, bare before.
            rows = slice(round((BAND[0] - Y0) * crop.shape[0] / (Y1 - Y0)),
                         round((BAND[1] - Y0) * crop.shape[0] / (Y1 - Y0)))
            assert (crop[rows].min(axis=2) >= WHITE).sum() > 150
            assert (bare_crop[rows].min(axis=2) >= WHITE).sum() == 0
    finally:
        ctx.close()
        s.stop()
