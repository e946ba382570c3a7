"""The weather over a preset that is not the window frost (fern, Table 1's): a page may
choose one while `frost serve --weather` runs, and `--weather` may come with any preset.
The weather's temperature is the window frost's knob alone: over a touch preset a cold
reading leaves the growth as it is (the oracle: the same run without the reading);
tests/test_weather_frost.py has its thaw and the thread going on."""

from __future__ import annotations

import numpy as np
import pytest

from sim import Params
from sim.io.session import weather_event
from sim.io.timeline import Timeline, grow
from sim.weather import Glass, Reading

STOCKHOLM_COLD = Reading(place="Stockholm, Sweden", latitude=59.3, longitude=18.1,
                         temperature_c=-25.0, humidity_pct=80.0, dew_point_c=-27.6,
                         weather_code=71, is_day=False, time="2026-01-10T23:00")


@pytest.mark.parametrize("preset", ["fern", "c-2"])
def test_a_cold_reading_leaves_a_touch_presets_growth_as_it_is(preset):
    runs = {}
    for name, events in (("alone", []), ("cold", [weather_event(STOCKHOLM_COLD, Glass(), 10)])):
        timeline = Timeline(Params.preset(preset), 2, touches=[(380.0, 640.0)])
        grow(timeline, 40, events)
        ice = timeline.sim.ice
        runs[name] = (ice.crystals.raw()[ice.crystal_alive.raw()].copy(), timeline.weather)
    assert runs["cold"][1] is not None and runs["alone"][1] is None
    assert len(runs["alone"][0]) > 50 and np.array_equal(runs["cold"][0], runs["alone"][0])
