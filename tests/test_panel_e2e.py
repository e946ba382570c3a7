"""End to end: the tuning panel under Xvfb, driven with xdotool like a user would.

One session (about 15 s) runs this file as a script on an Xvfb server of its own: it
starts the window with the panel's widget positions logged, shows the panel (M) in its
own window, clicks on it where no widget is, drags the hc slider, types a file name and
saves the parameter set, changes hc with a key over the phone, loads the set back, takes
a screenshot with the panel's button and presses Esc over the panel. The tests then read
its log, its session file, the saved set and the screenshot.
"""

from __future__ import annotations

import ctypes
import ctypes.util
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
from support import ROOT
from support.window import finish, played, wait_for, window_id, xdo

from sim import Params
from sim.io.paramsets import load_params
from sim.io.session import SessionLog

pytestmark = pytest.mark.usefixtures("window_tools")

# The window with the panel's debug lines (where each widget lies) in its log.
APP = ("import logging, sys; logging.getLogger('app.window.panel').setLevel(logging.DEBUG); "
       "from app.__main__ import main; sys.exit(main(sys.argv[1:]))")
PANEL = "^frost tuning"  # the panel window's title
EMPTY = (140, 1250)  # in the panel's window, below its last widget
# The set's file name, typed into the panel's field over its default: C and S are keys of
# the window too (clear, screenshot), which must not fire while the field is typed into.
SET = "sc-set.json"


def widget(log: Path, name: str) -> tuple[float, float, float, float]:
    """The widget's box (x, y, w, h) in the panel window's px."""
    pattern = rf"panel: {name} at (\d+),(\d+) size (\d+)x(\d+)"
    end = time.monotonic() + 20
    while time.monotonic() < end:
        boxes = [tuple(map(float, m)) for m in re.findall(pattern, log.read_text(encoding="utf-8"))]
        if boxes:
            return boxes[-1]
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


class ClientMessage(ctypes.Structure):
    """Xlib's XClientMessageEvent, padded to the size of an XEvent (24 longs)."""

    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("window", ctypes.c_ulong),
                ("message_type", ctypes.c_ulong), ("format", ctypes.c_int),
                ("l", ctypes.c_long * 5), ("pad", ctypes.c_long * 24)]


def close_window(wid: str) -> None:
    """Ask window `wid` to close as a window manager's close button does (a WM_DELETE_WINDOW
    message; this xdotool, 3.2016, has no windowquit)."""
    x11 = ctypes.CDLL(ctypes.util.find_library("X11"))
    x11.XOpenDisplay.restype, x11.XOpenDisplay.argtypes = ctypes.c_void_p, [ctypes.c_char_p]
    x11.XInternAtom.restype = ctypes.c_ulong
    x11.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
    x11.XSendEvent.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_long,
                               ctypes.c_void_p]
    x11.XFlush.argtypes = x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    display = x11.XOpenDisplay(None)
    event = ClientMessage(type=33, window=int(wid), format=32,  # 33: ClientMessage
                          message_type=x11.XInternAtom(display, b"WM_PROTOCOLS", 0))
    event.l[0] = x11.XInternAtom(display, b"WM_DELETE_WINDOW", 0)
    x11.XSendEvent(display, int(wid), 0, 0, ctypes.byref(event))
    x11.XFlush(display)
    x11.XCloseDisplay(display)


def drive(out: Path) -> None:
    log = out / "app.log"
    cmd = [sys.executable, "-c", APP, "--preset", "fern", "--seed", "2",
           "--screenshot-dir", "shots", "--session-dir", "sessions", "--max-seconds", "300"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with open(log, "w", encoding="utf-8") as sink:
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
    phone, wid = wid, window_id(name=PANEL)
    hc = widget(log, "hc")
    click(wid, *EMPTY)  # on the panel: no seed
    drag_slider(wid, hc)
    wait_for(log, r"params: hc=", 1)
    field = widget(log, "file")
    click(wid, field[0] + 40, field[1] + field[3] / 2)
    time.sleep(0.3)  # the click selected the whole name: typing replaces it
    xdo("type", "--delay", "30", SET)
    wait_for(log, rf"panel: the file field holds '{re.escape(SET)}'")  # typed, all of it
    save = widget(log, "save_params")
    click(wid, save[0] + save[2] / 2, save[1] + save[3] / 2)
    wait_for(log, r"params saved: ")
    xdo("mousemove", "--window", phone, "380", "640")
    xdo("key", "bracketright")  # hc up half a px, by key
    wait_for(log, r"params: hc=", 2)
    load = widget(log, "load_params")
    click(wid, load[0] + load[2] / 2, load[1] + load[3] / 2)
    wait_for(log, r"params loaded from \S+: hc=")
    time.sleep(1.0)
    shoot = widget(log, "screenshot")
    click(wid, shoot[0] + shoot[2] / 2, shoot[1] + shoot[3] / 2)  # the button, not S
    wait_for(log, r"screenshot: ")
    place, phone_place = xdo("getwindowgeometry", wid), xdo("getwindowgeometry", phone)
    xdo("mousemove", "--window", wid, *map(str, EMPTY))
    xdo("key", "m")  # over the panel: the window's key (the field is not typed into)
    wait_for(log, r"panel: hidden")
    xdo("mousemove", "--window", phone, "5", "5")
    xdo("key", "m")
    wait_for(log, r"panel: shown", 2)
    close_window(window_id(name=PANEL))
    wait_for(log, r"panel: hidden", 2)  # closed: hidden, the app goes on
    xdo("key", "Escape")
    return {"status": app.wait(timeout=60), "hc_box": hc, "panel_at": place,
            "phone_at": phone_place}


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
    costs = re.search(r"panel: (\d+) redraws, median ([\d.]+) ms, max ([\d.]+) ms.*shown "
                      r"([\d.]+) s: ([\d.]+) ms a second", run["log"])
    assert costs, run["log"][-2000:]
    print(f"benchmark: panel {costs[1]} redraws in {costs[4]} s of clicks, drags and typing, "
          f"median {costs[2]} ms, max {costs[3]}: {costs[5]} ms a second (GL finished, "
          "llvmpipe under Xvfb)")


def test_the_panel_is_a_window_right_of_the_phone_and_the_phone_keeps_its_size(run):
    assert "Position: 760,0" in run["result"]["panel_at"]  # no window manager: no frames
    assert re.search(r"Geometry: 400x\d+", run["result"]["panel_at"])
    shown = re.search(r"panel: shown \(its own window, 400x(\d+) at 760,0\)", run["log"])
    assert shown, run["log"][-2000:]
    assert "Geometry: 760x1280" in run["result"]["phone_at"]  # the phone's size, panel shown


def test_a_dragged_slider_is_one_change_recorded_with_its_tick(run):
    said = [float(v) for v in re.findall(r"params: hc=([\d.]+)", run["log"])]
    drag, key, load = changes(run)  # one for the whole drag, not one per pixel
    assert drag["params"]["hc"] == said[0] > 7.0  # dragged right from 7
    assert key["params"]["hc"] == said[0] + 0.5 == said[1]
    # Each at the tick it applied, counted from the rebuild before it (a new timeline).
    assert all(isinstance(e["tick"], int) and e["tick"] >= 0 for e in (drag, key, load))
    first = Params(**run["session"].params)
    assert Params(**drag["params"]) == first.replace(hc=said[0], step=first.step)


def test_m_over_the_panel_hides_it_and_closing_its_window_does_too(run):
    said = re.findall(r"panel: (shown|hidden)", run["log"])
    assert said == ["shown", "hidden", "shown", "hidden"], run["log"][-2000:]


def test_a_click_on_the_panel_plants_no_seed(run):
    assert [e for e in run["session"].events if e["kind"] == "touch"] == []


def test_keys_typed_into_the_panel_are_not_the_windows_keys(run):
    assert "cleared" not in run["log"]  # C
    assert len(re.findall(r"screenshot: ", run["log"])) == 1  # S: only the button's
    saved = re.findall(r"params saved: .*|panel: the file field holds .*", run["log"])
    assert re.search(rf"params saved: {re.escape(SET)}$", run["log"], re.M), saved


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
