"""The window's parts that need no display: the key table, letterboxing and cursor
mapping, the simulation thread's schedule, snapshots, rebuilds and failures."""

from __future__ import annotations

import dataclasses
import json
import logging
import math
import os
import re
import signal
import sys
import threading
import time

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from PIL import Image

from app import keys
from app.keys import BINDINGS, Binding, help_lines, key_table
from app.session_keeper import AUTOSAVE_PERIOD
from app.simthread import thread as simthread
from app.simthread.backlog import Backlog
from app.simthread.schedule import RATE_WINDOW
from app.simthread.thread import SimThread
from app.window import lost_display
from app.window.capture import Capture
from app.window.record import FRAME_GAP, Recorder
from app.window.status import IDLE_GAP, DrawRate, Status
from app.window.view import cursor_to_phone, fit_scale, letterbox, screen_scale
from sim import Params, preset_name, tuning
from sim.io.gestures import path_points
from sim.io.session import SessionLog


@pytest.fixture(autouse=True)
def input_backlog_on_a_still_clock(monkeypatch):
    """Threads driven tick by tick here apply every command sent before a tick in that
    tick: the backlog's time budget (tested in test_bounds) must not depend on the load."""
    monkeypatch.setattr(simthread, "Backlog", lambda **kw: Backlog(**kw, clock=lambda: 0.0))


# ---- keys ------------------------------------------------------------------------------


def test_every_key_is_bound_once_and_listed_in_the_help():
    codes = key_table(lambda name: name)
    assert len(codes) == sum(len(b.keys) for b in BINDINGS)
    assert len(help_lines()) == len(BINDINGS)
    presets = {b.keys: b.arg for b in BINDINGS if b.action == "preset"}
    assert presets == {**{(str(i),): name for i, name in enumerate(
        ["a-1", "a-2", "a-3", "b-1", "b-2", "b-3", "c-1", "c-2", "c-3"], start=1)}, ("0",): "fern",
        ("W",): "window"}
    # What README.md promises a user, written out by hand.
    text = "\n".join(help_lines())
    for label, word in (("Esc", "quit"), ("Space", "pause"), ("S F12", "screenshot"),
                        ("H", "help"), ("C", "clear"), ("G", "growth"), ("1", "a-1"),
                        ("9", "c-3"), ("]", "hc up"), ("=", "humidity up")):
        assert re.search(rf"^{re.escape(label)} {{2,}}.*{re.escape(word)}", text, re.M), label


def test_a_key_bound_twice_is_refused(monkeypatch):
    twice = (*BINDINGS, Binding(("SPACE",), "Space", "again", "pause"))
    monkeypatch.setattr(keys, "BINDINGS", twice)
    with pytest.raises(ValueError, match="SPACE is bound twice"):
        keys.key_table(lambda name: name)


def test_every_bound_action_exists_in_the_window():
    from app.window.actions import Actions

    actions = Actions(Params(), *[None] * 8)
    assert {b.action for b in BINDINGS} <= set(actions.table)


def test_key_names_are_glfw_keys():
    import glfw  # a hard dependency: its absence is a failure, not a skip

    key_table(lambda name: getattr(glfw, f"KEY_{name}"))


# ---- view --------------------------------------------------------------------------------


def test_fit_scale_shrinks_to_a_small_work_area_and_never_grows():
    assert fit_scale((1920, 2000)) == 1.0
    assert fit_scale((1920, 1080)) == pytest.approx(0.95 * 1080 / 1280)


@pytest.mark.parametrize("workarea", [(1366, 768), (1920, 1080), (2560, 1600), (3840, 2160)])
@pytest.mark.parametrize("content_scale", [1.0, 1.25, 1.5, 2.0])
@pytest.mark.parametrize("points", [False, True], ids=["pixels", "points"])
def test_the_window_opens_at_the_screens_scale_as_large_as_fits(workarea, content_scale, points):
    """760x1280 times the content scale where screen coordinates are pixels (Windows, X11),
    as it is where they are points (a Mac), no larger than 95 % of the work area."""
    scale = fit_scale(workarea, most=screen_scale(content_scale, points))
    w, h = round(760 * scale), round(1280 * scale)
    assert w <= 0.95 * workarea[0] + 1 and h <= 0.95 * workarea[1] + 1  # it fits
    wanted = 1.0 if points else content_scale
    if 1280 * wanted <= 0.95 * workarea[1] and 760 * wanted <= 0.95 * workarea[0]:
        assert scale == wanted  # room for all of it: the phone at the screen's scale
    else:
        assert h == pytest.approx(0.95 * workarea[1], abs=1)  # else as tall as fits
    if (workarea, content_scale) == ((3840, 2160), 1.5):  # worked by hand: 1140 x 1920
        assert (w, h) == ((1140, 1920) if not points else (760, 1280))


@pytest.mark.parametrize("ratio", [2.0, 1.5])
def test_a_click_lands_on_the_phone_point_under_it_whatever_the_framebuffers_density(ratio):
    """A framebuffer `ratio` times the window (a Retina Mac: 2; 1.5): the window's cursor
    maps through it to the phone point drawn under it."""
    window = (500, 1000)  # letterboxed: the phone 500 x 842.1 window px, 78.9 above and below
    framebuffer = (round(500 * ratio), round(1000 * ratio))
    phone_h = 500 * 1280 / 760
    top = (1000 - phone_h) / 2
    for px, py in ((2.0, 2.0), (380.0, 640.0), (756.0, 1276.0), (100.0, 1200.0)):
        cursor = (px * 500 / 760, top + py * phone_h / 1280)  # the window point over it
        got = cursor_to_phone(cursor, window, framebuffer)
        assert got is not None and got == pytest.approx((px, py), abs=1.5 / ratio + 0.6)
    assert cursor_to_phone((250.0, top - 5.0), window, framebuffer) is None  # the bar


def test_a_click_maps_each_axis_by_its_own_ratio_of_framebuffer_to_window():
    """A window of 507 x 853 at 150 % has a framebuffer of 760 x 1280 (each side rounded
    on its own: 1.499 across, 1.5006 down). The phone fills it; a cursor's x maps by the
    one ratio, its y by the other (hand-worked: x 253.5 * 760 / 507, y 852 * 1280 / 853)."""
    got = cursor_to_phone((253.5, 852.0), (507, 853), (760, 1280))
    assert got == pytest.approx((380.0, 852 * 1280 / 853), abs=1e-9)


def test_hud_text_is_drawn_at_the_windows_content_scale():
    from PIL import ImageFont

    from app.window.hud import FONT_SIZE, text_image

    lines = ["tick 1234\t25.0/s", "a longer second line\tx"]
    one = text_image(lines, ImageFont.load_default(size=FONT_SIZE), 1.0)
    two = text_image(lines, ImageFont.load_default(size=2 * FONT_SIZE), 2.0)
    assert two.size[0] == pytest.approx(2 * one.size[0], rel=0.08)
    assert two.size[1] == pytest.approx(2 * one.size[1], rel=0.08)


def test_letterbox_keeps_the_aspect_and_centres():
    assert letterbox((760, 1280)) == (0, 0, 760, 1280)
    x, y, w, h = letterbox((1000, 1280))
    assert (x, y, w, h) == (120, 0, 760, 1280)
    x, y, w, h = letterbox((760, 2000))
    assert (x, w) == (0, 760) and y == (2000 - 1280) // 2


def test_cursor_maps_through_hidpi_and_letterbox():
    # A 380x640 window on a 2x screen: the framebuffer is 760x1280.
    assert cursor_to_phone((190, 320), (380, 640), (760, 1280)) == (380, 640)
    # A wide window: bars of 120 px on each side.
    assert cursor_to_phone((120, 0), (1000, 1280), (1000, 1280)) == (0, 0)
    assert cursor_to_phone((100, 10), (1000, 1280), (1000, 1280)) is None
    assert cursor_to_phone((10, 10), (0, 0), (0, 0)) is None  # minimized


@given(cx=st.floats(-100, 1500), cy=st.floats(-100, 1500), w=st.integers(1, 1500),
       h=st.integers(1, 1500))
@example(cx=760.0, cy=5.0, w=760, h=1280)  # the right edge: px = 760.0 exactly
@example(cx=5.0, cy=1280.0, w=760, h=1280)
def test_a_spot_the_window_gives_is_one_a_session_file_takes(cx, cy, w, h):
    spot = cursor_to_phone((cx, cy), (w, h), (w, h))
    if spot is None:
        return
    touch = {"kind": "touch", "tick": 0, "x": spot[0], "y": spot[1]}
    melt = {"kind": "melt", "tick": 0, "x": spot[0], "y": spot[1], "r": 24.0}
    SessionLog.from_json({"format": "frost-session", "seed": 0, "params": {},
                          "events": [touch, melt]})  # raises if either is refused


def test_drag_path_points_are_evenly_spaced():
    pts = path_points((0, 0), (100, 0), 28)
    np.testing.assert_allclose(pts, [(28, 0), (56, 0), (84, 0)])
    assert path_points((0, 0), (10, 0), 28) == []


# ---- simulation thread -----------------------------------------------------------------


class FakeClock:
    """Time for the thread's schedule that moves only when it waits or a tick works
    (`work` seconds per step); the schedule stops after `ticks` ticks."""

    def __init__(self, thread: SimThread, work: float, ticks: int):
        self.now, self.starts, self.ticks = 100.0, [], ticks
        thread.schedule.clock, thread.schedule.wait = (lambda: self.now), self.wait
        step = thread.timeline.step

        def working_step():
            self.starts.append(self.now)
            self.now += work
            return step()

        thread.timeline.step = working_step

    def wait(self, seconds: float) -> bool:
        assert seconds >= 0
        self.now += seconds
        return len(self.starts) >= self.ticks


def test_ticks_every_dt_on_the_clock_with_immutable_snapshots():
    thread = SimThread(Params(), 0, [(380, 640)])
    clock = FakeClock(thread, work=0.012, ticks=50)
    thread.schedule.run(thread.tick)
    snaps = thread.drain()
    np.testing.assert_allclose(np.diff(clock.starts), 0.04)  # 25 per second, on schedule
    assert clock.starts[0] == pytest.approx(100.04)
    assert [s.stats.tick for s in snaps] == list(range(1, 51))
    assert snaps[-1].stats.rate == pytest.approx(25.0) and snaps[-1].stats.overruns == 0
    assert snaps[-1].stats.crystals >= 1 and snaps[-1].touches == ((380, 640),)
    with pytest.raises(AttributeError):
        snaps[0].stats.tick = 5


@pytest.mark.parametrize("work, gap, skipped", [(0.05, 0.08, 1), (0.13, 0.16, 3)])
def test_a_late_tick_skips_the_missed_slots_and_counts_them(work, gap, skipped):
    thread = SimThread(Params(), 0, dt=0.04)
    clock = FakeClock(thread, work=work, ticks=10)
    thread.schedule.run(thread.tick)
    snaps = thread.drain()
    np.testing.assert_allclose(np.diff(clock.starts), gap)  # no catching up
    # A snapshot reports the slots skipped before its tick; the thread counts them all.
    assert [s.stats.overruns for s in snaps] == [skipped * k for k in range(10)]
    assert thread.schedule.overruns == 10 * skipped
    assert snaps[-1].stats.rate == pytest.approx(1 / gap)


def test_the_real_clock_keeps_the_rate_printed_not_asserted():
    thread = SimThread(Params(), 0, [(380, 640)])
    thread.start()
    time.sleep(1.0)
    thread.stop()
    assert not thread.is_alive()
    snaps = thread.drain()
    assert [s.stats.tick for s in snaps] == list(range(1, len(snaps) + 1))
    print(f"benchmark: {len(snaps)} ticks in 1 s, rate {snaps[-1].stats.rate:.1f}/s, "
          f"{snaps[-1].stats.overruns} overruns")


def test_touch_applies_at_the_next_tick():
    thread = SimThread(Params(), 0)
    thread.send("touch", ((100.0, 200.0), (0, time.monotonic())))
    thread.tick()
    snap = thread.drain()[-1]
    assert snap.touches == ((100.0, 200.0),) and snap.stats.crystals >= 1
    assert len(snap.clicks) == 1


def test_param_change_rebuilds_and_replays_the_touches_deterministically():
    a = SimThread(Params(), 3, [(380, 640)])
    for _ in range(5):
        a.tick()
    a.send("params", Params(hc=8.0))
    for _ in range(20):
        a.tick()
    snaps = a.drain()
    assert snaps[5].reset and snaps[5].params.hc == 8.0 and snaps[5].stats.tick == 1
    b = SimThread(Params(hc=8.0), 3, [(380, 640)])
    for _ in range(20):
        b.tick()
    assert np.array_equal(a.sim.crystals, b.sim.crystals)


def test_every_map_export_asked_for_is_written_even_in_one_tick_or_at_stop(tmp_path):
    """E pressed three times within one tick, then twice more as the window closes: five
    folders, each with its three maps, and a notice for each; none overwrites another."""
    thread = SimThread(Params(), 0, [(380, 640)])
    folders = [tmp_path / f"maps-{i}" for i in range(5)]
    thread.tick()
    for folder in folders[:3]:
        thread.send("export", folder)
    thread.tick()
    for folder in folders[3:]:
        thread.send("export", folder)
    thread.stop()
    notices = [text for _, text in simthread.take_all(thread.notices)]
    for folder in folders:
        assert sorted(p.name for p in folder.iterdir()) == ["alpha.png", "height.png",
                                                            "normal.png"]
        assert sum(str(folder / "height.png") in text for text in notices) == 1
    assert len(notices) == 5


def test_a_subscriber_reads_every_snapshot_and_is_woken_after_each():
    woken: list[str] = []
    thread = SimThread(Params(), 0, [(380, 640)], wake=lambda: woken.append("maker"))
    thread.tick()
    drain = thread.subscribe(lambda: woken.append("reader"))
    for _ in range(3):
        thread.tick()
    mine, theirs = thread.drain(), drain()
    assert [s.stats.tick for s in mine] == [1, 2, 3, 4] and theirs == mine[1:]
    assert woken == ["maker"] + ["maker", "reader"] * 3
    thread.notify(logging.INFO, "a notice")  # (read by the maker, told to all)
    assert woken[-2:] == ["maker", "reader"] and drain() == []


def test_work_between_ticks_runs_once_after_the_snapshot_and_before_the_next_tick():
    thread = SimThread(Params(), 0, [(380, 640)])
    seen: list[tuple[int, int]] = []
    thread.tick()
    thread.between_ticks(lambda: seen.append((thread.sim.tick, thread.outbox.qsize())))
    thread.tick()  # its snapshot is out, then the work, with the sim still at that tick
    thread.tick()
    assert seen == [(2, 2)] and thread.drain()[1].stats.tick == 2


def test_pause_and_single_step():
    thread = SimThread(Params(), 0, [(380, 640)])
    thread.send("pause")
    thread.tick()
    thread.tick()
    thread.send("step")
    thread.tick()
    snaps = thread.drain()
    assert [s.stats.tick for s in snaps] == [0, 0, 1]
    assert snaps[0].delta is None and snaps[2].delta is not None


def test_a_click_while_paused_is_timed_when_it_shows():
    thread = SimThread(Params(), 0)
    thread.send("pause")
    thread.send("touch", ((100.0, 200.0), (0, 0.0)))
    thread.tick()
    thread.send("step")
    thread.tick()
    first, second = thread.drain()
    assert first.clicks == () and second.clicks == ((0, 0.0),)


def test_a_click_is_reported_grown_once_at_the_tick_its_seed_first_gets_a_child():
    thread = SimThread(Params(), 0, [(100.0, 100.0)])  # crystal 0: a seed nobody clicked
    thread.send("touch", ((380.0, 640.0), (0, 1.0)))
    seed, reported, first_child = 1, [], None
    for _ in range(60):
        thread.tick()
        snap = thread.drain()[-1]
        reported += [(snap.stats.tick, click) for click in snap.grown]
        if first_child is None and (thread.sim.parents == seed).any():  # the oracle
            first_child = snap.stats.tick
    assert first_child is not None and reported == [(first_child, (0, 1.0))]


def test_a_click_into_full_cells_is_neither_shown_nor_reported_grown():
    # Its touch plants nothing (version 9): the crystal planted last before it is not its
    # seed, and the click's frost never shows.
    thread = SimThread(Params.preset("fern", hc=16.0, D=1.0, grid_spacing=2), 0,
                       [(380.0, 640.0)] * 200)
    crystals = len(thread.sim.crystals)
    assert crystals < 200  # the cells filled: the later touches planted nothing
    thread.send("touch", ((380.0, 640.0), (0, 1.0)))
    shown, grown = [], []
    for _ in range(30):
        thread.tick()
        snap = thread.drain()[-1]
        shown += snap.clicks
        grown += snap.grown
    assert len(thread.sim.crystals) == crystals and shown == grown == []


def test_a_rebuild_forgets_the_seeds_it_renumbered():
    thread = SimThread(Params(), 0)
    thread.send("touch", ((380.0, 640.0), (0, 1.0)))
    thread.tick()
    thread.send("params", Params(hc=8.0))  # the touch is replanted, but not as a click
    grown = []
    for _ in range(60):
        thread.tick()
        grown += thread.drain()[-1].grown
    assert (thread.sim.parents == 0).any() and grown == []


@pytest.mark.parametrize("together", [False, True])
def test_a_right_drag_is_logged_when_a_frame_shows_all_its_melts(monkeypatch, caplog, together):
    from app.window.status import Status

    caplog.set_level(logging.INFO, logger="app.window")
    # One command a tick (a spent input budget). Melts arriving one a tick take three
    # ticks; arriving together (a fast drag) they are one group, applied in the first.
    monkeypatch.setattr(simthread, "Backlog", lambda **kw: Backlog(**kw, budget_s=0.0, clock=lambda: 0.0))
    thread, status = SimThread(Params.preset("c-3"), 0, [(380, 640)]), Status()
    xs = [360.0, 380.0, 400.0]
    sent = [thread.send("melt", (x, 640.0, 20.0)) for x in xs] if together else []
    status.melted(3, 3, 20.0)
    logged = []
    for k in range(3):
        if not together:
            sent.append(thread.send("melt", (xs[k], 640.0, 20.0)))
        thread.tick()
        for snap in thread.drain():
            status.shown(snap)
        status.presented(time.monotonic(), lambda now: [])
        logged.append(caplog.text.count("all shown"))
    assert sent == [1, 2, 3] and logged == ([1, 1, 1] if together else [0, 0, 1])
    tick = 1 if together else 3
    assert f"warm finger: 3 melts of radius 20 px, all shown at tick {tick}" in caplog.text
    assert thread.handled == 3 and len(thread.sim.crystal_alive) >= 1


def test_the_summary_gives_each_latency_kind_its_count_median_and_worst():
    from app.window.status import latency_summary

    clicks = [("frost", 1, 30.0), ("growth", 5, 200.0), ("frost", 1, 50.0), ("frost", 2, 40.0)]
    assert latency_summary(clicks) == ("frost 3 clicks median 40 ms max 50 ms, "
                                       "growth 1 clicks median 200 ms max 200 ms")
    assert latency_summary([]) == "none"


def test_clear_drops_touches_and_resets():
    thread = SimThread(Params(), 0, [(380, 640)])
    thread.tick()
    thread.send("clear")
    thread.tick()
    snap = thread.drain()[-1]
    assert snap.reset and snap.touches == () and snap.stats.crystals == 0


def test_a_failing_tick_is_reported_not_hung(monkeypatch, caplog):
    thread = SimThread(Params(), 0, [(380, 640)])
    monkeypatch.setattr(thread.geometry, "update", lambda sim: 1 / 0)
    thread.start()
    thread.join(60)  # (a bound on a hang, not a claim on speed)
    assert not thread.is_alive()
    snap = thread.drain()[-1]
    assert snap.error and "ZeroDivisionError" in snap.error
    assert "simulation thread failed" in caplog.text and "Traceback" in caplog.text


# ---- the HUD's figures ----------------------------------------------------------------------


def test_the_draw_rate_counts_redraws_while_drawing_and_reads_idle_between():
    rate = DrawRate()
    for t in (0.0, 0.04, 0.08, 0.12, 1.0, 1.04):  # 25 fps, a pause, 25 fps again
        rate.drew(t)
    assert rate.fps(1.05) == pytest.approx(25.0)  # the 0.88 s gap is not drawing
    assert rate.fps(1.04 + IDLE_GAP + 0.01) is None  # a still window is idle, not 3.6 fps
    for k in range(10):  # slow growth: a redraw every 0.3 s
        rate.drew(10.0 + 0.3 * k)
    assert rate.fps(12.8) == pytest.approx(1 / 0.3)


def test_the_tick_median_is_the_median_of_the_last_ticks_shown():
    thread = SimThread(Params(), 0, [(380, 640)])
    for _ in range(70):
        thread.tick()
    snaps = thread.drain()
    last = sorted(s.stats.tick_ms for s in snaps[-RATE_WINDOW:])
    middle = RATE_WINDOW // 2
    assert snaps[-1].stats.tick_median_ms == pytest.approx((last[middle - 1] + last[middle]) / 2)


def test_the_hud_shows_ticks_per_second_fps_while_drawing_and_the_tick_median():
    stats = simthread.Stats(tick=120, tick_ms=30.0, crystals=5, water=7, rate=24.5, overruns=2,
                            paused=False, tick_median_ms=3.25)
    snap = simthread.Snapshot(None, stats, Params(), ())
    view = type("View", (), {"show_features": True, "show_bumps": False,
                             "light": (0.0, 0.0, 1.0)})()
    status = Status()
    idle = status.lines(0.0, snap, Params(), view, None, 1.5)[:3]
    assert idle == ["sim 24.5 ticks/s  tick median  3.2 ms  overruns 2",
                    "drawing idle (nothing changed)  render  1.5 ms",
                    "tick 120  crystals 5  water 7  preset " + preset_name(Params())]
    for k in range(5):
        status.drawing.drew(100.0 + 0.05 * k)
    status.refresh(100.2, lambda now: status.lines(now, snap, Params(), view, None, 1.5))
    assert status.stats[1] == "drawing 20.0 fps  render  1.5 ms"
    assert status.lines(0.0, snap, Params(), view, None, 1.5)[-2] == "running"
    queued = simthread.Snapshot(None, dataclasses.replace(stats, waiting=312, paused=True),
                                Params(), ())
    lines = status.lines(0.0, queued, Params(), view, "REC 4 frames", 1.5)
    assert lines[0].endswith("overruns 2  input waiting 312")  # (the log's stats line too)
    assert lines[-2] == "PAUSED  REC 4 frames"


def test_the_hud_says_paused_not_a_tick_rate_while_paused():
    stats = simthread.Stats(tick=9, tick_ms=0.1, crystals=5, water=7, rate=25.0, overruns=0,
                            paused=True, tick_median_ms=0.1)
    lines = Status().lines(0.0, simthread.Snapshot(None, stats, Params(), ()), Params(), VIEW,
                           None, 1.5)
    assert lines[0] == "sim paused  tick median  0.1 ms  overruns 0" and lines[-2] == "PAUSED"


VIEW = type("View", (), {"show_features": True, "show_bumps": False, "light": (0.0, 0.0, 1.0)})()


def test_the_hud_shows_the_weather_outside_under_the_parameters():
    """The place and the reading, worked by hand: -25 C outside single glazing makes the
    glass 20 - 5.8 x 0.13 x 45 = -13.9 C."""
    from sim.weather import Glass, Reading

    stats = simthread.Stats(tick=9, tick_ms=0.1, crystals=5, water=7, rate=25.0, overruns=0,
                            paused=False, tick_median_ms=0.1)
    reading = Reading(place="Stockholm, Sweden", latitude=59.3, longitude=18.1,
                      temperature_c=-25.0, humidity_pct=80.0, dew_point_c=-27.6, weather_code=71,
                      is_day=False, time="2026-01-10T23:00")
    weather = {"reading": reading.as_json(), "glass": Glass().as_json()}
    params = Params.preset("window")
    plain = Status().lines(0.0, simthread.Snapshot(None, stats, params, ()), params, VIEW, None, 1.5)
    lines = Status().lines(0.0, simthread.Snapshot(None, stats, params, (), weather=weather),
                           params, VIEW, None, 1.5)
    assert lines[:3] == plain[:3]
    # The temperature the frost grows by is the weather's: 13.9 C below the onset (0 C: the
    # stated room's frost point, 5.6 C, lies above it), not the preset's 10.
    assert plain[3].endswith("  temperature -10 C")
    assert lines[3] == plain[3].replace("temperature -10 C", "temperature -13.9 C (the weather's)")
    assert lines[4] == ("weather Stockholm, Sweden: -25.0 C, 80 %, dew point -27.6 C at 23:00: "
                        "glass -14 C, frost grows")
    assert lines[5:] == plain[4:]


def test_in_a_thaw_the_hud_counts_the_crystals_alive_and_says_what_the_drawing_waits_for():
    from sim.weather import THAW_TICKS, Glass, Reading

    thread = SimThread(Params.preset("c-3"), 0, [(380, 640)])
    for _ in range(40):
        thread.tick()
    grown = thread.drain()[-1].stats.crystals
    warm = Reading("59.30,18.10", 59.3, 18.1, 6.0, 80.0, 2.0, 61, False, "2026-01-10T23:00")
    thread.show_weather(warm, Glass())  # glass 20 - 0.754 x 14 = 9.4 C: the ice melts
    for _ in range(2 * THAW_TICKS + 1):
        thread.tick()
    snaps = thread.drain()
    counts = [snap.stats.crystals for snap in snaps]
    # By hand: the crystals ever made, less those whose alive flag a melt cleared.
    ice = thread.sim.ice
    assert counts[-1] == len(ice.crystal_alive.raw()) - int((~ice.crystal_alive.raw()).sum())
    assert counts[-1] < grown and len(set(counts)) == 3  # two layers of tips melted
    status = Status()
    lines = status.lines(0.0, snaps[-1], snaps[-1].params, VIEW, None, 1.5)
    assert lines[1] == "drawing at each thaw step (the ice's edges melt every 50 ticks)  render  1.5 ms"
    assert lines[2].startswith(f"tick {snaps[-1].stats.tick}  crystals {counts[-1]}  ")
    assert lines[4].endswith("glass 9 C, frost melts")
    # The frosted window's temperature in a thaw: none, the weather's thaw.
    window = dataclasses.replace(snaps[-1], params=Params.preset("window"))
    line = status.lines(0.0, window, window.params, VIEW, None, 1.5)[3]
    assert line.endswith("  temperature: none, frost melts (the weather's)")
    # Paused, or with no ice left, nothing changes: idle.
    for stats in (dataclasses.replace(snaps[-1].stats, paused=True),
                  dataclasses.replace(snaps[-1].stats, crystals=0)):
        still = dataclasses.replace(snaps[-1], stats=stats)
        assert status.lines(0.0, still, still.params, VIEW, None, 1.5)[1].startswith("drawing idle")


def window_keys(params: Params):
    """The window's key handler over a simulation thread, with the HUD's Status."""
    import glfw

    from app.window.actions import Actions

    thread, status = SimThread(params, 0, [(380, 640)]), Status()
    actions = Actions(params, thread, None, status, None, None, lambda: None, lambda: None,
                      lambda: None)

    def press(key: str) -> list[str]:
        """`key` pressed, a tick applied as the window applies it: the HUD's lines."""
        actions.on_key(None, getattr(glfw, f"KEY_{key}"), 0, glfw.PRESS, 0)
        thread.tick()
        for snap in thread.drain():
            if snap.message:
                status.say(snap.message)
        return status.lines(time.monotonic(), snap, actions.params, VIEW, None, 1.0)

    return press


def test_t_and_y_show_the_temperature_in_the_hud_with_the_rebuild_they_made():
    press = window_keys(Params.preset("window"))
    lines = press("T")
    assert "temperature -12 C" in lines[3]  # the parameters' line (10 C below 0, then 2 more)
    assert lines[-3:] == ["params: temperature=12",
                          "rebuilt with 1 touch replanted at tick 0", "H help"]
    assert "temperature -10 C" in press("Y")[3]


def test_a_refused_t_in_the_fern_look_says_what_to_do():
    lines = window_keys(Params.preset("fern"))("T")
    assert lines[-2] == ("refused: temperature=12.0 needs window_frost=True: press W (the "
                         "frosted window) first")
    assert "temperature" not in lines[3]


def test_the_hud_keeps_the_last_messages_for_their_time(monkeypatch):
    from app.window import status as hud

    clock = StepClock()
    monkeypatch.setattr(hud.time, "monotonic", clock)
    status = Status()
    for k, text in enumerate(["a", "b", "c", "d"]):
        clock.now = k
        status.say(text)
    shown = [status.lines(now, None, Params(), VIEW, None, 1.0)[6:-1] for now in (3.5, 5.5)]
    # MESSAGES_SHOWN (3) at most, each for MESSAGE_SECONDS (4 s) from when it was said.
    assert shown == [["b", "c", "d"], ["c", "d"]]


@pytest.mark.parametrize("ticks, melts, words", [
    ([], 0, "rebuilt: nothing to replant (no touch yet)"),
    ([4], 0, "rebuilt with 1 touch replanted at tick 4"),
    ([4, 9], 1, "rebuilt with 2 touches replanted in their order by tick 9 and 1 melt at its tick"),
    ([4, 9, 2], 3, "rebuilt with 3 touches replanted in their order by tick 9 and 3 melts at "
     "their ticks")])
def test_a_rebuild_is_worded_in_the_singular_and_plural(ticks, melts, words):
    from sim.io.timeline import rebuilt_words
    assert rebuilt_words(ticks, melts) == words


# ---- the session kept on disk ---------------------------------------------------------------


class FakeRenderer:
    def __init__(self):
        self.light = [0.0, 0.0, 1.0]

    def view(self) -> dict:
        return {"light": list(self.light), "features": True, "bumps": True}


def keeper(tmp_path) -> tuple[SimThread, Capture, list[str], FakeRenderer]:
    thread = SimThread(Params(), 0, [(380, 640)])
    renderer, said = FakeRenderer(), []
    presenter = type("FakePresenter", (), {"renderer": renderer})()
    capture = Capture(thread, presenter, lambda text, *_: said.append(text), tmp_path / "shots",
                      tmp_path / "sessions")
    return thread, capture, said, renderer


def ticked(thread: SimThread, ticks: int):
    for _ in range(ticks):
        thread.tick()
    return thread.drain()[-1]


def test_the_session_file_follows_the_run_at_most_every_autosave_period(tmp_path):
    """What a process killed at once (SIGKILL, the display gone) leaves: the session as
    it was at the last save, saved again once it changed and AUTOSAVE_PERIOD passed."""
    thread, capture, said, renderer = keeper(tmp_path)
    saved, files, snap = [], [], None
    for now, ticks in ((0.0, 5), (1.0, 5), (AUTOSAVE_PERIOD, 5), (2 * AUTOSAVE_PERIOD, 0),
                       (3 * AUTOSAVE_PERIOD, 0)):
        snap = ticked(thread, ticks) if ticks else snap
        capture.keep_session(snap, now)
        capture.keeper.wait()
        saved.append(SessionLog.load(capture.session_path).steps)
        info = capture.session_path.stat()
        files.append((info.st_ino, info.st_mtime_ns))  # (a save replaces the file whole)
    assert saved == [5, 5, 15, 15, 15]  # too soon at 1 s; unchanged at the end
    # Two periods with nothing new: the file is left as it is, not written again.
    assert files[2] == files[3] == files[4] and files[1] != files[2]
    renderer.light = [0.5, 0.0, 0.866]  # the view alone changed: saved with it
    capture.keep_session(snap, 4 * AUTOSAVE_PERIOD)
    capture.keeper.wait()
    assert SessionLog.load(capture.session_path).view["light"] == [0.5, 0.0, 0.866]
    assert said == [] and len(list((tmp_path / "sessions").iterdir())) == 1


def test_an_autosave_never_holds_a_frame_nor_outlives_the_last_save(tmp_path, monkeypatch):
    """A slow disk: keep_session returns while its file is written, starts no second one
    meanwhile, and the save at exit waits for it, so the file ends with the last state."""
    thread, capture, _, _ = keeper(tmp_path)
    gate, save, writes = threading.Event(), SessionLog.save, []

    def slow_save(session, path):
        writes.append(session.steps)
        if len(writes) == 1:
            assert gate.wait(10)
        return save(session, path)

    monkeypatch.setattr(SessionLog, "save", slow_save)
    capture.keep_session(ticked(thread, 3), 0.0)  # returns with the write held at the gate
    capture.keep_session(ticked(thread, 3), 2 * AUTOSAVE_PERIOD)  # still writing: skipped
    last = ticked(thread, 3)
    threading.Timer(0.2, gate.set).start()
    capture.save_session(last)
    capture.keeper.wait()  # (nothing left to wait for)
    assert writes == [3, 9] and SessionLog.load(capture.session_path).steps == 9


def test_a_session_that_cannot_be_kept_is_told_once(tmp_path):
    thread, capture, said, _ = keeper(tmp_path)
    (tmp_path / "sessions").write_text("a file where the folder must be", encoding="utf-8")
    for k in range(3):
        capture.keep_session(ticked(thread, 1), k * AUTOSAVE_PERIOD)
        capture.keeper.wait()
    told = [text for _, text in simthread.take_all(thread.notices)]
    assert len(told) == 1 and told[0].startswith("session NOT saved: ") and said == []


@pytest.mark.skipif(not hasattr(signal, "SIGHUP"), reason="no SIGHUP on this platform")
def test_the_window_ends_on_a_signal_but_leaves_one_its_parent_ignored():
    """Under nohup (SIGHUP ignored by the parent) the window takes SIGTERM and Ctrl-C to end
    its loop and leaves SIGHUP ignored: a hang-up neither ends it nor kills it. Each signal
    has its handler of before once the window is closed."""
    from app.window.frost_window import _signals_end

    ended: list[int] = []
    app = type("FakeWindow", (), {"end_by": lambda self, num: ended.append(num)})()
    kept = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    try:
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        with _signals_end(app):
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
            for signum in (signal.SIGHUP, signal.SIGTERM, signal.SIGINT):
                os.kill(os.getpid(), signum)
            deadline = time.monotonic() + 30  # (Python runs a handler between bytecodes)
            while len(ended) < 2 and time.monotonic() < deadline:
                time.sleep(0.01)
        assert ended == [signal.SIGTERM, signal.SIGINT]
        assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        for signum, handler in kept.items():
            signal.signal(signum, handler)


def test_the_lost_display_handler_rescues_once_and_never_waits_on_itself():
    """Xlib may call its handler from the main and the simulation thread, and again from
    inside the rescue: one rescue; the rescuer returns at once; another thread waits (the
    process ends when the rescue returns)."""
    rescues = []
    handler = lost_display._once(lambda: rescues.append(handler(None)))
    first = threading.Thread(target=handler, args=(None,), daemon=True)
    first.start()
    first.join(60)
    assert not first.is_alive() and rescues == [0]  # the inner call returned at once
    other = threading.Thread(target=handler, args=(None,), daemon=True)
    other.start()
    other.join(0.3)
    assert other.is_alive() and rescues == [0]  # waits; no second rescue


def test_a_lost_window_is_reported_once_and_later_errors_on_it_alone_are_ignored():
    """Errors before a window is lost go on to the handler there was; the first BadWindow
    or BadDrawable is reported with its X id, and `lost` names the ids of that window (its
    GLX drawable's too); later errors on those ids are ignored, others are not: another
    error still goes on, and another window lost is reported in turn."""
    import ctypes

    lost, passed = [], []
    panel, phone = (0x40000D, 0x40000E), (0x400007, 0x400008)  # (X window, GLX window)

    def report(resource: int) -> tuple[int, ...]:
        lost.append(resource)
        return next(ids for ids in (panel, phone) if resource in ids)

    handler = lost_display.reporting(report, lambda d, e: passed.append(
        e.contents.error_code) or 7)

    def error(code: int, resource: int) -> int:
        event = lost_display.XErrorEvent(error_code=code, resourceid=resource)
        return handler(None, ctypes.pointer(event))

    glx_bad_window = 170  # GLX's error base + 12, met by glXDestroyWindow on a window gone
    assert error(8, 0x11) == 7 and passed == [8] and lost == []  # BadMatch: not ours
    assert error(lost_display.BAD_DRAWABLE, 0x40000D) == 0 and lost == [0x40000D]
    assert error(lost_display.BAD_WINDOW, 0x40000D) == 0  # the panel again: ignored
    assert error(glx_bad_window, 0x40000E) == 0  # its GLX drawable: ignored
    assert lost == [0x40000D] and passed == [8]
    assert error(8, 0x11) == 7 and passed == [8, 8]  # not the panel's: goes on
    assert error(lost_display.BAD_WINDOW, 0x400007) == 0 and lost == [0x40000D, 0x400007]
    assert error(glx_bad_window, 0x400008) == 0 and error(lost_display.BAD_DRAWABLE,
                                                          0x400007) == 0
    assert lost == [0x40000D, 0x400007] and passed == [8, 8]


def test_a_lost_window_that_names_no_ids_has_its_own_ignored_and_a_failing_report_is_kept():
    import ctypes

    calls = []

    def report(resource: int):
        calls.append(resource)
        raise RuntimeError("a bug in the report")  # must not unwind into Xlib

    handler = lost_display.reporting(report, lambda d, e: 7)
    event = lost_display.XErrorEvent(error_code=lost_display.BAD_WINDOW, resourceid=0x99)
    assert handler(None, ctypes.pointer(event)) == 0 and handler(None, ctypes.pointer(event)) == 0
    assert calls == [0x99]  # reported once, then ignored


# ---- recording ----------------------------------------------------------------------------


class StepClock:
    """A clock that reads `now`, moved by hand."""

    def __init__(self):
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def record(tmp_path, times: list[float], end: float, grey=lambda i: (7 * i) % 256
           ) -> tuple[list[int], int]:
    """Frames offered at `times` (frame i all `grey(i)`; by default each a different grey),
    stopped at `end`: the durations (ms) of the WebP written and how many were offered."""
    clock = StepClock()
    rec = Recorder(tmp_path, clock=clock)
    rec.toggle()
    for i, t in enumerate(times):
        clock.now = t
        rec.offer(lambda i=i: np.full((1280, 760, 3), grey(i), np.uint8))
    clock.now = end
    rec.toggle()
    rec.close()
    return webp_durations(tmp_path), len(times)


def webp_durations(folder) -> list[int]:
    """The frame durations (ms) of the one WebP in `folder`."""
    (path,) = folder.glob("*.webp")
    with Image.open(path) as image:
        assert image.size == (380, 640)
        durations = []
        for k in range(image.n_frames):
            image.seek(k)
            image.load()  # Pillow reads a frame's duration with its pixels
            durations.append(image.info["duration"])
    return durations


def test_a_recording_frame_lasts_until_the_next_one_kept(tmp_path):
    # Hand-worked: 0.03 and 0.05 come sooner than FRAME_GAP (0.08 s) after 0, 0.52 after
    # 0.5; the last frame lasts until the stop at 1.0.
    durations, _ = record(tmp_path, [0.0, 0.03, 0.05, 0.09, 0.2, 0.5, 0.52], end=1.0)
    assert durations == [90, 110, 300, 500]


def test_a_still_scene_records_one_frame_lasting_from_r_to_r(tmp_path):
    """Every frame the same (nothing moved in 38 s): libwebp keeps one frame, which must
    last the whole 38 s (hand-worked), not the 0 ms of a still image."""
    durations, _ = record(tmp_path, [0.1 * k for k in range(10)], end=38.0, grey=lambda i: 90)
    assert durations == [38000]


def test_the_last_frame_lasts_until_r_stopped_it_whatever_came_before(tmp_path):
    # Hand-worked: a grey at 0, another at 0.5 and again at 1.0 (merged with the one
    # before), stopped at 3.25: the second grey shows from 0.5 to the stop.
    durations, _ = record(tmp_path, [0.0, 0.5, 1.0], end=3.25, grey=lambda i: min(i, 1) * 99)
    assert durations == [500, 2750]


def test_a_still_scene_keeps_one_frame_in_memory_however_long_it_is_recorded(tmp_path):
    """40 s of the same frame, offered 32 times a second: one frame held (not the 375 of
    the cap, about 270 MB), no cap reached, and it lasts the 40 s (hand-worked). Every
    third offer is read (3/32 s >= FRAME_GAP > 2/32 s): the thinning counts from the last
    frame looked at, not the last kept."""
    clock, said, reads = StepClock(), [], []
    rec = Recorder(tmp_path, lambda level, text: said.append(text), clock=clock)
    rec.toggle()
    for k in range(1280):
        clock.now = k / 32
        rec.offer(lambda: reads.append(1) or np.full((1280, 760, 3), 90, np.uint8))
    assert rec.count == 1 and rec.readout() == "REC 1 frames" and not rec.full
    assert len(reads) == 427  # k = 0, 3, ..., 1278
    clock.now = 40.0
    rec.toggle()
    rec.close()
    assert not [t for t in said if "cap" in t]
    assert webp_durations(tmp_path) == [40000]


def one_pixel(grey: int) -> np.ndarray:
    """A grey frame with one pixel white: after the downscale still another frame."""
    frame = np.full((1280, 760, 3), grey, np.uint8)
    frame[641, 379] = 255
    return frame


def test_an_unchanged_frame_lengthens_the_last_and_a_one_pixel_change_is_a_new_one(tmp_path):
    # Hand-worked: A at 0 (again at 0.1), A with a pixel at 0.2 (again at 0.3), A at 0.4
    # (0.5), B at 0.6, stopped at 1.0: four frames of 200, 200, 200 and 400 ms.
    frames = [90, 90, "A+1", "A+1", 90, 90, 30]
    clock = StepClock()
    rec = Recorder(tmp_path, clock=clock)
    rec.toggle()
    for k, f in enumerate(frames):
        clock.now = 0.1 * k
        rec.offer(lambda f=f: one_pixel(90) if f == "A+1" else np.full((1280, 760, 3), f,
                                                                        np.uint8))
    assert rec.count == 4
    clock.now = 1.0
    rec.toggle()
    rec.close()
    assert webp_durations(tmp_path) == [200, 200, 200, 400]


@pytest.mark.parametrize("fps, seconds, run", [(21.0, 4.0, 5), (3.6, 10.0, 3), (60.0, 2.0, 7)])
def test_a_recording_with_repeated_frames_plays_as_long_as_it_was_recorded(
        tmp_path, fps, seconds, run):
    """Each grey offered `run` times in a row: it still plays R to R to the ms (the
    durations rounded on the running total), one frame per grey kept."""
    times = [100.0 + k / fps for k in range(int(seconds * fps))]
    durations, _ = record(tmp_path, times, end=100.0 + seconds, grey=lambda i: 9 * (i // run))
    assert sum(durations) == round(seconds * 1000)
    if fps < 1 / FRAME_GAP:
        assert len(durations) == -(-len(times) // run)


def test_an_unchanged_render_count_reads_nothing_and_a_skipped_render_is_read_later(tmp_path):
    """`drawn` (the phone's render count) the same as the frame last looked at: the same
    frame, not read. A render offered within FRAME_GAP of the last look is skipped, and
    read at the next offer though its count is unchanged since."""
    clock, reads = StepClock(), []
    rec = Recorder(tmp_path, clock=clock)
    rec.toggle()

    def offer(t: float, drawn: int, grey: int) -> None:
        clock.now = t
        rec.offer(lambda: reads.append(t) or np.full((1280, 760, 3), grey, np.uint8), drawn)

    offer(0.0, 1, 10)
    offer(0.1, 1, 10)  # no render since: nothing read
    offer(0.2, 1, 10)
    offer(0.25, 2, 50)  # a new render: read
    offer(0.3, 3, 90)  # 0.05 after the last look (0.25): skipped
    offer(0.34, 3, 90)  # its render not looked at yet: read now
    offer(0.5, 3, 90)
    assert reads == [0.0, 0.25, 0.34] and rec.count == 3
    clock.now = 1.0
    rec.toggle()
    rec.close()
    assert webp_durations(tmp_path) == [250, 90, 660]


SMALL = np.random.default_rng(3).integers(1, 255, (640, 380, 3), np.uint8)  # a frame kept


@given(st.integers(0, 639), st.integers(0, 379), st.integers(0, 2), st.sampled_from([-1, 1]))
@example(0, 0, 0, 1)
@example(639, 379, 2, -1)
def test_two_frames_are_the_same_exactly_when_every_byte_is(y, x, channel, step):
    """`same` against the obvious oracle: one channel of one pixel off by one differs."""
    from app.window.record import same

    other = SMALL.copy()
    assert same(Image.fromarray(SMALL), Image.fromarray(other))
    other[y, x, channel] = int(SMALL[y, x, channel]) + step  # (1..254: no wrap)
    assert not np.array_equal(SMALL, other)
    assert not same(Image.fromarray(SMALL), Image.fromarray(other))


def test_a_full_recording_is_written_and_the_next_r_ends_it(tmp_path, monkeypatch):
    """At MAX_FRAMES (4 here) the recording is written, keeps no more frames and says
    so; R then ends it (no new recording), and the R after starts one."""
    from app.window import record as recording
    monkeypatch.setattr(recording, "MAX_FRAMES", 4)
    clock, said = StepClock(), []
    rec = Recorder(tmp_path, lambda level, text: said.append(text), clock=clock)
    rec.toggle()
    for k in range(10):  # each grey twice: the cap counts distinct frames
        clock.now = 0.1 * k
        rec.offer(lambda k=k: np.full((1280, 760, 3), 40 * (k // 2), np.uint8))
        assert rec.full == (k >= 6)
    assert rec.count == 0 and not rec.active and rec.readout() == \
        "REC full (4 frames written, R ends)"
    rec.toggle()
    assert rec.readout() is None and not rec.active
    rec.close()
    assert webp_durations(tmp_path) == [200, 200, 200, round(FRAME_GAP * 1000)]
    assert "recording: 4 frames is the cap: written, no more kept (R ends it)" in said
    assert "recording: ended (written at the cap)" in said  # and the writer says it wrote:
    assert f"recording: 4 frames (0.7 s) written to {next(tmp_path.glob('*.webp'))}" in said
    rec.toggle()
    assert rec.active and rec.readout() == "REC 0 frames"


@pytest.mark.parametrize("fps, seconds", [(21.0, 4.0), (3.6, 10.0), (60.0, 2.0)])
def test_a_recording_plays_as_long_as_it_was_recorded(tmp_path, fps, seconds):
    """Drawn at 21 fps for 4 s, an idle window's 3.6 fps for 10 s, or faster than a
    recording keeps: it plays for as long as it was made."""
    times = [100.0 + k / fps for k in range(int(seconds * fps))]
    durations, offered = record(tmp_path, times, end=100.0 + seconds)
    assert sum(durations) == round(seconds * 1000)
    assert min(durations) >= FRAME_GAP * 1000 - 1  # at most 12.5 frames a second kept
    if fps < 1 / FRAME_GAP:
        assert len(durations) == offered


def test_recordings_stopped_while_another_is_written_get_their_own_files(tmp_path,
                                                                         monkeypatch):
    """R toggled fast: each recording's name is new though the writer of the one before
    has not made its file yet."""
    from app.window import record as recording
    gate, write = threading.Event(), recording.write_animation
    monkeypatch.setattr(recording, "write_animation",
                        lambda *args: (gate.wait(10), write(*args))[1])
    rec = Recorder(tmp_path)
    for grey in (0, 255, 128):
        rec.toggle()
        rec.offer(lambda g=grey: np.full((1280, 760, 3), g, np.uint8))
        rec.toggle()
    gate.set()
    rec.close()
    greys = []
    for path in tmp_path.glob("*.webp"):
        with Image.open(path) as image:
            greys.append(int(np.asarray(image.convert("L")).mean().round()))
    assert sorted(greys) == [0, 128, 255]


# ---- tuning -------------------------------------------------------------------------------


def test_lowering_hc_below_step_takes_step_with_it():
    p = tuning.shifted(Params(hc=3.0, step=3.0), "hc", -0.5)
    assert (p.hc, p.step) == (2.5, 2.5)


def test_invalid_values_are_refused_not_clamped_silently():
    with pytest.raises(ValueError, match="step"):
        tuning.shifted(Params(hc=3.0, step=3.0), "step", 0.5)
    with pytest.raises(ValueError, match="D"):
        tuning.shifted(Params(D=0.5), "D", -0.5)


def test_humidity_scales_and_presets_keep_the_rest():
    assert tuning.scaled(Params(humidity=3000), "humidity", 1.5).humidity == 4500
    assert tuning.scaled(Params(humidity=1), "humidity", 1 / 1.5).humidity == 1
    p = tuning.preset(Params(bump=2.0, step=1.0), "b-1")
    assert (p.hc, p.D, p.humidity, p.bump, p.step) == (3.0, 3.0, 3000, 2.0, 3.0)
    assert tuning.differences(Params(), Params(hc=8.0)) == {"hc": 8.0}


def test_growth_mode_toggles_and_keeps_the_rest():
    p = Params.preset("c-2")
    on = tuning.toggled(p, "grow")
    assert on.grow and tuning.differences(p, on) == {"grow": True}
    assert not tuning.toggled(on, "grow").grow
    assert any(b.keys == ("G",) and b.arg == "grow" for b in BINDINGS)


def test_the_thread_tells_its_backlog_what_each_step_cost(monkeypatch):
    # A clock that moves 3 units a reading: a step, timed by two readings, costs 3.
    now = [0.0]

    def clock():
        now[0] += 3.0
        return now[0]

    monkeypatch.setattr(simthread, "Backlog", lambda **kw: Backlog(**kw, budget_s=100.0, clock=clock))
    thread = SimThread(Params.preset("c-3"), 0, [(380, 640)])
    told: list[float] = []
    thread.backlog.stepped = told.append  # type: ignore[method-assign]
    thread.tick()
    assert told == [3.0]
    thread.paused = True
    thread.tick()  # no step while paused: nothing to learn
    assert told == [3.0]


def test_input_still_waiting_at_exit_is_reported_by_kind():
    thread = SimThread(Params.preset("c-3"), 0, [(380, 640)])
    for x in (100.0, 200.0):
        thread.send("touch", ((x, 300.0), None))
    thread.send("melt", (380.0, 640.0, 20.0))
    thread.send("params", Params.preset("c-2"))
    thread.send("pause")  # not a change of the frost: not counted
    thread.stop()  # never started: nothing applied
    notices = [thread.notices.get() for _ in range(thread.notices.qsize())]
    assert notices == [(logging.WARNING, "input still waiting at exit, never applied (not in the "
                        "session): 2 touches, 1 melts, 1 parameter changes")]
    assert thread.session().events == [{"kind": "touch", "x": 380.0, "y": 640.0, "tick": 0}]


def test_tuning_changes_replaced_before_their_tick_are_told_at_exit_and_the_last_is_kept():
    thread = SimThread(Params.preset("c-3"), 0, [(380, 640)])
    for name in ("c-1", "c-2", "fern"):  # three keys within one tick: the last one stands
        thread.send("params", Params.preset(name))
    thread.send("touch", ((100.0, 300.0), None))
    thread.send("params", Params.preset("c-3"))  # a touch between: not replaced
    thread.tick()
    thread.stop()
    notices = [thread.notices.get() for _ in range(thread.notices.qsize())]
    assert (logging.INFO, "2 parameter changes were replaced by the next before their tick "
            "(the session holds the later)") in notices
    params = [e for e in thread.session().events if e["kind"] == "params"]
    assert len(params) == 2 and thread.sent == 5


def test_a_session_saved_after_the_thread_ticked_past_the_frame_shown_replays_that_frame(tmp_path):
    """The window saves the frame it shows while the thread has gone on: a touch, a melt
    and a tuning change (a rebuild) applied after that frame must not reach its file."""
    from sim.io.timeline import replay

    thread, capture, _, _ = keeper(tmp_path)
    thread.send("touch", ((200.0, 300.0), None))
    shown = ticked(thread, 30)
    frozen = {k: getattr(thread.sim, k).copy() for k in ("crystals", "parents", "crystal_alive")}
    thread.send("touch", ((500.0, 900.0), None))
    thread.send("melt", (380.0, 640.0, 25.0))
    thread.send("params", Params(humidity=4000))
    ticked(thread, 12)
    assert len(thread.timeline.events) == 5 and thread.timeline.steps == shown.steps + 12
    path = capture.save_session(shown, tmp_path / "shown.json")
    log = SessionLog.load(path)
    assert (log.steps, [e["kind"] for e in log.events]) == (shown.steps, ["touch", "touch"])
    again = replay(log).sim
    assert again.tick == shown.stats.tick
    for name, value in frozen.items():
        assert np.array_equal(getattr(again, name), value), name


@pytest.mark.parametrize("start", ["fern", "window", "c-2"])
def test_the_scripted_scribble_presses_the_windows_own_tuning_keys(start):
    """app.bench.scribble's tuning changes are what the window's key table does, key by key
    (from fern, key 1 is Table 1's a-1 with the fern rules off, as in the window)."""
    from app.bench.scribble import tuning_changes

    by_label = {b.label: b for b in BINDINGS}
    act = {"scale": lambda p, a: tuning.scaled(p, *a), "shift": lambda p, a: tuning.shifted(p, *a),
           "toggle_param": tuning.toggled, "preset": tuning.preset}
    pressed, p = [], Params.preset(start)
    for label in ["=", "-", "]", "[", "'", ";", "P", "O", "L", "K", "G", "G", *"123456789"]:
        b = by_label[label]
        p = act[b.action](p, b.arg)
        pressed.append(p)
    assert tuning_changes(Params.preset(start)) == pressed
    assert pressed[-9] == Params.preset("a-1")  # the paper's a-1, whatever look it left


def test_without_imgui_the_panel_key_says_why_and_the_panel_costs_nothing(monkeypatch):
    from app.window.no_panel import NoPanel, no_wheel

    said: list[str] = []
    panel = NoPanel(said.append)
    with monkeypatch.context() as patched:
        patched.setitem(sys.modules, "imgui_bundle", None)  # (its import fails, as uninstalled)
        panel.toggle()
    # where pip installs it, it must have failed to import: the line says so, and how to
    # install it (the other reasons: tests/test_requirements.py)
    if no_wheel() is None:
        assert said[0].startswith("the tuning panel needs imgui-bundle==1.93.0, which cannot "
                                  "be imported (") and "pip install imgui-bundle==1.93.0" in said[0]
    assert len(said) == 1 and "\n" not in said[0] and "(H)" in said[0]
    panel.frame(True)
    assert not panel.needs_frame() and panel.readout(25) is None  # no cost on the stats line
    assert panel.lost(0x400007) == ()  # no window of its own to lose
    host = pytest.importorskip("app.window.panel_host").PanelHost
    used = {"toggle", "needs_frame", "frame", "readout", "lost", "close"}  # FrostWindow's calls
    assert used <= {n for n in dir(host) if not n.startswith("_")}
    assert used <= {n for n in dir(NoPanel) if not n.startswith("_")}


class _Failing:
    """A window whose loop raises, having lost a window (`lost`: its X id) or not."""

    def __init__(self, lost: int | None):
        self.lost_window, self.running, self.exit_status, self.closed = lost, True, 0, False

    def loop(self) -> int:
        raise RuntimeError("GL call on a dead drawable")

    def close(self) -> None:
        self.closed = True


@pytest.mark.parametrize("lost", [None, 0x400007])
def test_a_frame_that_fails_after_its_window_was_destroyed_is_no_new_error(lost, caplog):
    from app.window import frost_window

    app = _Failing(lost)
    with caplog.at_level(logging.INFO, logger="app.window"):
        assert frost_window._run(app) == 1
    assert app.closed and not app.running and app.exit_status == 1
    tracebacks = [r for r in caplog.records if r.exc_info]
    if lost is None:  # a real failure: its traceback is the report
        assert [r.getMessage() for r in tracebacks] == ["window failed"]
    else:  # the window's loss was said already: one line, no traceback
        assert tracebacks == []
        assert any("ended with the window gone" in r.getMessage() for r in caplog.records)


def test_a_replayed_session_grows_in_the_window_by_its_own_versions_rules():
    """The window replays a session (`frost replay` with a display) on its simulation
    thread: an older session must grow as it grew, by its version's rules (the headless
    replay, sim.io.timeline.replay, is the oracle), and the file the window keeps says that
    version. One spot tapped 20 times a tick past the cells' cap: version 9 caps it, 8 not."""
    from sim.io.session import SessionLog
    from sim.io.timeline import replay
    from tests.frozen_runs import state_hash

    params = Params.preset("fern", hc=16.0, D=1.0, grid_spacing=2)
    events = [{"kind": "touch", "x": 380.0, "y": 640.0, "tick": t} for t in range(15)
              for _ in range(20)]
    grown = {}
    for version in (8, 9):
        want = replay(SessionLog(11, params.as_dict(), events=events, steps=15, version=version))
        thread = SimThread(params, 11, (), script=events, version=version)
        for _ in range(15):
            thread.tick()
        grown[version] = state_hash(thread.timeline.sim)
        assert grown[version] == state_hash(want.sim), version
        assert thread.session().version == version
    assert grown[8] != grown[9]


def test_the_windowed_replay_takes_the_sessions_version(tmp_path):
    import argparse

    from app.cli import commands
    from sim.io.session import SessionLog

    path = tmp_path / "old.json"
    log_ = SessionLog(3, Params.preset("c-2").as_dict(), events=[], steps=5, version=8)
    path.write_text(json.dumps(log_.as_json()), encoding="utf-8")
    args = argparse.Namespace(replay=str(path), background=None, light=None, features=None,
                              bumps=None, params_file=None)
    commands._windowed_replay(args)
    assert args.session_version == 8 and args.seed == 3


def test_the_arrow_keys_move_the_light_a_step_a_press_and_never_past_its_tilt():
    """Right pressed from straight on moves the light LIGHT_STEP a press on the screen,
    until it is MAX_LIGHT_TILT off the axis (it never grazes the glass), where more presses
    keep it; Left then moves it back a step, and Up from there keeps it on the rim. At every
    press the light is a unit vector toward the viewer. The oracle: the steps counted by
    hand, the rim's point by Pythagoras."""
    import types

    import glfw

    from app.keys import LIGHT_STEP
    from app.window.actions import MAX_LIGHT_TILT, Actions

    renderer = types.SimpleNamespace(light=(0.0, 0.0, 1.0))
    actions = Actions(Params(), SimThread(Params(), 0), types.SimpleNamespace(renderer=renderer),
                      Status(), None, None, lambda: None, lambda: None, lambda: None)

    def press(key: str, times: int = 1) -> tuple[float, float, float]:
        for _ in range(times):
            actions.on_key(None, getattr(glfw, f"KEY_{key}"), 0, glfw.PRESS, 0)
            x, y, z = renderer.light
            assert math.isclose(x * x + y * y + z * z, 1.0) and z > 0, renderer.light
            assert math.hypot(x, y) <= MAX_LIGHT_TILT + 1e-12, renderer.light
        return renderer.light

    inside = int(MAX_LIGHT_TILT / LIGHT_STEP)  # presses that stay inside the tilt
    assert inside >= 2
    for k in range(1, inside + 1):
        x, y, z = press("RIGHT")
        assert (x, y) == pytest.approx((k * LIGHT_STEP, 0.0)), k
    rim = (MAX_LIGHT_TILT, 0.0, math.sqrt(1 - MAX_LIGHT_TILT ** 2))
    assert press("RIGHT", 5) == pytest.approx(rim)
    assert press("LEFT") == pytest.approx((MAX_LIGHT_TILT - LIGHT_STEP, 0.0,
                                           math.sqrt(1 - (MAX_LIGHT_TILT - LIGHT_STEP) ** 2)))
    x, y, _ = press("UP", 3 * inside)
    assert math.hypot(x, y) == pytest.approx(MAX_LIGHT_TILT) and y < 0 < x
