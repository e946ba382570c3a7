"""The lock screen's live clock (app/lockscreen.py): its minutes as session events
(version 10), recorded by the simulation thread from a clock the test sets, shown by
renders and replays at the ticks the session showed them, and sent to the pages as the
clock box's pixels only.

The oracle for what a picture shows is the clock function drawn directly at that minute
over the lock screen's static parts (`clock_patch`): with no ice on the pane the glass is
clear and the frame is the backdrop exactly (docs/looks.md), so the frame's clock box
must equal it pixel for pixel."""

from __future__ import annotations

import concurrent.futures
import io
import json
import subprocess
import sys
from collections.abc import Callable
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.backdrops import LIVE, load_backdrop, read_backdrop
from app.lockscreen import (
    CLOCK_BOX,
    DEFAULT_MINUTE,
    clock_patch,
    outside_line,
    parse_clock,
    with_clock,
)
from sim import Params
from sim.io.session import SessionError, SessionLog
from sim.io.timeline import Timeline
from tests import frozen_runs

ROOT = Path(__file__).resolve().parent.parent
STATIC = np.asarray(read_backdrop(LIVE))
X0, Y0, X1, Y1 = CLOCK_BOX


def box(image: np.ndarray) -> np.ndarray:
    return image[Y0:Y1, X0:X1]


# ---- the picture ---------------------------------------------------------------------

def test_a_minute_changes_the_clock_box_and_nothing_else():
    a, b = with_clock(STATIC, "2026-11-26T15:41"), with_clock(STATIC, "2026-11-26T15:42")
    changed = np.argwhere((a != b).any(axis=2))
    assert len(changed) > 200  # the last digit, redrawn
    (top, left), (bottom, right) = changed.min(axis=0), changed.max(axis=0)
    assert Y0 <= top <= bottom < Y1 and X0 <= left <= right < X1
    outside = np.ones(STATIC.shape[:2], bool)
    outside[Y0:Y1, X0:X1] = False
    assert np.array_equal(a[outside], STATIC[outside])


def test_the_date_follows_the_day_and_the_static_box_is_bare_wallpaper():
    # Another day, the same time: the date line (the box's top 100 px) differs, the time
    # line does not.
    a, b = clock_patch(STATIC, "2026-11-26T15:41"), clock_patch(STATIC, "2026-11-27T15:41")
    assert (a[:100] != b[:100]).any() and np.array_equal(a[110:], b[110:])
    # The asset holds no clock: no white figures in its box (a few stars), the clock
    # draws thousands of white pixels there.
    assert (box(STATIC).min(axis=2) > 240).sum() < 100
    assert (box(with_clock(STATIC, DEFAULT_MINUTE)).min(axis=2) > 240).sum() > 5000


def test_the_clock_tells_the_afternoon_from_the_morning():
    """The clock is in 24-hour form: 15:41 is not 03:41 (whose figures a 12-hour clock
    draws for both), nor 00:05 12:05; the time line alone differs (the box's lower part)."""
    for late, early in (("2026-11-26T15:41", "2026-11-26T03:41"),
                        ("2026-11-26T00:05", "2026-11-26T12:05")):
        a, b = clock_patch(STATIC, late), clock_patch(STATIC, early)
        assert np.array_equal(a[:100], b[:100]) and (a[110:] != b[110:]).any(), (late, early)


def weather_at(celsius: float) -> dict:
    """A weather event's reading and glass at `celsius` outside (the fields a Reading has)."""
    return {"reading": {"place": "Stockholm", "latitude": 59.3, "longitude": 18.1,
                        "temperature_c": celsius, "humidity_pct": 80.0, "dew_point_c": -27.6,
                        "weather_code": 3, "is_day": False, "time": "2026-11-26T23:00"},
            "glass": {"glazing": "single", "room_c": 20.0, "room_humidity": 40.0}}


@pytest.mark.parametrize(("celsius", "says"), [(-25.0, "-25 °C outside"), (-0.4, "0 °C outside"),
                                               (6.6, "7 °C outside"), (-12.5, "-12 °C outside")])
def test_the_lock_screen_says_the_temperature_outside_in_whole_degrees(celsius, says):
    assert outside_line(weather_at(celsius)) == says
    assert outside_line(None) == ""


def test_the_temperature_outside_is_drawn_under_the_time_inside_the_box():
    """Under the time (the box's lower part, below its figures) and nowhere else; a new
    temperature redraws that line alone."""
    bare = clock_patch(STATIC, DEFAULT_MINUTE)
    cold = clock_patch(STATIC, DEFAULT_MINUTE, outside_line(weather_at(-25)))
    mild = clock_patch(STATIC, DEFAULT_MINUTE, outside_line(weather_at(6)))
    changed = np.argwhere((bare != cold).any(axis=2))
    assert (cold.min(axis=2) > 240).sum() - (bare.min(axis=2) > 240).sum() > 300  # white text
    assert changed[:, 0].min() > 264 - 10  # below the time's figures (their shadow's edge)
    assert np.array_equal(cold[:250], mild[:250]) and (cold[270:] != mild[270:]).any()
    whole = with_clock(STATIC, DEFAULT_MINUTE, "-25 °C outside")
    assert np.array_equal(box(whole), cold)


def test_load_backdrop_draws_the_default_minute_or_none():
    assert np.array_equal(load_backdrop(LIVE), with_clock(STATIC, DEFAULT_MINUTE))
    assert np.array_equal(load_backdrop(LIVE, minute=None), STATIC)
    assert np.array_equal(load_backdrop(LIVE, minute="2026-01-02T03:04"),
                          with_clock(STATIC, "2026-01-02T03:04"))


def test_clock_times_on_the_command_line():
    assert parse_clock("15:42") == datetime(2026, 11, 26, 15, 42)
    assert parse_clock("23:59:50") == datetime(2026, 11, 26, 23, 59, 50)
    assert parse_clock("2027-02-03T04:05") == datetime(2027, 2, 3, 4, 5)
    assert parse_clock("2027-02-03T04:05:58") == datetime(2027, 2, 3, 4, 5, 58)
    for bad in ("25:00", "15h42", "", "2027-02-30T04:05"):
        with pytest.raises(ValueError, match="clock"):
            parse_clock(bad)


# ---- sessions ----------------------------------------------------------------------------

def session(events, version=10, steps=40) -> dict:
    return {"format": "frost-session", "version": version, "seed": 2, "params": {},
            "steps": steps, "events": events}


def test_clock_events_are_checked_and_need_version_10():
    clock = {"tick": 0, "kind": "clock", "minute": "2026-11-26T15:41"}
    assert SessionLog.from_json(session([clock])).events == [clock]
    with pytest.raises(SessionError, match="needs version 10"):
        SessionLog.from_json(session([clock], version=9))
    for minute in ("15:41", "2026-11-26 15:41", "2026-02-30T15:41", 1541, "2026-11-26T15:41:00"):
        with pytest.raises(SessionError, match="minute"):
            SessionLog.from_json(session([{**clock, "minute": minute}]))
    # A session of minutes alone has nothing to replay (no file is written for it).
    assert not SessionLog.from_json(session([clock])).replayable()
    touch = {"tick": 3, "kind": "touch", "x": 100.0, "y": 100.0}
    assert SessionLog.from_json(session([clock, touch])).replayable()


def test_a_clock_event_leaves_the_frost_as_version_9_grew_it():
    # The frost of version 10 is version 9's: the same touches with minutes between them
    # grow the same ice, tick for tick.
    def grown(version, minutes):
        timeline = Timeline(Params.preset("fern"), 4, version=version)
        for k in range(30):
            if k % 10 == 0:
                timeline.apply([{"kind": "touch", "x": 200.0 + 10 * k, "y": 500.0}])
            if minutes and k % 7 == 0:
                timeline.apply([{"kind": "clock", "minute": f"2026-11-26T15:{k:02d}"}])
            timeline.step()
        return frozen_runs.state_hash(timeline.sim), timeline.geometry.heights.copy()

    (a, heights_a), (b, heights_b) = grown(9, False), grown(10, True)
    assert a == b and np.array_equal(heights_a, heights_b)
    with pytest.raises(ValueError, match="version 10"):
        Timeline(Params(), 1, version=9).apply([{"kind": "clock", "minute": DEFAULT_MINUTE}])


def test_version_10_grows_the_frost_stored_for_version_9():
    stored = json.loads((ROOT / "tests" / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.state_hash(frozen_runs.one_spot(version=10)) == stored["v9/one-spot"]


# ---- the simulation thread records the minutes shown ---------------------------------------

class FakeClock:
    def __init__(self, start: datetime):
        self.now = start

    def __call__(self) -> datetime:
        return self.now


def test_the_thread_records_each_minute_shown_at_its_tick():
    from app.simthread.thread import SimThread

    clock = FakeClock(datetime(2026, 11, 26, 15, 41, 50))
    thread = SimThread(Params.preset("fern"), 1, [(380.0, 640.0)])
    thread.clock = clock
    for _ in range(3):
        thread.tick()  # not shown: nothing recorded
    assert [e for e in thread.timeline.events if e["kind"] == "clock"] == []
    thread.show_clock("pages", True)
    for k in range(20):
        clock.now += timedelta(seconds=1)  # 15:41:51 ... 15:42:10
        thread.tick()
        if k == 12:
            thread.show_clock("pages", False)  # hidden from 15:42:04 ...
        if k == 15:
            thread.show_clock("window", True)  # ... and shown again at 15:42:07
    snapshot = thread.drain()[-1]
    clocks = [e for e in thread.timeline.events if e["kind"] == "clock"]
    assert [(e["tick"], e["minute"]) for e in clocks] == [(3, "2026-11-26T15:41"),
                                                          (12, "2026-11-26T15:42")]
    assert snapshot.minute == "2026-11-26T15:42"
    # (the session saved holds them, and checks as a file of version 10 or later)
    saved = SessionLog.from_json(json.loads(json.dumps(thread.session().as_json())))
    assert saved.version >= 10 and [e for e in saved.events if e["kind"] == "clock"] == clocks


# ---- renders and replays show the session's minutes --------------------------------------

@pytest.mark.gl
def test_a_replay_shows_the_minute_the_session_showed_at_each_tick(gl_ctx):
    from app.tools.replay import replay_offscreen

    # A touch far below the clock: its ice never reaches the box within 40 ticks.
    log_ = SessionLog.from_json({
        **session([{"tick": 0, "kind": "clock", "minute": "2026-11-26T15:41"},
                   {"tick": 0, "kind": "touch", "x": 380.0, "y": 1150.0},
                   {"tick": 20, "kind": "clock", "minute": "2026-11-26T15:42"}]),
        "view": {"light": [0.4, 0.5, 1.0], "features": True, "bumps": True,
                 "background": "lockscreen"}})
    shown = {}
    for ticks in (10, 19, 20, 40):
        offscreen = replay_offscreen(gl_ctx, log_, ticks)
        shown[ticks] = box(offscreen.frame())
        offscreen.release()
    first, second = (clock_patch(STATIC, f"2026-11-26T15:4{m}") for m in (1, 2))
    assert not np.array_equal(first, second)
    for ticks, want in ((10, first), (19, first), (20, second), (40, second)):
        assert np.array_equal(shown[ticks], want), ticks


@pytest.mark.gl
@pytest.mark.usefixtures("subprocesses")
def test_frost_render_shows_the_clock_it_is_given_and_the_same_every_time(tmp_path):
    def render(*extra: str) -> np.ndarray:
        out = tmp_path / f"r{len(list(tmp_path.iterdir()))}.png"
        subprocess.run([sys.executable, "-m", "app", "render", "--background", "lockscreen",
                        "--touch", "380,1150", "--ticks", "15", "--out", str(out), *extra],
                       cwd=ROOT, check=True, capture_output=True, timeout=300)
        return np.asarray(Image.open(out).convert("RGB"))

    given, default, again = render("--clock", "07:05"), render(), render()
    assert np.array_equal(box(given), clock_patch(STATIC, "2026-11-26T07:05"))
    assert np.array_equal(box(default), clock_patch(STATIC, DEFAULT_MINUTE))
    assert np.array_equal(default, again)
    bad = subprocess.run([sys.executable, "-m", "app", "render", "--clock", "7h05"], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "clock '7h05'" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) <= 2  # (usage, then the one-line error)


# ---- the pages get the clock box only ---------------------------------------------------------

def test_the_feed_sends_the_clock_box_of_each_minute_to_the_pages():
    from support.feed import ByHand, Wire

    from app.serve.feed import Feed
    from app.serve.pages import ConnectedPage as Page
    from app.serve.protocol import CLOCK, decode_clock, message_type
    from app.simthread.thread import SimThread

    clock = FakeClock(datetime(2026, 11, 26, 15, 41, 58))
    params = Params.preset("fern")
    thread = SimThread(params, 1, [(380.0, 640.0)])
    feed = Feed(params, 1, backdrop="lockscreen", thread=thread)
    thread.clock = clock
    page = Page(Wire(), "page", feed.ask_redraw)
    page.waiting = False  # (live: it gets what is broadcast)
    feed.pages.add(page)
    by_hand = ByHand(thread)
    try:
        by_hand.tick(feed, 2)  # the thread records 15:41 at its first tick shown
        clock.now += timedelta(seconds=3)
        by_hand.tick(feed, 2)
    finally:
        by_hand.stop()
    sent = [m for m, _end in page.queue if isinstance(m, bytes) and message_type(m) == CLOCK]
    minutes = [decode_clock(m)["minute"] for m in sent]
    assert minutes[-2:] == ["2026-11-26T15:41", "2026-11-26T15:42"]
    whole = io.BytesIO()
    Image.fromarray(load_backdrop(LIVE)).save(whole, "PNG")
    for m in sent:
        fields = decode_clock(m)
        assert (fields["x"], fields["y"], fields["x"] + fields["w"], fields["y"] + fields["h"]) == CLOCK_BOX
        picture = np.asarray(Image.open(io.BytesIO(fields["png"])).convert("RGB"))
        assert np.array_equal(picture, clock_patch(STATIC, fields["minute"]))
        assert len(m) < len(whole.getvalue()) / 2


class HeldLoop:
    """A running loop as the feed sees it, whose workers' results come when the test says
    (`finish`, in the order it gives): a slow drawing of a minute, met every time."""

    def __init__(self):
        self.held: list[tuple[concurrent.futures.Future, Callable, tuple]] = []

    def is_running(self) -> bool:
        return True

    def run_in_executor(self, _executor, fn, *args):
        future: concurrent.futures.Future = concurrent.futures.Future()
        self.held.append((future, fn, args))
        return future

    def call_soon_threadsafe(self, *_args) -> None:
        pass  # (the test pumps the feed itself)

    def finish(self, order=None) -> None:
        held, self.held = self.held, []
        for k in order or range(len(held)):
            future, fn, args = held[k]
            future.set_result(fn(*args))  # (its done callbacks run here)


@pytest.mark.parametrize("case", ["left", "stale"])
def test_a_minute_drawn_too_late_is_never_sent(case):
    """A minute's picture drawn on a worker after the lock screen was left, or after a
    newer minute was asked for, is not sent: a page never shows a clock over another
    backdrop, nor an older minute after a newer one."""
    from support.feed import ByHand, Wire

    from app.serve.feed import Feed
    from app.serve.pages import ConnectedPage as Page
    from app.serve.protocol import CLOCK, Input, decode_clock, message_type
    from app.simthread.thread import SimThread

    clock = FakeClock(datetime(2026, 11, 26, 15, 41, 58))
    params = Params.preset("fern")
    thread = SimThread(params, 1, [(380.0, 640.0)])
    feed = Feed(params, 1, backdrop="lockscreen", thread=thread)
    thread.clock, feed.workers.loop = clock, HeldLoop()
    page = Page(Wire(), "page", feed.ask_redraw)
    page.waiting = False  # (live: it gets what is broadcast)
    feed.pages.add(page)
    by_hand = ByHand(thread)
    try:
        by_hand.tick(feed, 2)  # 15:41 asked for; its drawing held
        if case == "left":
            feed.controls.handle(Input("backdrop", name="dusk"), {})
            by_hand.tick(feed, 2)
            feed.workers.loop.finish()
        else:
            clock.now += timedelta(seconds=3)
            by_hand.tick(feed, 2)  # 15:42 asked for too
            feed.workers.loop.finish(order=(2, 1, 0))  # (09:41, the default, asked first) 15:42 done first
    finally:
        by_hand.stop()
    sent = [decode_clock(m)["minute"] for m, _end in page.queue
            if isinstance(m, bytes) and message_type(m) == CLOCK]
    assert sent == ([] if case == "left" else ["2026-11-26T15:42"])


# ---- the window ------------------------------------------------------------------------------

WINDOW_RUN = """
"$PY" -m app --preset fern --seed 1 --background lockscreen --clock-start "$START" \\
    --touch 380,1150 --screenshot-dir "$OUT/shots" --session-dir "$OUT/sessions" \\
    --max-seconds 90 > "$OUT/app.log" 2>&1 &
APP=$!
W=$(xdotool search --sync --onlyvisible --name '^frost$' | head -1)
until grep -q 'stats (' "$OUT/app.log"; do sleep 0.2; done
xdotool mousemove --window "$W" 5 5 key --clearmodifiers s
until grep -q 'screenshot: ' "$OUT/app.log"; do sleep 0.2; done
xdotool key --clearmodifiers Escape
wait $APP
"""


@pytest.mark.usefixtures("window_tools")
def test_the_window_shows_and_records_the_clock_it_is_given(tmp_path):
    """The window under Xvfb with --clock-start: its screenshot's clock box is the clock
    function drawn directly at the minute that screenshot's own session file says was
    shown last, and the session at exit records that minute (version 10)."""
    import shlex
    import shutil

    from support.window import xvfb

    if shutil.which("xdotool") is None or shutil.which("Xvfb") is None:
        pytest.fail("Xvfb and xdotool are dependencies: apt-get install xvfb xdotool")
    given = {"PY": sys.executable, "START": "2026-11-26T07:05", "OUT": str(tmp_path),
             "PYTHONPATH": str(ROOT)}
    script = " ".join(f"{k}={shlex.quote(v)}" for k, v in given.items()) + "; export PYTHONPATH\n"
    done = xvfb(["sh", "-c", script + WINDOW_RUN], cwd=ROOT, timeout=180)
    log = (tmp_path / "app.log").read_text(encoding="utf-8")
    assert done.returncode == 0, log
    shots = sorted((tmp_path / "shots").glob("*.png"))
    assert shots, log
    beside = json.loads((tmp_path / "sessions" / f"{shots[0].stem}.json").read_text(encoding="utf-8"))
    minutes = [e["minute"] for e in beside["events"] if e["kind"] == "clock"]
    assert minutes and minutes[0] == "2026-11-26T07:05"
    shot = np.asarray(Image.open(shots[0]).convert("RGB"))
    assert np.array_equal(box(shot), clock_patch(STATIC, minutes[-1]))
    saved = json.loads(next((tmp_path / "sessions").glob("session-*.json")).read_text(encoding="utf-8"))
    assert saved["version"] >= 10
    assert [e for e in saved["events"] if e["kind"] == "clock"][:1] == \
        [e for e in beside["events"] if e["kind"] == "clock"][:1]
