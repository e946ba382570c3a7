"""What the weather does to the frost (issue 48): a reading changes the growth from the next
tick, a thaw grows nothing and melts the ice's tips, each reading is a session event (version
12) that replays exactly; older files refuse it. No network: readings are made here."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

from app.simthread.thread import SimThread
from app.window.actions import Actions
from sim import Params
from sim.io.session import SessionError, SessionLog, weather_event
from sim.io.timeline import Timeline, grow, replay
from sim.weather import THAW_TICKS, Glass, Reading

WINDOW = Params.preset("window")
SEED = 2


def reading(outside_c: float) -> Reading:
    return Reading("59.33,18.07", 59.33, 18.07, outside_c, 80.0, -27.6, 71, False,
                   "2026-01-10T23:00")


def crystals(timeline: Timeline) -> np.ndarray:
    """The live crystals' positions, in the order they froze."""
    ice = timeline.sim.ice
    return ice.crystals.raw()[ice.crystal_alive.raw()].copy()


def counts(events: list[dict], ticks: int) -> list[int]:
    """Live crystals after each tick of a window run with `events`."""
    timeline, out = Timeline(WINDOW, SEED), []
    grow(timeline, ticks, events, on_tick=lambda sim: out.append(int(sim.ice.crystal_alive.raw().sum())))
    return out


def test_a_reading_mid_run_changes_the_growth_from_the_next_tick():
    cold = [weather_event(reading(-25.0), Glass())]
    warmer = counts(cold + [weather_event(reading(-12.0), Glass(), 60)], 80)
    thaw = counts(cold + [weather_event(reading(6.0), Glass(), 60)], 80)
    alone = counts(cold, 80)
    # Up to tick 60 the three runs are one; from the step after it they part.
    assert warmer[:60] == thaw[:60] == alone[:60]
    assert warmer[60] - warmer[59] < alone[60] - alone[59]  # glass -4 C: fewer hits take
    assert thaw[60:] == [thaw[59]] * 20  # nothing grows and tick 61 .. 80 melts no layer


def test_the_thaw_melts_the_tips_every_thaw_ticks_as_a_slow_loop_finds_them():
    timeline = Timeline(WINDOW, SEED)
    grow(timeline, 2 * THAW_TICKS, [weather_event(reading(-25.0), Glass()),
                                    weather_event(reading(6.0), Glass(), 2 * THAW_TICKS - 1)])
    ice = timeline.sim.ice
    alive, parents = ice.crystal_alive.raw().copy(), ice.parents.raw().copy()
    # The tips the obvious way: a live crystal that is no live crystal's parent.
    tips = {i for i in range(len(alive)) if alive[i]
            and not any(alive[j] and parents[j] == i for j in range(len(alive)))}
    deltas = timeline.step()  # the step at tick 2 THAW_TICKS: one layer melts first
    after = ice.crystal_alive.raw()
    assert tips and set(np.flatnonzero(alive & ~after)) == tips
    assert len(deltas) == 2 and deltas[0].clear_box is not None  # the melt's delta, the step's
    for _ in range(THAW_TICKS - 1):
        timeline.step()
    assert ice.crystal_alive.raw().sum() == after.sum()  # no layer until the next THAW_TICKS



def heights(alive: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """Each live crystal's height in the live tree: 0 for one no live crystal grows from,
    else one more than its highest live child's (-1 for a dead one). Worked from the last
    crystal to the first, a crystal's children being later than it (asserted)."""
    height = np.where(alive, 0, -1)
    for j in range(len(alive) - 1, -1, -1):
        if alive[j] and parents[j] >= 0:
            assert parents[j] < j and alive[parents[j]]
            height[parents[j]] = max(height[parents[j]], height[j] + 1)
    return height


def test_a_thaw_melts_layer_after_layer_until_the_ice_is_gone():
    """Layer k of a thaw melts the crystals of height k in the tree as it was when the thaw
    began: its first layers as the weather's thaw melts them (one every THAW_TICKS ticks),
    then the rest one `melt_tips` at a time, until no ice is left, and none after that.
    The oracle: the heights worked once at the start, not the tips layer by layer."""
    timeline = Timeline(WINDOW, SEED)
    grow(timeline, 2 * THAW_TICKS, [weather_event(reading(-25.0), Glass()),
                                    weather_event(reading(6.0), Glass(), 2 * THAW_TICKS - 1)])
    ice = timeline.sim.ice
    height = heights(ice.crystal_alive.raw().copy(), ice.parents.raw().copy())
    layers = int(height.max()) + 1
    assert layers >= 5, layers  # (a tree deep enough to tell a thaw that stops)
    for k in range(3):  # the weather's thaw: a layer at each THAW_TICKS
        before = ice.crystal_alive.raw().copy()
        for _ in range(THAW_TICKS):
            timeline.step()
        gone = set(np.flatnonzero(before & ~ice.crystal_alive.raw()))
        assert gone == set(np.flatnonzero(height == k)), k
    for k in range(3, layers):
        melted = timeline.sim.melt_tips()
        assert sorted(melted.crystals) == sorted(np.flatnonzero(height == k)), k
        assert not ice.crystal_alive.raw()[height == k].any()
        assert ice.crystal_alive.raw()[height > k].all()
    assert not ice.crystal_alive.raw().any()  # all the ice melted
    assert len(timeline.sim.melt_tips().crystals) == 0

def test_a_rebuild_keeps_the_weather():
    timeline = Timeline(WINDOW, SEED)
    grow(timeline, 5, [weather_event(reading(6.0), Glass()),
                       {"tick": 3, "kind": "params", "params": WINDOW.replace(humidity=3000)}])
    assert timeline.sim.thawing and timeline.weather["reading"]["temperature_c"] == 6.0
    grow(timeline, 5, [weather_event(reading(-25.0), Glass(), timeline.tick)])
    assert not timeline.sim.thawing


def test_a_run_with_readings_replays_exactly_from_its_session_file(tmp_path):
    events = [weather_event(reading(-25.0), Glass()), weather_event(reading(-12.0), Glass("double"), 40),
              weather_event(reading(6.0), Glass(), 90), weather_event(reading(-30.0), Glass(), 120)]
    timeline = Timeline(WINDOW, SEED)
    grow(timeline, 150, events)
    log_ = SessionLog(SEED, WINDOW.as_dict(), events=timeline.events, steps=150)
    path = log_.save(tmp_path / "weather.json")
    again = replay(SessionLog.load(path))
    assert np.array_equal(crystals(again), crystals(timeline))
    # (written as the newest version: weather events need 12 or later)
    assert again.weather == timeline.weather and json.loads(path.read_text(encoding="utf-8"))["version"] >= 12


def test_the_thread_records_each_reading_at_its_tick_and_its_session_replays():
    thread = SimThread(WINDOW, SEED)
    for k in range(60):
        if k in (0, 30):
            thread.show_weather(reading(-25.0 if k == 0 else 6.0), Glass())
        thread.tick()
    snapshot = thread.drain()[-1]
    weather = [(e["tick"], e["reading"]["temperature_c"]) for e in thread.timeline.events]
    assert weather == [(0, -25.0), (30, 6.0)]
    assert snapshot.weather == {"reading": reading(6.0).as_json(), "glass": Glass().as_json()}
    saved = SessionLog.from_json(json.loads(json.dumps(thread.session().as_json())))
    assert np.array_equal(crystals(replay(saved)), crystals(thread.timeline))


def test_touch_mode_has_no_temperature_but_thaws():
    thread = SimThread(Params.preset("fern"), SEED, [(380.0, 640.0)])  # the window's default
    thread.show_weather(reading(-25.0), Glass())
    for _ in range(30):
        thread.tick()
    grown = len(thread.sim.crystals)
    assert grown > 1 and thread.drain()[-1].error is None
    thread.show_weather(reading(6.0), Glass())
    for _ in range(3 * THAW_TICKS):
        thread.tick()
    assert int(thread.sim.ice.crystal_alive.raw().sum()) < grown and thread.drain()[-1].error is None


def test_a_session_older_than_version_12_holds_no_weather():
    event = weather_event(reading(-25.0), Glass(), 3)
    data = {"format": "frost-session", "version": 11, "seed": 0, "params": WINDOW.as_dict(),
            "steps": 5, "events": [event]}
    with pytest.raises(SessionError, match=r"a weather event needs version 12 or later \(this "
                                           r"file is version 11\)"):
        SessionLog.from_json(data)
    with pytest.raises(ValueError, match="needs session version 12"):
        Timeline(WINDOW, 0, version=11).apply([event])
    thread = SimThread(WINDOW, 0, version=11)  # a replay of an old file, under --weather
    thread.show_weather(reading(-25.0), Glass())
    thread.tick()
    assert thread.drain()[-1].message == "weather: a session of version 11 grows without the weather"
    assert thread.timeline.events == []


@pytest.mark.parametrize("change, words", [
    ({"reading": {**reading(-25.0).as_json(), "humidity_pct": 150}}, "humidity_pct"),
    ({"reading": "cold"}, "must be an object"),
    ({"glass": {"glazing": "triple", "room_c": 20.0, "room_humidity": 40.0}}, "glazing 'triple'"),
    ({"glass": {"glazing": "single"}}, "must hold glazing, room_c and room_humidity")])
def test_a_weather_event_that_is_not_one_is_refused_in_one_line(change, words):
    event = {**weather_event(reading(-25.0), Glass(), 7), **change}
    data = {"format": "frost-session", "version": 12, "seed": 0, "params": WINDOW.as_dict(),
            "events": [event]}
    with pytest.raises(SessionError) as err:
        SessionLog.from_json(data)
    assert str(err.value).startswith("weather event at tick 7: ") and words in str(err.value)
    assert "\n" not in str(err.value)


def test_under_the_weather_t_and_y_say_so_and_change_nothing():
    said, tuned = [], []
    keys = SimpleNamespace(weather_sets_temperature=True, status=SimpleNamespace(say=said.append),
                           _tune=lambda *arg: tuned.append(arg))
    Actions._shift(keys, ("temperature", 2.0))
    Actions._shift(keys, ("hc", 0.5))  # other keys tune as ever
    assert said == ["temperature: the weather sets it (--weather): T and Y change nothing"]
    assert [arg[1:] for arg in tuned] == [("hc", 0.5)]
    keys.weather_sets_temperature = False
    Actions._shift(keys, ("temperature", 2.0))
    assert [arg[1:] for arg in tuned] == [("hc", 0.5), ("temperature", 2.0)]
