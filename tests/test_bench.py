"""The simulation benchmark's sections run on their own and measure what they say."""
import json

import pytest

from sim import bench
from sim.params import Params


@pytest.mark.parametrize("humidity", bench.BUSY_HUMIDITIES)
def test_busy_ticks_are_timed_with_the_whole_pool_walking(humidity, monkeypatch):
    """Each timed tick starts with >= 90 % of `humidity` walkers (a screen budget below
    the humidity would cap the pool and leave no busy tick to time)."""
    pools = []
    step = bench.FrostSim.step

    def counted(sim):
        pools.append(len(sim.water_area))
        step(sim)

    monkeypatch.setattr(bench.FrostSim, "step", counted)
    times = bench.busy_ticks(humidity, 3)
    assert len(times) == 3 == len(pools)
    assert min(pools) >= 0.9 * humidity


def test_a_busy_tick_that_cannot_happen_is_refused():
    """A budget below the humidity is said, not looped on forever."""
    small = Params.preset("c-2", humidity=3000, water_budget=1000)
    with pytest.raises(ValueError, match="no tick of it can be busy"):
        bench.busy_ticks_for(small, 3)


def test_each_section_runs_alone(capsys):
    """`--section memory` prints that section's figures and its JSON, and no other."""
    assert bench.main(["--quick", "--section", "memory"]) == 0
    out = capsys.readouterr().out
    figures = json.loads(out.strip().splitlines()[-1])
    assert set(figures) == {"memory"}
    assert figures["memory"]["crystals"] > 0
    assert "Fig. 9" not in out
