"""What the user sees is what was recorded: screenshots, map exports and session files
state the snapshot that made their image, snapshots and exports are copies, a replay
draws the screenshot again bit for bit (view included), writers fail loudly and
atomically, long headless runs show progress and stop cleanly on Ctrl-C."""

from __future__ import annotations

import json
import logging
import os
import signal
import subprocess
import sys
import threading
import types
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.images import export_maps, read_image, save_png
from app.simthread import export
from app.simthread.thread import SimThread
from app.window.record import Recorder
from sim import Params
from sim.io.files import write_all_atomic, write_atomic
from sim.io.session import SessionLog
from sim.io.timeline import replay
from sim.look.maps import live_segments

ROOT = Path(__file__).resolve().parent.parent
PARAMS = Params.preset("c-3")
VIEW = {"light": [0.4, 0.2, 0.8944271909999159], "features": False, "bumps": True}


def unwritable(tmp_path: Path) -> Path:
    """A folder no one can make, root included: its parent is a regular file."""
    (tmp_path / "afile").write_text("not a folder", encoding="utf-8")
    return tmp_path / "afile" / "sub"


def ticked(thread: SimThread, n: int) -> list:
    for _ in range(n):
        thread.tick()
    return thread.drain()


# ---- snapshots and exports are copies of one tick --------------------------------------


def test_snapshots_do_not_change_when_the_simulation_goes_on():
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    snap = ticked(thread, 8)[-1]
    thread.send("melt", (380.0, 640.0, 30.0))
    melt_snap = ticked(thread, 1)[-1]
    kept = [(d.heights.copy(), d.features.copy()) for d in (snap.delta, *melt_snap.melts)]
    thread.send("touch", ((390.0, 650.0), None))
    ticked(thread, 30)  # the same rows keep growing
    rows = snap.delta.rows
    assert not np.array_equal(thread.geometry.heights[rows], kept[0][0])  # it did change
    for d, (heights, features) in zip((snap.delta, *melt_snap.melts), kept, strict=True):
        assert np.array_equal(d.heights, heights) and np.array_equal(d.features, features)
    assert snap.touches == ((380.0, 640.0),)


class HeightsShown:
    """The renderer's height grid on the CPU, fed snapshots as Snapshot's fields say: clear
    when `reset`, then the `melts`, then `delta` (each delta clears first if it resets)."""

    def __init__(self, thread: SimThread):
        self.grid = np.zeros_like(thread.geometry.heights)

    def show(self, snaps) -> None:
        for snap in snaps:
            if snap.reset:
                self.grid[:] = 0
            for delta in (*snap.melts, *([snap.delta] if snap.delta is not None else [])):
                if delta.reset:
                    self.grid[:] = 0
                self.grid[delta.rows] = delta.heights


@pytest.mark.parametrize("paused", [False, True])
@pytest.mark.parametrize("order", [("melt", "params"), ("params", "melt")])
def test_a_melt_and_a_parameter_change_in_one_tick_show_the_new_frost_only(order, paused,
                                                                          monkeypatch):
    """The frame after a tick holding a melt and a rebuild is the thread's own heights: the
    melt of the frost the rebuild replaced must not reach the renderer after its reset
    (paused, no step's delta follows to cover it)."""
    from app.simthread import thread as simthread  # every command sent applies at one tick
    backlog = simthread.Backlog
    monkeypatch.setattr(simthread, "Backlog", lambda **kw: backlog(**kw, clock=lambda: 0.0))
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    shown = HeightsShown(thread)
    shown.show(ticked(thread, 12))
    assert np.array_equal(shown.grid, thread.geometry.heights) and shown.grid.any()
    # A melt smaller than the frost: the rows it sends hold the ice left around it.
    args = {"melt": (380.0, 640.0, 10.0), "params": PARAMS.replace(hc=PARAMS.hc + 0.5),
            "pause": None}
    for kind in ("pause",) * paused + order:
        thread.send(kind, args[kind])
    (snap,) = ticked(thread, 1)
    assert snap.reset and (snap.delta is None) == paused
    shown.show([snap])
    assert np.array_equal(shown.grid, thread.geometry.heights)
    shown.show(ticked(thread, 5))
    assert np.array_equal(shown.grid, thread.geometry.heights)


def test_exported_arrays_are_copies_the_simulation_cannot_change(monkeypatch):
    jobs, done = [], threading.Event()
    monkeypatch.setattr(export, "write_maps", lambda *job: (jobs.append(job), done.set()))
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    ticked(thread, 10)
    thread.send("export", Path("unused"))
    ticked(thread, 1)
    assert done.wait(10)
    grid, segments = thread.geometry.heights.copy(), live_segments(thread.sim).copy()
    ticked(thread, 30)
    assert not np.array_equal(thread.geometry.heights, grid)  # the frost grew on
    _, got_grid, got_segments, *_ = jobs[0]
    assert np.array_equal(got_grid, grid) and np.array_equal(got_segments, segments)


def test_an_export_states_the_tick_touches_and_params_of_its_arrays(tmp_path):
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    ticked(thread, 12)
    thread.send("export", tmp_path / "live")
    thread.send("touch", ((200.0, 300.0), None))  # the same tick, after the request
    snap = ticked(thread, 1)[-1]
    level, text = thread.notices.get(timeout=30)
    assert level == logging.INFO and "frost maps written" in text
    oracle = export_maps(tmp_path / "oracle", thread.geometry.heights,
                         live_segments(thread.sim), thread.params, {})
    for name, path in oracle.items():
        live = Image.open(tmp_path / "live" / path.name)
        np.testing.assert_array_equal(np.asarray(live), np.asarray(Image.open(path)), name)
        assert live.text["tick"] == str(snap.stats.tick) and live.text["seed"] == "1"
        # (the second touch applied at tick 12, before the tick's export)
        assert json.loads(live.text["touches"]) == [[0, 380.0, 640.0], [12, 200.0, 300.0]]
        assert live.text["Software"] == "frost (window, key E)"
        assert json.loads(live.text["parameters"]) == snap.params.as_dict()
    assert len(snap.touches) == 2


# ---- the window states the snapshot shown (its methods on a stand-in, no display) --------


class FakeFbo:
    size = (4, 2)

    def read(self, components, alignment):
        return bytes(range(24))


def window_standin(tmp_path: Path, shots: Path, sessions: Path, touches=((380.0, 640.0),)):
    """The window's Capture on a real simulation thread, with a stand-in presenter (no GL)."""
    from app.window.capture import Capture

    said = []
    thread = SimThread(PARAMS, 3, list(touches))
    presenter = types.SimpleNamespace(renderer=types.SimpleNamespace(view=lambda: dict(VIEW)),
                                      render_phone=lambda: None,
                                      read_phone=lambda: read_image(FakeFbo()))
    capture = Capture(thread, presenter, lambda text, level=logging.INFO: said.append((level, text)),
                      shots, sessions)
    return types.SimpleNamespace(capture=capture, thread=thread, latest=None, params=PARAMS), said


def take_shot(win) -> None:
    win.capture.screenshot(win.latest, win.params)


def test_a_screenshot_states_the_snapshot_shown_not_a_key_pressed_since(tmp_path):
    win, said = window_standin(tmp_path, tmp_path / "shots", tmp_path / "sessions")
    win.latest = ticked(win.thread, 5)[-1]
    win.params = PARAMS.replace(hc=7.5)  # a key press the thread has not applied yet
    win.thread.send("params", win.params)
    take_shot(win)
    (shot,) = win.capture.screenshots
    text = Image.open(shot).text
    assert json.loads(text["parameters"]) == PARAMS.as_dict()
    assert text["tick"] == "5" and json.loads(text["view"]) == VIEW
    log_ = SessionLog.load(text["session"])
    assert replay(log_).params == PARAMS and log_.view == VIEW and log_.steps == 5
    assert said[-1] == (logging.INFO, f"screenshot: {shot}")


def test_a_screenshot_states_the_frame_shown_though_the_thread_ticked_past_it(tmp_path):
    """The window draws snapshot 5 while the thread has ticked to 9 and planted a touch
    (those snapshots not yet drained): the PNG and its session state tick 5."""
    win, said = window_standin(tmp_path, tmp_path / "shots", tmp_path / "sessions")
    win.latest = ticked(win.thread, 5)[-1]
    win.thread.send("touch", ((200.0, 300.0), None))
    ticked(win.thread, 4)
    assert win.thread.sim.tick == 9
    take_shot(win)
    (shot,) = win.capture.screenshots
    text = Image.open(shot).text
    assert text["tick"] == "5" and json.loads(text["touches"]) == [[0, 380.0, 640.0]]
    log_ = SessionLog.load(text["session"])
    assert log_.steps == 5 and [e["kind"] for e in log_.events] == ["touch"]
    assert replay(log_).sim.tick == 5


@pytest.mark.parametrize("bad", ["shots", "sessions", "both"])
def test_a_screenshot_into_an_unwritable_folder_is_reported_not_raised(tmp_path, bad):
    nowhere = unwritable(tmp_path)
    shots = nowhere if bad in ("shots", "both") else tmp_path / "shots"
    sessions = nowhere if bad in ("sessions", "both") else tmp_path / "sessions"
    win, said = window_standin(tmp_path, shots, sessions)
    win.latest = ticked(win.thread, 2)[-1]
    take_shot(win)
    warnings = [t for level, t in said if level == logging.WARNING]
    assert warnings and all("NOT saved" in t and "afile" in t and "a file is in the way" in t
                            for t in warnings)
    assert len(win.capture.screenshots) == (bad == "sessions")  # what can be written still is
    assert len(list(tmp_path.rglob("*.tmp"))) == 0


def test_a_full_disk_at_a_screenshot_names_the_file_and_keeps_its_session(tmp_path,
                                                                          monkeypatch):
    def full(_image, path, _meta):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("app.window.capture.save_png", full)
    win, said = window_standin(tmp_path, tmp_path / "shots", tmp_path / "sessions")
    win.latest = ticked(win.thread, 2)[-1]
    take_shot(win)
    level, text = said[-1]
    assert level == logging.WARNING and text.startswith("screenshot NOT saved: ")
    assert str(tmp_path / "shots" / "frost-") in text and text.endswith(".png: No space left on device")
    assert len(list((tmp_path / "sessions").glob("*.json"))) == 1 and not win.capture.screenshots


def test_failed_screenshots_in_one_second_never_share_a_session_file(tmp_path):
    win, said = window_standin(tmp_path, unwritable(tmp_path), tmp_path / "sessions")
    win.latest = ticked(win.thread, 2)[-1]
    take_shot(win)
    win.latest = ticked(win.thread, 2)[-1]
    take_shot(win)
    steps = sorted(SessionLog.load(p).steps for p in (tmp_path / "sessions").glob("*.json"))
    assert steps == [2, 4]  # the first is not overwritten by the second
    names = [win.capture.fresh_name("") for _ in range(3)]  # e.g. map folders asked for at once
    assert len(set(names)) == 3


def test_a_window_run_with_no_event_leaves_no_session_file(tmp_path):
    sessions = tmp_path / "sessions"
    win, _ = window_standin(tmp_path, tmp_path / "shots", sessions, touches=())
    win.latest = ticked(win.thread, 3)[-1]
    assert win.capture.save_session(win.latest) is None and not sessions.exists()
    win.thread.send("melt", (100.0, 100.0, 20.0))  # one event: now there is a run to replay
    win.latest = ticked(win.thread, 2)[-1]
    saved = win.capture.save_session(win.latest)
    assert [p.name for p in sessions.iterdir()] == [saved.name]
    assert [e["kind"] for e in SessionLog.load(saved).events] == ["melt"]


# ---- atomic writes -------------------------------------------------------------------


@pytest.mark.parametrize("error", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, error):
    path = tmp_path / "s.json"
    write_atomic(path, lambda f: f.write(b"old"))

    def half(f):
        f.write(b"new but ")
        raise error

    with pytest.raises(type(error)):
        write_atomic(path, half)
    assert path.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]
    assert oct(path.stat().st_mode & 0o777) == oct(0o666 & ~current_umask())


def current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_a_set_of_files_appears_whole_or_not_at_all(tmp_path):
    def full(_f):
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError):
        write_all_atomic({tmp_path / "a": lambda f: f.write(b"a"), tmp_path / "b": full})
    assert list(tmp_path.iterdir()) == []
    write_all_atomic({tmp_path / "a": lambda f: f.write(b"a"), tmp_path / "b": lambda f: None})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "b"]


def test_every_writer_raises_oserror_on_an_unwritable_folder(tmp_path):
    nowhere = unwritable(tmp_path)
    with pytest.raises(NotADirectoryError):
        SessionLog(0, {}).save(nowhere / "s.json")
    with pytest.raises(NotADirectoryError):
        save_png(np.zeros((2, 2, 3), np.uint8), nowhere / "x.png", {})
    with pytest.raises(NotADirectoryError):
        export_maps(nowhere, np.zeros((3, 3), np.float32), np.zeros((0, 4)), PARAMS, {},
                    width=8, height=8)


def test_a_map_set_that_fails_half_way_leaves_no_maps(tmp_path, monkeypatch):
    from app import images

    real = images.png_writer

    def disk_full_at_alpha(image, meta):
        if meta["map"] != "alpha":
            return real(image, meta)
        return lambda f: (_ for _ in ()).throw(OSError(28, "No space left on device"))

    monkeypatch.setattr(images, "png_writer", disk_full_at_alpha)
    with pytest.raises(OSError):
        export_maps(tmp_path, np.ones((3, 3), np.float32), np.zeros((0, 4)), PARAMS, {},
                    width=8, height=8)
    assert list(tmp_path.iterdir()) == []


def test_an_export_worker_that_cannot_write_reports_it(tmp_path):
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    ticked(thread, 3)
    thread.send("export", unwritable(tmp_path) / "maps")
    ticked(thread, 1)
    level, text = thread.notices.get(timeout=30)
    assert level == logging.WARNING and "NOT written" in text and "afile" in text


def test_a_recording_that_cannot_be_written_is_reported(tmp_path, monkeypatch):
    said = []
    rec = Recorder(unwritable(tmp_path), lambda _level, text: said.append(text))
    rec.start()
    rec.offer(lambda: np.zeros((1280, 760, 3), np.uint8))
    rec.stop()  # cannot even name the file: reported at once
    assert "1 frames lost" in said[-1]
    rec = Recorder(tmp_path / "ok", lambda _level, text: said.append(text))
    rec.start()
    rec.offer(lambda: np.zeros((1280, 760, 3), np.uint8))
    monkeypatch.setattr("app.window.record.write_atomic", lambda *a: (_ for _ in ()).throw(
        PermissionError(13, "Permission denied")))  # root ignores the mode: fail as it would
    rec.close()
    assert "recording NOT written: " in said[-1] and "Permission denied" in said[-1]


# ---- a replay draws the screenshot again, view and touches included ------------------


def test_a_replay_with_a_moved_light_and_no_features_matches_the_live_frame(gl_ctx, tmp_path):
    from app.images import read_image
    from app.tools.offscreen import Offscreen
    from app.tools.replay import replay_offscreen

    thread = SimThread(PARAMS, 4, [(380.0, 640.0)])
    thread.send("touch", ((300.0, 500.0), None))
    snaps = ticked(thread, 40)
    live = Offscreen(gl_ctx, PARAMS, 4)
    live.renderer.set_view(VIEW)
    for snap in snaps:
        live.renderer.apply(snap.delta)
    live.renderer.render(live.fbo)
    log_ = thread.session(snaps[-1].steps, snaps[-1].events)
    log_.view = live.renderer.view()
    again = replay_offscreen(gl_ctx, SessionLog.load(log_.save(tmp_path / "s.json")))
    shot = again.snapshot(tmp_path / "again.png")
    assert np.array_equal(read_image(live.fbo), np.asarray(Image.open(shot)))
    log_.view = None  # the defaults: a different picture, so the view is what matched
    plain = replay_offscreen(gl_ctx, log_)
    plain.renderer.render(plain.fbo)
    assert not np.array_equal(read_image(live.fbo), read_image(plain.fbo))
    text = Image.open(shot).text
    assert json.loads(text["view"]) == {**VIEW, "background": "dusk"}
    assert json.loads(text["touches"]) == [[0, 380.0, 640.0], [0, 300.0, 500.0]]


def test_replayed_touches_follow_clears_and_rebuilds():
    from sim.io.timeline import Timeline, grow

    events = [{"tick": 0, "kind": "touch", "x": 1.0, "y": 2.0},
              {"tick": 3, "kind": "touch", "x": 900.0, "y": 2.0},  # off the screen
              {"tick": 4, "kind": "touch", "x": 5.0, "y": 6.0},
              {"tick": 40, "kind": "touch", "x": 9.0, "y": 9.0},
              {"tick": 45, "kind": "params", "params": {}},
              {"tick": 2, "kind": "touch", "x": 7.0, "y": 8.0}]
    timeline = Timeline(Params(), 0)
    grow(timeline, 47, events)  # 45 ticks, the rebuild, 2 ticks
    # replanted in their order, the pause of 36 ticks shortened to 12; the new one at 2
    assert timeline.touch_ticks() == [(0, 1.0, 2.0), (2, 7.0, 8.0), (4, 5.0, 6.0),
                                      (16, 9.0, 9.0)]
    grow(timeline, 1, [{"tick": 3, "kind": "clear"}])
    assert timeline.touch_ticks() == []


@pytest.mark.parametrize("view, problem", [
    ({"light": [0, 0, 0], "features": True, "bumps": True}, "light"),
    ({"light": [1, 2], "features": True, "bumps": True}, "light"),
    ({"light": [1, "a", 2], "features": True, "bumps": True}, "light"),
    ({"light": [1, 0, 1], "features": 1, "bumps": True}, "features"),
    ([1, 2, 3], "light"),
])
def test_a_bad_view_in_a_session_file_is_a_clear_error(tmp_path, view, problem):
    from sim.io.session import SessionError

    data = {**SessionLog(0, {}).as_json(), "view": view}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(SessionError, match=problem):
        SessionLog.load(path)
    path.write_text(json.dumps(SessionLog(0, {}).as_json()), encoding="utf-8")  # older files have none
    assert SessionLog.load(path).view is None


# ---- progress and Ctrl-C --------------------------------------------------------------


def headless(monkeypatch, gl_ctx, capsys, argv: list[str]) -> tuple[int, list[str], str]:
    """`frost ARGV` in this process: (status, progress lines, stderr)."""
    status, out, err = headless_out(monkeypatch, gl_ctx, capsys, argv)
    return status, [ln for ln in out if ln.startswith("tick ")], err


def headless_out(monkeypatch, gl_ctx, capsys, argv: list[str]) -> tuple[int, list[str], str]:
    """`frost ARGV` in this process, a progress line every tick: (status, stdout's lines,
    stderr)."""
    from app.cli import main
    from app.tools import progress, replay
    from app.tools import render_png as render

    for mode in (render, replay):
        monkeypatch.setattr(mode, "make_context", lambda: gl_ctx)
    monkeypatch.setattr(progress, "PROGRESS_EVERY_S", 0.0)
    status = main(argv)
    out, err = capsys.readouterr()
    return status, out.splitlines(), err


def test_a_touch_run_shows_progress(monkeypatch, gl_ctx, capsys, tmp_path):
    status, lines, _ = headless(monkeypatch, gl_ctx, capsys, [
        "render", "--touch", "380,640", "--ticks", "6", "--out", str(tmp_path / "x.png")])
    assert status == 0 and len(lines) == 6 and lines[-1].startswith("tick 6/6, ")


def test_the_scripted_demo_counts_against_the_whole_run(monkeypatch, gl_ctx, capsys, tmp_path):
    status, lines, _ = headless(monkeypatch, gl_ctx, capsys, [
        "render", "--ticks", "10", "--out", str(tmp_path / "x.png")])
    assert status == 0 and [ln.split()[1] for ln in lines] == [f"{i}/10," for i in range(1, 11)]


def test_a_replay_names_the_rebuild_its_tick_counts_from(monkeypatch, capsys):
    from app.tools import progress

    monkeypatch.setattr(progress, "PROGRESS_EVERY_S", 0.0)
    # A rebuild at tick 4 and a clear 3 ticks into the new timeline, 12 steps in all: by
    # hand, the run's ticks 1-4 are the first simulation's, 5-7 ticks 1-3 after rebuild 1,
    # 8-12 ticks 1-5 after rebuild 2.
    log_ = SessionLog(0, PARAMS.as_dict(), steps=12, events=[
        {"tick": 0, "kind": "touch", "x": 380.0, "y": 640.0},
        {"tick": 4, "kind": "params", "params": PARAMS.replace(humidity=1000).as_dict()},
        {"tick": 3, "kind": "clear"}])
    replay(log_, on_tick=progress.Progress(12).step)
    lines = capsys.readouterr().out.splitlines()
    want = [f"tick {i}/12, " for i in range(1, 5)] + \
        [f"tick {4 + i}/12 (tick {i} since rebuild 1), " for i in range(1, 4)] + \
        [f"tick {7 + i}/12 (tick {i} since rebuild 2), " for i in range(1, 6)]
    assert len(lines) == len(want)
    assert all(ln.startswith(w) for ln, w in zip(lines, want, strict=True))


def test_figure8_names_the_preset_each_tick_belongs_to(monkeypatch, gl_ctx, capsys, tmp_path):
    from app.cli import main
    from app.tools import figure8, progress

    monkeypatch.setattr(figure8, "make_context", lambda: gl_ctx)
    monkeypatch.setattr(progress, "PROGRESS_EVERY_S", 0.0)
    assert main(["figure8", str(tmp_path / "f.png"), "--ticks", "2"]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("tick ")]
    names = list(figure8.PRESETS)  # nine presets of 2 ticks: the run's tick i is preset
    want = [f"tick {i}/18 (preset {names[(i - 1) // 2]} at tick {(i - 1) % 2 + 1}), "
            for i in range(1, 19)]
    assert len(lines) == 18
    assert all(ln.startswith(w) for ln, w in zip(lines, want, strict=True))


def test_a_replay_shows_progress(monkeypatch, gl_ctx, capsys, tmp_path):
    thread = SimThread(PARAMS, 2, [(380.0, 640.0)])
    snap = ticked(thread, 4)[-1]
    path = thread.session(snap.steps, snap.events).save(tmp_path / "s.json")
    status, lines, _ = headless(monkeypatch, gl_ctx, capsys, [
        "replay", str(path), "--out", str(tmp_path / "x.png")])
    assert status == 0 and [ln.split()[1] for ln in lines] == [f"{i}/4," for i in range(1, 5)]


# ---- what a headless run writes, and says it wrote ----------------------------------


@pytest.mark.parametrize("ticks,stops", [(0, [0]), (1, [0, 1]), (2, [0, 2]), (10, [2, 4, 10])])
def test_the_demo_lists_exactly_the_files_it_writes(monkeypatch, gl_ctx, capsys, tmp_path,
                                                    ticks, stops):
    # stops by hand: the demo's touches come at 0, ticks // 5 and 2 * ticks // 5, and it
    # ends at `ticks`; stages that end on the same tick make one PNG.
    monkeypatch.chdir(tmp_path)
    status, out, _ = headless_out(monkeypatch, gl_ctx, capsys, ["render", "--ticks", str(ticks)])
    files = sorted(p.name for p in (tmp_path / "frost-out").iterdir())
    assert status == 0 and [int(f[-8:-4]) for f in files] == stops
    listed = out[-1].split(": ", 1)[1].split(", ")
    assert out[-1].startswith(f"wrote {len(files)} PNG file") and sorted(listed) == files


def test_window_mode_renders_one_png_not_the_demo(monkeypatch, gl_ctx, capsys, tmp_path):
    # as frost render --help says: the frosted window grows untouched, no scripted demo
    monkeypatch.chdir(tmp_path)
    status, out, _ = headless_out(monkeypatch, gl_ctx, capsys,
                                  ["render", "--window-frost", "--ticks", "2"])
    (png,) = (tmp_path / "frost-out").iterdir()
    assert status == 0 and out[-1] == f"wrote {Path('frost-out') / png.name}"
    assert json.loads(Image.open(png).text["touches"]) == []


def test_a_second_demo_overwrites_nothing_of_the_first(monkeypatch, gl_ctx, capsys, tmp_path):
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "frost-out"
    headless(monkeypatch, gl_ctx, capsys, ["render", "--ticks", "5"])
    first = {p: p.read_bytes() for p in folder.iterdir()}
    headless(monkeypatch, gl_ctx, capsys, ["render", "--ticks", "10"])  # (the same second)
    assert len(first) == 3 and all(p.read_bytes() == b for p, b in first.items())
    assert len(list(folder.iterdir())) == 6


@pytest.mark.parametrize("cmd", [["render", "--touch", "380,640", "--ticks", "2", "--out", "OUT/x.png"],
                                 ["render", "--ticks", "5", "--out", "OUT/x.png"],
                                 ["replay", "SESSION", "--out", "OUT/x.png"],
                                 ["figure8", "OUT/f.png", "--ticks", "1"],
                                 ["maps", "OUT", "--ticks", "3"]])
@pytest.mark.parametrize("frost", [["-m", "app"], [str(ROOT / "tests" / "windows_like.py")]],
                         ids=["here", "as-on-windows"])
@pytest.mark.usefixtures("subprocesses")
def test_each_file_a_headless_run_writes_is_named_on_one_line(tmp_path, cmd, frost):
    """Also as on Windows (tests/windows_like.py: no os.fchmod, no os.getloadavg...,
    text without an encoding an error): every file is written all the same."""
    # A subprocess: the log lines (basicConfig on stderr) are what a user sees there.
    session, out = tmp_path / "s.json", tmp_path / "out"
    SessionLog(0, PARAMS.as_dict(), steps=2,
               events=[{"tick": 0, "kind": "touch", "x": 380, "y": 640}]).save(session)
    argv = [a.replace("OUT", str(out)).replace("SESSION", str(session)) for a in cmd]
    done = subprocess.run([sys.executable, *frost, *argv], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT)})
    lines = (done.stdout + done.stderr).splitlines()
    files = [p.name for p in out.iterdir()]
    assert done.returncode == 0 and files, done.stderr
    assert all(sum(name in ln for ln in lines) == 1 for name in files), lines


def test_a_headless_png_into_an_unwritable_folder_is_one_line_exit_2(monkeypatch, gl_ctx, capsys,
                                                                     tmp_path):
    from app.cli import commands

    # The writer's own failure: the start-up check would refuse this path first (its
    # message is tested in tests/test_inputs.py), and a folder can go bad during a run.
    monkeypatch.setattr(commands, "check_paths", lambda *_: [])
    status, _, err = headless(monkeypatch, gl_ctx, capsys, [
        "render", "--touch", "380,640", "--ticks", "1", "--out", str(unwritable(tmp_path) / "x.png")])
    assert status == 2 and "frost: error: cannot write" in err and "Traceback" not in err


def interrupted(cmd: list[str], ready: str, cwd: Path, env=None) -> tuple[int, str]:
    """Run `python -m app CMD`, send SIGINT once `ready` is on stdout; (status, stderr)."""
    proc = subprocess.Popen([sys.executable, "-m", "app", *cmd], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        for line in proc.stdout:
            if ready in line:
                break
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    return proc.returncode, err


LONG_RUN = ["--preset", "c-3", "--ticks", "100000000"]


@pytest.mark.parametrize("mode", [["render", "--touch", "380,640", "--out", "OUT/x.png", *LONG_RUN],
                                  ["maps", "OUT/maps", *LONG_RUN],
                                  ["figure8", "OUT/f.png", "--ticks", "100000000"],
                                  ["replay", "LONG", "--out", "OUT/x.png"]])
@pytest.mark.usefixtures("subprocesses")
def test_ctrl_c_ends_a_long_headless_run_with_130_and_no_file(tmp_path, mode):
    out, long = tmp_path / "out", tmp_path / "long.json"
    SessionLog(0, PARAMS.as_dict(), events=[{"tick": 0, "kind": "touch", "x": 380, "y": 640}],
               steps=100_000_000).save(long)
    cmd = [a.replace("OUT", str(out)).replace("LONG", str(long)) for a in mode]
    status, err = interrupted(cmd, "tick ", tmp_path, {**os.environ, "PYTHONPATH": str(ROOT)})
    assert status == 130, err
    assert "frost: interrupted" in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.usefixtures("subprocesses")
def test_a_display_that_does_not_exist_falls_back_to_headless(tmp_path):
    env = {**os.environ, "DISPLAY": ":97531", "PYTHONPATH": str(ROOT)}
    env.pop("WAYLAND_DISPLAY", None)
    done = subprocess.run([sys.executable, "-m", "app", "--ticks", "5"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    said = [ln for ln in done.stderr.splitlines() if ln.startswith("frost: no display")]
    assert len(said) == 1 and ":97531" in said[0] and "headless" in said[0]
    assert len(list((tmp_path / "frost-out").glob("frost-demo-*.png"))) == 3
