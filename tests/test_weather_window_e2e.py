"""The window under --weather: over the lock screen the temperature outside stands under
the clock. Runs this file as a script on an Xvfb server of its own (the app in a
subprocess, reading the stand-in weather API the test runs, driven by xdotool), then reads
what it saw. The oracle is the clock box drawn directly (`clock_patch`) at the minute the
screenshot's own session file shows last, with the temperature line and without it: the
line's rows must be the one drawn with it (the window frost's first film and ice dim the
glass a little, so the nearer of the two by far). The box is drawn on a worker after the
reading's tick, so the driver takes screenshots until one shows the line (at most 60 s).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support import ROOT
from support.weather_api import StandIn
from support.window import escape, finish, played, wait_for, window_id, xdo

from app.backdrops import LIVE, read_backdrop
from app.lockscreen import CLOCK_BOX, clock_patch, outside_line

pytestmark = pytest.mark.usefixtures("window_tools")

OUTSIDE_C = -7.0  # (glass -0.4 C: the window frost grows slowly, the box stays clear longer)
X0, Y0, X1, Y1 = CLOCK_BOX
LINE = slice(270, 320)  # the box's rows the temperature line is drawn in


def line_off(shot: np.ndarray, minute: str, outside: str) -> float:
    """How far the screenshot's temperature line is from the box drawn at `minute` with
    `outside` under the time (mean absolute difference over the line's rows)."""
    static = np.asarray(read_backdrop(LIVE))
    want = clock_patch(static, minute, outside)[LINE].astype(int)
    return float(np.abs(shot[Y0:Y1, X0:X1][LINE].astype(int) - want).mean())


def drive(out: Path, api: str) -> None:
    log = out / "app.log"
    cmd = [sys.executable, "-m", "app", "--preset", "window", "--seed", "2", "--scale", "1",
           "--background", "lockscreen", "--clock-start", "2026-11-26T07:05",
           "--weather", "59.33,18.07", "--weather-api", api, "--max-seconds", "150",
           "--screenshot-dir", str(out / "shots"), "--session-dir", str(out / "sessions")]
    env = {**os.environ, "XDG_CONFIG_HOME": str(out / "config")}
    with open(log, "w", encoding="utf-8") as sink:
        app = subprocess.Popen(cmd, cwd=ROOT, stdout=sink, stderr=subprocess.STDOUT, env=env)
    result: dict = {"tries": 0}
    try:
        wid = window_id()
        wait_for(log, r"weather: -7\.0 C", timeout=60)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and "seen" not in result:
            result["tries"] += 1
            xdo("key", "--window", wid, "s")
            wait_for(log, r"screenshot: ", result["tries"], timeout=60)
            shot = sorted((out / "shots").glob("*.png"))[-1]
            beside = json.loads((out / "sessions" / f"{shot.stem}.json").read_text(encoding="utf-8"))
            minutes = [e["minute"] for e in beside["events"] if e["kind"] == "clock"]
            weather = [e for e in beside["events"] if e["kind"] == "weather"]
            if not minutes or not weather:
                continue
            pixels = np.asarray(Image.open(shot).convert("RGB"))
            told = outside_line(weather[-1])
            offs = {"with": line_off(pixels, minutes[-1], told),
                    "without": line_off(pixels, minutes[-1], "")}
            if offs["with"] < offs["without"] / 5:
                result.update(seen=told, offs=offs)
        escape(wid)
        result["status"] = app.wait(timeout=60)
    finally:
        finish(app, out, result)


def test_the_window_shows_the_temperature_outside_under_the_clock(tmp_path):
    with StandIn(temperature_c=OUTSIDE_C) as api:
        log, result = played(__file__, tmp_path, api.url, timeout=240)
    assert result.get("status") == 0, log[-3000:]
    assert result.get("seen") == "-7 °C outside", (result, log[-3000:])
    assert "Traceback" not in log


if __name__ == "__main__":
    drive(Path(sys.argv[1]), sys.argv[2])
