"""FrostSim's parts (sim/core, sim/index) at their boundaries, worked by hand: each case
sits exactly on a comparison the code makes (a rim, a half-hc gap, a screen edge)."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim import FrostSim, Params, walk_displacements
from sim.core import placement
from sim.core.areas import shell
from sim.core.versions import PARTS
from sim.core.walk import outside

SMALL = Params(hc=8.0, active_radius=60.0, humidity=200, water_budget=400)


def test_a_touch_on_an_areas_rim_joins_it():
    sim = FrostSim(SMALL, 400, 400, seed=0)
    assert sim.touch(100.0, 100.0) == 0
    assert sim.touch(160.0, 100.0) == 0  # exactly 60 px from the centre: on the disc
    assert sim.touch(160.5, 100.0) == 1 and len(sim.areas) == 2


def test_a_launch_circle_on_the_areas_rim_is_not_used():
    # Reach 70 + launch 30 = 100, the outer radius: the circle is not inside the area, so
    # water goes back to the annulus (20 .. 100); 29 puts it inside (99 .. 99).
    rows = np.array([[0.0, 0.0, 100.0, 20.0, 70.0]], np.float32)
    assert [v.tolist() for v in shell(rows, 30.0)] == [[20.0], [100.0]]
    assert [v.tolist() for v in shell(rows, 29.0)] == [[99.0], [99.0]]


def test_glass_starts_exactly_half_hc_from_a_crystal_and_at_the_screens_zero_edges():
    sim = FrostSim(SMALL, 400, 400, seed=0)
    sim.touch(100.0, 100.0)
    x, y = np.float32([104.0, 103.5, 0.0]), np.float32([100.0, 100.0, 300.0])
    assert sim.index.glass(x, y).tolist() == [True, False, True]  # 4 px = hc / 2 is glass
    assert sim.index.free(np.float32([0.0, 300.0]), np.float32([300.0, 0.0])).all()


def test_a_crystal_exactly_radius_away_is_not_near():
    sim = FrostSim(SMALL, 400, 400, seed=0)
    sim.touch(100.0, 100.0)
    assert sim.index.crystals_near(103.0, 104.0, 5.0).tolist() == []  # 3-4-5: exactly 5 away
    assert sim.index.crystals_near(103.0, 104.0, 5.001).tolist() == [0]


def test_a_walker_on_its_areas_rim_is_inside_and_one_on_the_screen_edge_is_off():
    x, y = np.float32([160.0, 160.5]), np.float32([100.0, 100.0])
    assert outside(x, y, (100.0, 100.0, 60.0), (400, 400), False).tolist() == [False, True]
    x, y = np.float32([0.0, 400.0, 100.0]), np.float32([100.0, 100.0, 0.0])
    assert outside(x, y, (100.0, 100.0, 200.0), (400, 400), False).tolist() == [False, True,
                                                                                False]


def test_a_clearance_equal_to_the_step_is_no_jump():
    step = 5.0
    plain = walk_displacements(np.random.default_rng(1), 50, step)
    same = walk_displacements(np.random.default_rng(1), 50, step, np.full(50, step, np.float32))
    longer = walk_displacements(np.random.default_rng(1), 50, step, np.full(50, 6.0, np.float32))
    assert all(np.array_equal(a, b) for a, b in zip(plain, same, strict=True))
    assert np.allclose(np.hypot(*longer), 6.0)


def test_a_new_area_takes_its_whole_pool_when_it_exactly_fills_the_budget():
    # 200 walkers left in area 0, a budget of 500, humidity 300: a far touch wants 300 =
    # the room left, so it gets them all and nobody gives any up (the fair share, 250,
    # plays no part: the budget is not short).
    p = SMALL.replace(humidity=300, water_budget=500)
    sim = FrostSim(p, 400, 400, seed=0)
    sim.touch(100.0, 100.0)
    sim.set_water(np.column_stack((np.full(200, 150.0), np.linspace(60.0, 140.0, 200))), 0)
    sim.touch(300.0, 300.0)
    assert np.bincount(sim.water_area).tolist() == [200, 300]


def test_a_second_melt_reports_only_what_it_cut():
    sim = FrostSim(Params.preset("c-2"), seed=3)
    sim.touch(380.0, 640.0)
    for _ in range(120):
        sim.step()
    first = sim.melt(380.0, 640.0, 20.0)
    alive = sim.segments_alive.copy()
    second = sim.melt(380.0, 640.0, 40.0)
    assert len(first.segments) and len(second.segments)
    assert alive[second.segments].all()  # none of them was dead already
    assert not np.intersect1d(first.segments, second.segments).size


def placements(sim, first, second, both: bool):
    """The answers of placing walkers of areas `first`, then of `second`, at once or in
    turn, and the random state after."""
    ice = sim.ice_state()
    if both:
        answers = sim.placer.place_both(first, second, ice)
    else:
        answers = (sim.placer.place(first, ice), sim.placer.place(second, ice))
    return [a.tolist() for pair in answers for a in pair], sim.streams.placement.bit_generator.state


@pytest.mark.parametrize("touches", [[(380.0, 640.0)], [(6.0, 8.0)], [(380.0, 640.0), (700.0, 1250.0)]])
@pytest.mark.parametrize("sizes", [(12, 3), (1, 40), (30, 30)])
def test_placing_two_lots_at_once_answers_as_placing_them_in_turn(touches, sizes, monkeypatch):
    """`place_both` against two `place` calls on a copy: the same spots, flags and draws,
    at a lone touch, at a corner (where the launch circle runs off the screen, so a lot
    often needs more rounds of draws: the second's go on, the first's are taken back)
    and over two areas."""
    sim = FrostSim(Params.preset("fern"), seed=4)
    for x, y in touches:
        sim.touch(x, y)
    later = []  # rounds drawn after the first, in each `place_both`
    draw = placement.disc_spots
    monkeypatch.setattr(placement, "disc_spots", lambda *a: later.append(1) or draw(*a))
    for tick in range(60):
        sim.step()
        rng = np.random.default_rng(tick)
        first = rng.integers(0, len(sim.areas), sizes[0]).astype(np.int32)
        second = rng.integers(0, len(sim.areas), sizes[1]).astype(np.int32)
        twin = copy.deepcopy(sim)
        later.clear()
        at_once = placements(sim, first, second, True)
        more = len(later)
        assert at_once == placements(twin, first, second, False)
        if touches[0] == (6.0, 8.0) and more:
            break
    else:
        assert touches[0] != (6.0, 8.0), "no lot at the corner needed a later round"


@pytest.mark.parametrize("touch", [(380.0, 640.0), (3.0, 1277.0), (757.0, 2.0)])
def test_clearance_rings_are_the_capped_cell_distance_to_the_candidate_cells(touch):
    """Without melts, each cell's ring count is the Chebyshev distance in cells to the
    nearest candidate cell, capped: brute force over every cell, by the screen's middle
    and its corners (where the rings around a cell run off the grid)."""
    from sim.index.clearance import CAP
    sim = FrostSim(Params.preset("fern"), seed=1)
    sim.touch(*touch)
    for _ in range(80):
        sim.step()
    g = sim.grid
    cand = np.flatnonzero(sim.candidates.count > 0)
    cy, cx = np.divmod(np.arange(g.size), g.cols)
    ky, kx = np.divmod(cand, g.cols)
    dist = np.maximum(np.abs(cx[:, None] - kx), np.abs(cy[:, None] - ky)).min(axis=1)
    assert len(cand) > 20
    assert sim.index.clearance.rings.tolist() == np.minimum(dist, CAP).tolist()


def test_clearance_radii_equal_the_float64_arithmetic_bit_for_bit():
    """Walkers' clearances worked in float64 as the rule reads (the cell from the float32
    quotient, the offsets and borders in float64) equal `radii`'s float32 offsets, at
    random spots and at the awkward ones: on and a float32 step either side of cell
    borders, by the screen's zero edges, and where x / s rounds up to the next cell."""
    sim = FrostSim(Params.preset("fern"), seed=2)
    sim.touch(380.0, 640.0)
    for _ in range(40):
        sim.step()
    clear = sim.index.clearance
    s = np.float32(sim.grid.cell)
    rng = np.random.default_rng(0)
    edges = (np.arange(1, 54) * s).astype(np.float32)
    xs = np.concatenate([rng.uniform(0, 760, 4000), edges, np.nextafter(edges, 0),
                         np.nextafter(edges, 1000), [0.0, 1e-30, 1e-7, 6.9999995, 7.0, 759.99994]])
    x = xs.astype(np.float32)
    y = np.resize(rng.permutation(x) * np.float32(1280 / 760), len(x)).astype(np.float32)
    y = np.minimum(y, np.float32(1279.9999))
    rim = rng.uniform(-5, 300, len(x)).astype(np.float32)
    kx, ky = (x / s).astype(np.int32), (y / s).astype(np.int32)
    fx, fy = x.astype(np.float64) - kx * np.float64(s), y.astype(np.float64) - ky * np.float64(s)
    border = np.minimum(np.minimum(fx, s - fx), np.minimum(fy, s - fy))
    k = clear.rings[ky * sim.grid.cols + kx]
    rho = np.where(k >= 1, (k - 1).astype(np.float32) * s + border, 0.0)
    edge = np.minimum(np.minimum(x, 760 - x), np.minimum(y, 1280 - y))
    want = np.minimum(np.minimum(rho, rim), edge) - np.float32(1e-2)
    assert (k >= 2).any() and (k == 1).any() and (k == 0).any()
    np.testing.assert_array_equal(clear.radii(x, y, rim), want)


@pytest.mark.parametrize("area", [(380.0, 640.0, 300.0), (301.0, 301.0, 300.0), (300.5, 640.0, 300.0),
                                  (375.0, 640.0, 380.0), (20.0, 30.0, 200.0)])
def test_a_walker_off_the_screen_is_outside_however_its_area_lies(area):
    """`outside` against the rule as written (off the screen, or beyond the area's rim) for
    one area a pixel or more inside the screen (where only the rim is checked), one just
    short of that, one reaching 5 px past an edge and one past a corner; walkers on, just
    off and far off every edge."""
    rng = np.random.default_rng(1)
    x = np.concatenate([rng.uniform(-60, 820, 3000), [-1e-3, 0.0, 759.999, 760.0, 760.001, -2.0]])
    y = np.concatenate([rng.uniform(-60, 1340, 3000), [-1e-3, 0.0, 1279.999, 1280.0, 1280.001, 640.0]])
    x, y = x.astype(np.float32), y.astype(np.float32)
    cx, cy, r = (np.float32(v) for v in area)
    ox, oy = x - cx, y - cy
    want = (x < 0) | (x >= 760) | (y < 0) | (y >= 1280) | (ox * ox + oy * oy > r * r)
    assert outside(x, y, np.array([cx, cy, r], np.float32), (760, 1280), False).tolist() == want.tolist()


# ---- random streams ------------------------------------------------------------------


def touched_then_walked(version: int, advanced: str | None = None):
    """A fern touch and one walk with the `advanced` part's stream (if any) 1000 draws
    on: (the seed's grain axis, the water as placed, the water after the walk)."""
    sim = FrostSim(Params.preset("fern"), seed=11, version=version)
    if advanced:
        getattr(sim.streams, advanced).random(1000)
    sim.touch(380.0, 640.0)
    placed = sim.water
    sim.walk()
    return sim.growth.axis.view().copy(), placed, sim.water


@pytest.mark.parametrize("advanced, changed", [("growth", "axis"), ("walk", "walked")])
def test_a_parts_own_draws_leave_the_other_parts_draws_as_they_were(advanced, changed):
    """From version 7 each part has its own stream: more draws by the growth rule (the
    seed's axis) leave where the water is placed and how it walks as they were, and more
    by the walk leave the axis and the placing. Up to version 6 the parts share one."""
    names = ("axis", "placed", "walked")
    before = dict(zip(names, touched_then_walked(7), strict=True))
    after = dict(zip(names, touched_then_walked(7, advanced), strict=True))
    for name in names:
        assert np.array_equal(before[name], after[name]) == (name != changed), name
    shared = touched_then_walked(6, advanced)
    assert not np.array_equal(touched_then_walked(6)[1], shared[1])


def test_each_part_of_version_7_draws_from_a_child_of_the_seed():
    """The streams are the seed's SeedSequence children in PARTS' order; version 6's one
    generator is numpy's for the seed."""
    sim = FrostSim(Params(), seed=42, version=7)
    children = np.random.SeedSequence(42).spawn(len(PARTS))
    for part, child in zip(PARTS, children, strict=True):
        assert getattr(sim.streams, part).random(4).tolist() == \
            np.random.default_rng(child).random(4).tolist()
    old = FrostSim(Params(), seed=42, version=6).streams
    assert len({id(getattr(old, part)) for part in PARTS}) == 1
    assert old.walk.random(4).tolist() == np.random.default_rng(42).random(4).tolist()


@given(st.integers(1, 40), st.integers(1, 12), st.floats(0.0, 1.0), st.integers(0, 2**32 - 1))
def test_checking_tries_by_rounds_picks_what_checking_them_all_picks(tries, k, p, seed):
    # The oracle: every draw checked at once (`first_good`). By rounds, a draw is checked
    # at most once, and not when its walker had a good try in an earlier run of tries
    # (runs double: try t's run starts at or after (t + 1) // 2).
    good = np.random.default_rng(seed).random((tries, k)) < p
    asked: list[int] = []

    def check(flat):
        asked.extend(flat.tolist())
        return good.ravel()[flat]

    placed, pick = placement.first_good_by_rounds(check, tries, k)
    want_placed, want_pick = placement.first_good(good)
    assert np.array_equal(placed, want_placed) and np.array_equal(pick, want_pick)
    assert len(asked) == len(set(asked))
    for flat in asked:
        t, w = divmod(flat, k)
        assert not good[:(t + 1) // 2, w].any()
    if p == 1.0:
        assert len(asked) == k  # every first try good: no other looked at
