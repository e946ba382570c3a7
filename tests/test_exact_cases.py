"""Hand-built cases on exact float32 values, each aimed at a one-line bug the statistical
tests let through: `<=` for `<` in the freezing test, ties to the highest crystal index,
a crystal hidden by float32 cell rounding without CELL_MARGIN, deltas that are views of
live arrays (exports: tests/test_recorded.py)."""

from __future__ import annotations

import numpy as np
import pytest

from sim import FrostSim, Params
from sim.look.geometry import FrostGeometry

SEARCHES = ["candidate", "grid9"]


def placed(seeds, walkers, hc: float, search: str = "candidate") -> FrostSim:
    """A sim with crystals at `seeds` (in this order) and exactly the water `walkers`."""
    sim = FrostSim(Params(hc=hc, step=min(5.0, hc), humidity=1, neighbor_search=search), seed=0)
    for x, y in seeds:
        sim.touch(x, y)
    sim.set_water(walkers)
    return sim


def frozen_to(sim: FrostSim) -> dict[int, int]:
    """walker -> parent crystal of one crystallization (no walk)."""
    frozen, parents = sim.crystallize()
    return dict(zip(frozen.tolist(), parents.tolist(), strict=True))


@pytest.mark.parametrize("search", SEARCHES)
def test_a_walker_exactly_hc_away_stays_water(search):
    # 7 px apart, hc 7: d^2 = 49 = hc^2 exactly in float32; the test is d < hc.
    sim = placed([(100, 100)], [(107, 100), (100, 93), (106.99999, 100)], 7.0, search)
    assert frozen_to(sim) == {2: 0}


@pytest.mark.parametrize("search", SEARCHES)
@pytest.mark.parametrize("seeds, parent", [([(100, 100), (114, 100)], 0),
                                            ([(114, 100), (100, 100)], 0)])
def test_a_tie_goes_to_the_lowest_crystal_index(search, seeds, parent):
    # (107, 100) is 7 px from both seeds, exactly in float32; hc 8 freezes it.
    sim = placed(seeds, [(107, 100)], 8.0, search)
    assert frozen_to(sim) == {0: parent}
    sim = placed(seeds, [(107, 100)], 8.0, search)
    sim.walk = lambda: None  # the whole tick, walker kept in place
    sim.step()
    assert sim.crystals[-1].tolist() == [107, 100] and sim.parents[-1] == parent


@pytest.mark.parametrize("search", SEARCHES)
def test_a_crystal_just_across_a_cell_edge_is_found(search):
    # hc 7: cells 14 px. The walker at the float32 just below 28 is 6.999998 px from the
    # crystal at 21 (within hc), but x * float32(1/14) rounds it into cell 2, which the
    # crystal's open disc (up to 28) only reaches with CELL_MARGIN.
    walker = float(np.nextafter(np.float32(28), np.float32(0)))
    sim = placed([(21, 100)], [(walker, 100)], 7.0, search)
    assert sim.grid.keys(np.float32([walker]), np.float32([100]))[0] % sim.grid.cols == 2
    assert frozen_to(sim) == {0: 0}


def test_geometry_deltas_are_copies_not_views_of_live_arrays():
    sim = FrostSim(Params.preset("c-3"), seed=2)
    sim.touch(380, 640)
    geometry = FrostGeometry(sim.params)
    deltas = [geometry.reset()]
    for _ in range(30):
        sim.step()
        deltas.append(geometry.update(sim))
    deltas.append(geometry.melt(sim, sim.melt(380, 640, 20.0)))
    live = [geometry.heights, sim.crystals, sim.segments, sim.upsampled]
    for delta in deltas:
        for array in (delta.heights, delta.features):
            assert not any(np.shares_memory(array, a) for a in live)
    before = deltas[-2].heights.copy()
    for _ in range(5):
        sim.step()
        geometry.update(sim)
    assert np.array_equal(deltas[-2].heights, before)
