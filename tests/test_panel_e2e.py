"""End to end: the tuning panel under Xvfb, driven with xdotool like a user would.

One session (about 15 s) runs this file as a script on an Xvfb server of its own: it
starts the window with the panel's widget positions logged, shows the panel (M), clicks
on the panel where no widget is, drags the hc slider, types a file name and saves the
parameter set, changes hc with a key, loads the set back, takes a screenshot with the
panel's button and presses Esc. The tests then read its log, its session file, the saved
set and the screenshot.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from test_window_e2e import ROOT, finish, played, wait_for, window_id, xdo

from sim import Params
from sim.io.paramsets import load_params
from sim.io.session import SessionLog

pytestmark = pytest.mark.window

# The window with the panel's debug lines (where each widget lies) in its log.
APP = ("import logging, sys; logging.getLogger('app.window.panel').setLevel(logging.DEBUG); "
       "from app.__main__ import main; sys.exit(main(sys.argv[1:]))")
PANEL_X = 760  # the panel's left edge once the window has widened, window px
EMPTY = (900, 1250)  # on the panel, below its last widget (phone px 700,1250 if it were not)
# The set's file name, typed into the panel's field over its default: C and S are keys of
# the window too (clear, screenshot), which must not fire while the field is typed into.
SET = "sc-set.json"


def widget(log: Path, name: str) -> tuple[float, float, float, float]:
    """The widget's box (x, y, w, h) in window px, once the panel has its place."""
    pattern = rf"panel: {name} at (\d+),(\d+) size (\d+)x(\d+)"
    end = time.monotonic() + 20
    while time.monotonic() < end:
        boxes = [tuple(map(float, m)) for m in re.findall(pattern, log.read_text())]
        placed = [b for b in boxes if b[0] >= PANEL_X]
        if placed:
            return placed[-1]
        time.sleep(0.05)
    raise TimeoutError(f"no box for {name} in {log}")


def click(wid: str, x: float, y: float) -> None:
    xdo("mousemove", "--window", wid, str(round(x)), str(round(y)))
    time.sleep(0.15)  # the panel sees the cursor there before the button
    xdo("click", "1")


def drag_slider(wid: str, box: tuple[float, float, float, float]) -> None:
    """Press at 6/15 of the slider (hc 7 of [1, 16]) and drag 80 px right in 4 px steps."""
    x, y, w, h = box
    x0, yc = round(x + w * 6 / 15), round(y + h / 2)
    xdo("mousemove", "--window", wid, str(x0), str(yc))
    time.sleep(0.15)
    xdo("mousedown", "1")
    for dx in range(4, 84, 4):
        xdo("mousemove", "--window", wid, str(x0 + dx), str(yc))
        time.sleep(0.02)
    xdo("mouseup", "1")


def drive(out: Path) -> None:
    log = out / "app.log"
    cmd = [sys.executable, "-c", APP, "--preset", "fern", "--seed", "2",
           "--screenshot-dir", "shots", "--session-dir", "sessions", "--max-seconds", "60"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with open(log, "w") as sink:
        app = subprocess.Popen(cmd, cwd=out, stdout=sink, stderr=subprocess.STDOUT, env=env)
    result: dict = {}
    try:
        result = session(app, log)
    except TimeoutError as err:  # what the app never did, for the tests to say
        result = {"error": str(err)}
    finally:
        finish(app, out, result)


def session(app: subprocess.Popen, log: Path) -> dict:
    wid = window_id()
    wait_for(log, r"stats \(")
    xdo("mousemove", "--window", wid, "5", "5")
    xdo("key", "m")
    wait_for(log, r"panel: shown")
    hc = widget(log, "hc")
    click(wid, *EMPTY)  # on the panel: no seed
    drag_slider(wid, hc)
    wait_for(log, r"params: hc=", 1)
    field = widget(log, "file")
    click(wid, field[0] + 40, field[1] + field[3] / 2)
    time.sleep(0.3)  # the click selected the whole name: typing replaces it
    xdo("type", "--delay", "30", SET)
    time.sleep(0.3)
    save = widget(log, "save_params")
    click(wid, save[0] + save[2] / 2, save[1] + save[3] / 2)
    wait_for(log, r"params saved: ")
    xdo("mousemove", "--window", wid, "380", "640")
    xdo("key", "bracketright")  # hc up half a px, by key
    wait_for(log, r"params: hc=", 2)
    load = widget(log, "load_params")
    click(wid, load[0] + load[2] / 2, load[1] + load[3] / 2)
    wait_for(log, r"params: hc=", 3)
    time.sleep(1.0)
    shoot = widget(log, "screenshot")
    click(wid, shoot[0] + shoot[2] / 2, shoot[1] + shoot[3] / 2)  # the button, not S
    wait_for(log, r"screenshot: ")
    xdo("key", "Escape")
    return {"status": app.wait(timeout=15), "hc_box": hc}


if __name__ == "__main__":
    drive(Path(sys.argv[1]))


# ---- the tests --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("panel")
    log, result = played(__file__, out, timeout=150)
    assert "error" not in result, f"{result['error']}; the app's log ends: {log[-1500:]}"
    session = SessionLog.load(out / re.findall(r"session: (\S+\.json)", log)[-1])
    return {"log": log, "result": result, "out": out, "session": session}


def changes(run) -> list[dict]:
    return [e for e in run["session"].events if e["kind"] == "params"]


def test_the_window_closes_cleanly_with_the_panel_shown(run):
    assert run["result"]["status"] == 0, run["log"][-2000:]
    costs = re.search(r"panel: (\d+) frames, median ([\d.]+) ms, max ([\d.]+) ms", run["log"])
    assert costs, run["log"][-2000:]
    print(f"benchmark: panel {costs[2]} ms a frame (median of {costs[1]}, max {costs[3]}, "
          "GL finished, llvmpipe under Xvfb)")


def test_a_dragged_slider_is_one_change_recorded_with_its_tick(run):
    said = [float(v) for v in re.findall(r"params: hc=([\d.]+)", run["log"])]
    drag, key, load = changes(run)  # one for the whole drag, not one per pixel
    assert drag["params"]["hc"] == said[0] > 7.0  # dragged right from 7
    assert key["params"]["hc"] == said[0] + 0.5 == said[1]
    # Each at the tick it applied, counted from the rebuild before it (a new timeline).
    assert all(isinstance(e["tick"], int) and e["tick"] >= 0 for e in (drag, key, load))
    first = Params(**run["session"].params)
    assert Params(**drag["params"]) == first.replace(hc=said[0], step=first.step)


def test_a_click_on_the_panel_plants_no_seed(run):
    assert [e for e in run["session"].events if e["kind"] == "touch"] == []


def test_keys_typed_into_the_panel_are_not_the_windows_keys(run):
    assert "cleared" not in run["log"]  # C
    assert len(re.findall(r"screenshot: ", run["log"])) == 1  # S: only the button's
    assert re.search(rf"params saved: {re.escape(SET)}$", run["log"], re.M)


def test_the_saved_set_is_the_dragged_parameters_and_loads_back(run):
    drag, _, load = changes(run)
    saved = load_params(run["out"] / SET)
    assert saved == Params(**drag["params"])
    assert Params(**load["params"]) == saved  # the key's half px undone by the load


def test_the_screenshot_is_the_phone_and_replays_bit_for_bit(run, tmp_path):
    shot = run["out"] / re.findall(r"screenshot: (\S+\.png)", run["log"])[-1]
    image = Image.open(shot)
    assert image.size == (760, 1280)
    assert json.loads(image.text["parameters"]) == changes(run)[-1]["params"]
    assert image.text["Software"] == "frost (window, key S)"
    session = run["out"] / image.text["session"]  # the app's folder, unless absolute
    out = tmp_path / "replay.png"
    subprocess.run([sys.executable, "-m", "app", "replay", str(session), "--headless",
                    "--out", str(out)], cwd=ROOT, check=True, timeout=120)
    replayed = np.asarray(Image.open(out).convert("RGB"))
    assert np.array_equal(replayed, np.asarray(image.convert("RGB")))
