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

TOUCH = (380.0, 640.0)


def reading(outside_c: float) -> Reading:
    return Reading("59.33,18.07", 59.33, 18.07, outside_c, 80.0, -27.6, 71, False,
                   "2026-01-10T23:00")


def crystals(timeline: Timeline) -> np.ndarray:
    ice = timeline.sim.ice
    return ice.crystals.raw()[ice.crystal_alive.raw()].copy()


@pytest.mark.parametrize("preset", ["fern", "c-2"])
def test_a_cold_reading_leaves_a_touch_presets_growth_as_it_is(preset):
    params = Params.preset(preset)
    alone, cold = Timeline(params, 2, touches=[TOUCH]), Timeline(params, 2, touches=[TOUCH])
    grow(alone, 40, [])
    grow(cold, 40, [weather_event(reading(-25.0), Glass(), 10)])
    assert cold.weather is not None and len(crystals(alone)) > 50
    assert np.array_equal(crystals(cold), crystals(alone))

