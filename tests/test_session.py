"""Sessions: the live thread records what it applies, a replay reproduces it bit for bit,
melts reach the renderer as deltas and survive rebuilds, bad files are clear errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from app.simthread import backlog
from app.simthread import thread as simthread
from app.simthread.backlog import Backlog
from app.simthread.thread import SimThread
from sim import FrostSim, Params
from sim.io.session import VERSION, SessionError, SessionLog
from sim.io.timeline import Timeline, grow, regrow, replay, touch_events

ROOT = Path(__file__).resolve().parent.parent
PARAMS = Params.preset("c-3")


@pytest.fixture(autouse=True)
def input_backlog_on_a_still_clock(monkeypatch):
    """Threads driven tick by tick here apply every command sent before a tick in that
    tick: the backlog's time budget (tested in test_bounds) must not depend on the load."""
    monkeypatch.setattr(simthread, "Backlog", lambda **kw: Backlog(**kw, clock=lambda: 0.0))



def live_session(ticks: int = 60) -> tuple[SimThread, list]:
    """A SimThread driven like the window: touches, a drag of melts, a parameter change
    and a pause, each arriving between ticks. Returns the thread and its snapshots."""
    thread = SimThread(PARAMS, 4, [(380.0, 640.0)])
    script = {5: [("touch", ((200.0, 300.0), None))],
              30: [("melt", (380.0, 640.0, 30.0)), ("melt", (395.0, 640.0, 30.0))],
              35: [("params", PARAMS.replace(humidity=4000))],
              40: [("pause", None), ("touch", ((500.0, 900.0), None))],
              41: [("melt", (200.0, 300.0, 20.0)), ("pause", None)],
              50: [("melt", (380.0, 660.0, 24.0))]}
    snaps = []
    for k in range(ticks):
        for kind, arg in script.get(k, ()):
            thread.send(kind, arg)
        thread.tick()
        snaps.extend(thread.drain())
    return thread, snaps


def same_frost(a, b) -> None:
    for name in ("crystals", "parents", "crystal_alive", "segments", "segments_alive",
                 "upsampled", "upsampled_alive", "water"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.tick == b.tick


def test_a_recorded_session_replays_bit_for_bit_through_a_json_file(tmp_path):
    thread, snaps = live_session()
    log = thread.session(snaps[-1].steps, snaps[-1].events)
    kinds = [e["kind"] for e in log.events]
    assert kinds.count("melt") == 4 and kinds.count("params") == 1 and log.steps == 59
    again = SessionLog.load(log.save(tmp_path / "s.json"))
    same_frost(replay(again).sim, thread.sim)
    assert replay(again).events == log.events  # the replay records the same session


def test_melt_through_the_thread_sends_a_delta_that_clears_ice():
    thread, snaps = live_session(32)
    melt = snaps[30].melts
    # the drag's two melts of tick 30 arrived together: one melt, one delta over both
    assert len(melt) == 1 and melt[0].clear_box is not None
    x0, y0, x1, y1 = melt[0].clear_box
    assert x0 <= 380.0 - 20 and x1 >= 395.0 + 20 and y0 <= 640.0 - 20 and y1 >= 640.0 + 20
    rows = melt[0].rows
    assert rows.stop > rows.start and melt[0].heights.min() >= 0
    assert not thread.sim.crystal_alive.all()


def test_a_rebuild_melts_again_at_the_melts_ticks(tmp_path):
    thread, snaps = live_session(80)
    assert "2 melts at their ticks" in snaps[35].message
    again = [s for s in snaps[36:] if len(s.melts) == 2]
    assert len(again) == 1 and again[0].stats.tick == 31  # applied at tick 30, then stepped
    assert sorted(m["tick"] for m in thread.timeline.melts) == [5, 14, 30, 30]
    log = thread.session(snaps[-1].steps, snaps[-1].events)
    same_frost(replay(SessionLog.load(log.save(tmp_path / "s.json"))).sim, thread.sim)


def test_replayed_frames_match_the_live_renderer(gl_ctx):
    from app.images import read_image
    from app.tools.offscreen import Offscreen
    from app.tools.replay import replay_offscreen

    thread, snaps = live_session()
    live = Offscreen(gl_ctx, PARAMS, 4)
    for snap in snaps:
        if snap.reset:
            live.renderer.reset()
        for delta in (*snap.melts, *([snap.delta] if snap.delta else [])):
            live.renderer.apply(delta)
    live.renderer.render(live.fbo)
    again = replay_offscreen(gl_ctx, thread.session(snaps[-1].steps, snaps[-1].events))
    again.renderer.render(again.fbo)
    assert np.array_equal(read_image(live.fbo), read_image(again.fbo))


@pytest.mark.parametrize("text, problem", [
    (None, "cannot read"), ("{", "not JSON"), ('{"format": "x"}', "not a frost session"),
    ('{"format": "frost-session", "seed": 0, "params": {"hc": -1}}', "hc"),
    ('{"format": "frost-session", "seed": 0, "params": {}, "events": [{"kind": "melt", '
     '"tick": 1, "x": 1, "y": "a", "r": 3}]}', "must be numbers"),
    ('{"format": "frost-session", "seed": 0, "params": {}, "events": [{"kind": "zap"}]}', "kind"),
])
def test_a_bad_session_file_is_a_clear_error(tmp_path, text, problem):
    path = tmp_path / "s.json"
    if text is not None:
        path.write_text(text, encoding="utf-8")
    with pytest.raises(SessionError, match=problem) as err:
        SessionLog.load(path)
    assert str(path) in str(err.value)


@pytest.mark.usefixtures("subprocesses")
def test_replay_cli_exits_2_naming_the_file(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text(json.dumps({"format": "frost-session", "events": []}), encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "app", "replay", "--headless", str(path)],
                          cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and str(path) in done.stderr and "Traceback" not in done.stderr


def test_a_windowed_replay_drives_the_thread_through_the_same_events():
    thread, snaps = live_session()
    log = thread.session(snaps[-1].steps, snaps[-1].events)
    again = SimThread(Params(**log.params), log.seed, script=log.events)
    for _ in range(log.steps):  # the live session paused one tick; a replay does not
        again.tick()
    assert again.session().events == log.events
    same_frost(again.sim, thread.sim)


def test_melt_options_become_melt_events_in_tick_order():
    from app.cli.parser import build_parser
    from app.tools.render_png import melt_events

    args = build_parser().parse_args(["render", "--melt", "10,20@30", "--melt", "5,5,9@2",
                                      "--melt-path", "100,50:140,50@7", "--melt-radius", "20"])
    events = melt_events(args)
    assert [e["tick"] for e in events] == [2, 7, 7, 7, 7, 7, 30]
    assert events[0]["r"] == 9 and events[-1]["r"] == 20
    assert [e["x"] for e in events if e["tick"] == 7] == [100, 110, 120, 130, 140]
    with pytest.raises(SystemExit):
        build_parser().parse_args(["render", "--melt", "1,2,0@3"])


@pytest.mark.parametrize("pause", [False, True])
def test_a_recording_that_ends_where_a_rebuilt_melt_is_due_replays_the_same(pause):
    thread = SimThread(PARAMS, 2, [(380.0, 640.0)])
    plan = {20: ("melt", (380.0, 640.0, 30.0)), 25: ("params", PARAMS.replace(humidity=4500)),
            45: ("pause", None)}
    for k in range(47 if pause else 45):
        if k in plan:
            thread.send(*plan[k])
        thread.tick()
    snap = thread.drain()[-1]
    assert thread.sim.tick == 20 and thread.timeline.pending  # the melt waits for a step
    same_frost(replay(thread.session(snap.steps, snap.events)).sim, thread.sim)


def test_clear_forgets_the_melts_a_rebuild_scheduled():
    timeline = Timeline(PARAMS, 0, touches=[(380.0, 640.0)])
    for _ in range(20):
        timeline.step()
    timeline.apply([{"kind": "melt", "x": 380.0, "y": 640.0, "r": 30.0}])
    timeline.apply([{"kind": "params", "params": PARAMS.replace(humidity=4000)}])
    assert len(timeline.pending) == 1
    timeline.apply([{"kind": "clear"}, {"kind": "touch", "x": 100.0, "y": 100.0}])
    assert timeline.pending == [] and timeline.touches == ((100.0, 100.0),)


def test_regrow_keeps_the_touches_order_and_shortens_only_long_pauses():
    ticks = [5, 5, 9, 60, 61, 200]  # by hand, gap 12: 0, 0, 4, 4+12, 16+1, 17+12
    touches = [{"tick": t, "kind": "touch", "x": float(k), "y": 0.0} for k, t in enumerate(ticks)]
    again = regrow(touches, 12)
    assert [e["tick"] for e in again] == [0, 0, 4, 16, 17, 29]
    assert [e["x"] for e in again] == [0, 1, 2, 3, 4, 5]
    assert [e["tick"] for e in regrow(touches, 0)] == [0] * 6  # version 1: all at tick 0


def frost_arrays(sim) -> dict[str, np.ndarray]:
    return {name: np.array(getattr(sim, name)) for name in
            ("crystals", "parents", "segments", "upsampled", "water", "areas")}


def test_a_rebuild_regrows_a_scribble_as_it_grew_live():
    # The fern look, drags from tick 0 with pauses of 5 ticks: a rebuild with the same
    # parameters must give back the very frost the scribble grew (the touches once went
    # all at tick 0, and the water split over every area at once left sparse twigs).
    from app.bench.scribble import STROKE_GAP, stroke
    from sim.io.gestures import DRAG_SPACING_HC

    params = Params.preset("fern")
    schedule = []
    for a, b in (((60, 80), (700, 600)), ((700, 100), (80, 1200)), ((380, 300), (600, 1250))):
        schedule += stroke(a, b, DRAG_SPACING_HC * params.hc, "touch") + [[]] * STROKE_GAP
    events = [{**e, "tick": t} for t, tick_events in enumerate(schedule) for e in tick_events]
    steps = len(schedule) + 40
    timeline = Timeline(params, 3)
    grow(timeline, steps, events)
    live = frost_arrays(timeline.sim)
    assert len(timeline.touches) > 60 and len(live["areas"]) < 10
    timeline.apply([{"kind": "params", "params": params}])
    grow(timeline, 7)  # a key pressed again mid-regrowth starts the same regrowth over
    timeline.apply([{"kind": "params", "params": params}])
    grow(timeline, steps)
    again = frost_arrays(timeline.sim)
    for name in live:
        assert np.array_equal(live[name], again[name]), name
    assert timeline.touch_ticks() == [(e["tick"], e["x"], e["y"]) for e in events]


@pytest.mark.parametrize("version, ticks", [(1, [0, 0, 0]), (2, [0, 12, 13])])
def test_a_session_file_replants_as_its_version_did(tmp_path, version, ticks):
    events = [*touch_events([(300.0, 400.0)]), *touch_events([(500.0, 700.0)], 30),
              *touch_events([(520.0, 700.0)], 31),
              {"tick": 40, "kind": "params", "params": PARAMS.replace(humidity=4000).as_dict()}]
    log = SessionLog(0, PARAMS.as_dict(), events=events, steps=60, version=version)
    log = SessionLog.load(log.save(tmp_path / "s.json"))
    assert log.version == version and log.as_json()["version"] == version
    timeline = replay(log)
    assert [t for t, _x, _y in timeline.touch_ticks()] == ticks
    # the same frost as a run that starts from the regrown schedule
    # (the touches due at tick 0 are planted at once, as a session's first touches are)
    at0 = [(e["x"], e["y"]) for e, t in zip(events[:3], ticks, strict=True) if t == 0]
    fresh = Timeline(PARAMS.replace(humidity=4000), 0, touches=at0, version=version)
    grow(fresh, 20, [{**e, "tick": t} for e, t in zip(events[:3], ticks, strict=True) if t > 0])
    same_frost(timeline.sim, fresh.sim)


def test_a_session_file_from_a_later_frost_is_refused():
    data = {"format": "frost-session", "version": VERSION + 1, "seed": 0, "params": {}, "events": []}
    with pytest.raises(SessionError, match="version"):
        SessionLog.from_json(data)


def test_events_due_after_the_last_step_still_apply():
    # Made while paused after the last step: a touch and a melt at tick 3 of a 3-step run.
    base = {"format": "frost-session", "seed": 1, "params": PARAMS.as_dict(), "steps": 3}
    events = [{"tick": 0, "kind": "touch", "x": 380.0, "y": 640.0},
              {"tick": 3, "kind": "touch", "x": 100.0, "y": 200.0},
              {"tick": 3, "kind": "melt", "x": 380.0, "y": 640.0, "r": 5.0}]
    timeline = replay(SessionLog.from_json({**base, "events": events}))
    assert timeline.steps == 3 and timeline.tick == 3
    assert timeline.touches == ((380.0, 640.0), (100.0, 200.0))
    assert len(timeline.events) == 3 and not timeline.sim.crystal_alive[0]  # the seed melted


@pytest.mark.parametrize("order", [("melt", "params"), ("params", "melt")])
def test_a_melt_and_a_rebuild_in_one_tick_replay_bit_for_bit(tmp_path, order):
    """Both orders in one tick: the melt before the rebuild is melted again at its tick
    by the rebuilt frost; the one after it melts the rebuilt frost at once."""
    thread = SimThread(PARAMS, 4, [(380.0, 640.0)])
    for _ in range(25):
        thread.tick()
    for kind in order:
        thread.send(kind, (380.0, 640.0, 30.0) if kind == "melt" else PARAMS.replace(humidity=4000))
    for _ in range(30):  # the rebuilt frost passes tick 25 again
        thread.tick()
    snaps = thread.drain()
    log = thread.session(snaps[-1].steps, snaps[-1].events)
    assert [e["kind"] for e in log.events] == ["touch", *order]
    same_frost(replay(SessionLog.load(log.save(tmp_path / "s.json"))).sim, thread.sim)
    assert thread.sim.crystal_alive.sum() < len(thread.sim.crystals)  # the melt took ice


@pytest.mark.parametrize("order", [("melt", "params"), ("params", "melt")])
def test_a_melt_and_a_rebuild_in_one_tick_grow_what_the_new_parameters_grow_from_the_start(order):
    """The oracle is a timeline that had the new parameters from the start: the melt
    before the rebuild comes again at its tick (25) in the rebuilt frost; the one after
    it melts the rebuilt frost at once (tick 0, the seed alone)."""
    new = PARAMS.replace(humidity=4000)
    melt = {"kind": "melt", "x": 380.0, "y": 640.0, "r": 30.0}
    timeline = Timeline(PARAMS, 4, touches=[(380.0, 640.0)])
    for _ in range(25):
        timeline.step()
    applied = timeline.apply([melt if k == "melt" else {"kind": "params", "params": new}
                              for k in order])
    assert applied.reset and timeline.tick == 0  # rebuilt: back to tick 0 either way
    oracle = Timeline(new, 4, touches=[(380.0, 640.0)])
    for _ in range(25 if order[0] == "melt" else 0):
        oracle.step()
    oracle.apply([melt])
    while oracle.tick < 55:
        oracle.step()
    while timeline.tick < 55:
        timeline.step()
    assert [m["tick"] for m in timeline.melts] == [25 if order[0] == "melt" else 0]
    for a, b in ((timeline.sim.crystals, oracle.sim.crystals),
                 (timeline.sim.parents, oracle.sim.parents),
                 (timeline.sim.crystal_alive, oracle.sim.crystal_alive),
                 (timeline.sim.water, oracle.sim.water)):
        assert np.array_equal(a, b)
    assert not timeline.sim.crystal_alive.all()  # the melt took ice


def test_a_ticks_melts_sent_together_are_recorded_as_one_group_and_replay_so():
    thread, snaps = live_session()
    melts = [e for e in thread.session(snaps[-1].steps, snaps[-1].events).events
             if e["kind"] == "melt"]
    groups = [(e["tick"], e["group"]) for e in melts]
    # tick 30's two melts came together: one group; the others each their own
    assert groups[0][1] == groups[1][1] and len({g for _t, g in groups}) == 3


def test_group_melts_groups_runs_of_overlapping_melts_up_to_its_cap():
    cap = backlog.MELT_GROUP
    drag = [("m", 10.0 * k, 0.0) for k in range(cap + 3)]  # 10 px apart, radius 6: overlapping
    far = [("m", 500.0, 500.0), ("m", 0.0, 900.0)]  # apart from each other and the drag
    items = ["t", *drag, "p", *far, "t"]
    out = backlog.group_melts(items, lambda i: (i[1], i[2], 6.0) if i[0] == "m" else None,
                              tuple)
    assert out == ["t", tuple(drag[:cap]), tuple(drag[cap:]), "p", far[0], far[1], "t"]


@pytest.mark.parametrize("version", [5, 6])
def test_melts_at_one_tick_apply_one_by_one_before_version_6_and_as_one_from_it(version):
    discs = [(380.0, 640.0, 20.0), (400.0, 650.0, 20.0), (420.0, 640.0, 20.0)]
    timeline = Timeline(Params.preset("fern"), 0, version=version)
    timeline.apply([{"kind": "touch", "x": 400.0, "y": 640.0}])
    for _ in range(60):
        timeline.step()
    sim = FrostSim(Params.preset("fern"), seed=0, version=version)
    sim.touch(400.0, 640.0)
    for _ in range(60):
        sim.step()
    applied = timeline.apply([{"kind": "melt", "x": x, "y": y, "r": r} for x, y, r in discs])
    if version == 5:
        for d in discs:
            sim.melt(*d)
    else:
        sim.melt_many(discs)
    assert len(applied.deltas) == (3 if version == 5 else 1)
    same_frost(timeline.sim, sim)


def test_melts_sent_at_one_paused_tick_but_apart_replay_as_they_applied(tmp_path):
    # Paused, the tick stays while the thread runs on: two melts sent a thread tick
    # apart apply as two groups at the same tick; the replay keeps them apart.
    thread = SimThread(PARAMS, 4, [(380.0, 640.0)])
    for _ in range(40):
        thread.tick()
    thread.send("pause")
    thread.tick()
    for x in (370.0, 395.0):
        thread.send("melt", (x, 640.0, 20.0))
        thread.tick()
    thread.send("pause")
    for _ in range(20):
        thread.tick()
    snaps = thread.drain()
    log = thread.session(snaps[-1].steps, snaps[-1].events)
    melts = [e for e in log.events if e["kind"] == "melt"]
    assert [e["tick"] for e in melts] == [40, 40] and melts[0]["group"] != melts[1]["group"]
    same_frost(replay(SessionLog.load(log.save(tmp_path / "s.json"))).sim, thread.sim)
