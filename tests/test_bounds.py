"""Bounded work whatever the input: the water budget, areas that merge, the per-cell cap,
melts that look only at the ice nearby, and input spread over ticks. Each is checked
against a slow, obvious version or a hand-worked case."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from app.bench.scribble import scribble, storm
from app.simthread.backlog import MIN_INPUT_S, STEP_SAMPLES, Backlog
from sim import FrostSim, Params
from sim.core import budget, frost
from sim.index.grid import CELL_MARGIN, HashGrid
from sim.io.timeline import Timeline
from sim.look.geometry import _segments_in


def grown(params: Params, touches, ticks: int, seed: int = 0) -> FrostSim:
    sim = FrostSim(params, seed=seed)
    for x, y in touches:
        sim.touch(x, y)
    for _ in range(ticks):
        sim.step()
    return sim


def area_of_slow(areas: list, x: float, y: float) -> int:
    """The area a touch joins, by brute force: nearest centre whose disc holds it."""
    inside = [((x - cx) ** 2 + (y - cy) ** 2, i) for i, (cx, cy, r) in enumerate(areas)
              if (x - cx) ** 2 + (y - cy) ** 2 <= r * r]
    return min(inside)[1] if inside else -1


# ---- areas and the water budget ---------------------------------------------------------


def test_one_touch_gets_the_papers_pool():
    for name in ("c-1", "c-2", "c-3", "a-1"):
        sim = FrostSim(Params.preset(name), seed=0)
        sim.touch(380, 640)
        assert len(sim.water_area) == Params.preset(name).humidity


@settings(max_examples=40, deadline=None)
@example(points=[(10.0, 10.0), (210.0, 10.0), (130.0, 10.0)], budget=4000)  # nearer the 2nd
@given(st.lists(st.tuples(st.floats(0, 759.9), st.floats(0, 1279.9)), min_size=1, max_size=40),
       st.integers(1, 4000))
def test_touches_join_the_area_that_holds_them_and_water_stays_in_budget(points, budget):
    params = Params(humidity=1500, water_budget=budget, active_radius=150.0)
    sim = FrostSim(params, seed=1)
    areas: list[tuple[float, float, float]] = []
    for x, y in points:
        want = area_of_slow(areas, np.float32(x), np.float32(y))
        before = np.bincount(sim.water_area, minlength=len(areas) + 1)
        got = sim.touch(x, y)
        # A touch never takes water from the area it tops up.
        assert np.bincount(sim.water_area, minlength=len(areas) + 1)[got] >= before[got]
        if want < 0:
            areas.append((np.float32(x), np.float32(y), params.active_radius))
            want = len(areas) - 1
        assert got == want
        assert len(sim.water_area) <= budget
        sim.step()
        assert len(sim.water_area) <= budget
    assert len(sim.areas) == len(areas)


def test_the_water_a_touch_brings_stays_in_the_budget():
    # Two areas share a budget of 200: 100 walkers each, both pools short of humidity
    # 150. A touch into the first brings its ring (touch_water 48) from its own walkers:
    # the budget has no room for new ones.
    params = Params.preset("fern").replace(water_budget=200, humidity=150)
    assert params.touch_water == 48
    sim = FrostSim(params, seed=0)
    assert [sim.touch(200.0, 300.0), sim.touch(560.0, 1000.0)] == [0, 1]
    assert np.bincount(sim.water_area).tolist() == [100, 100]
    assert sim.touch(205.0, 300.0) == 0
    assert np.bincount(sim.water_area).tolist() == [100, 100]


def test_batch_planting_assigns_areas_like_touches_one_by_one():
    rng = np.random.default_rng(3)
    pts = rng.uniform((0, 0), (760, 1280), (300, 2))
    one = FrostSim(Params(), seed=0)
    by_one = [one.touch(x, y) for x, y in pts]
    batch = FrostSim(Params(), seed=0).plant(pts)
    assert batch.tolist() == by_one


def test_a_new_area_beyond_the_budget_takes_a_fair_share():
    params = Params(humidity=3000, water_budget=7000)
    sim = FrostSim(params, seed=0)
    for x in (100, 600):  # two far-apart areas: 3000 + 3000
        sim.touch(x, 200)
    sim.touch(380, 1100)  # a third: the budget is 7000, a fair share 2333
    counts = np.bincount(sim.water_area, minlength=3)
    assert counts.sum() <= 7000
    share = 7000 // 3
    assert counts[2] >= share - 1 and counts[2] <= 3000
    assert (counts[:2] >= share).all()
    # The trimmed areas kept their oldest walkers: the first ones created.
    assert counts.sum() >= 7000 - 2


def test_a_drag_through_one_area_adds_no_pools():
    sim = FrostSim(Params.preset("c-2"), seed=0)
    for y in np.arange(500, 700, 28.0):  # a drag well inside one 200 px area
        sim.touch(380, y)
        sim.step()
    assert len(sim.areas) == 1
    assert len(sim.water_area) <= Params().humidity
    assert (sim.parents[:1] == -1).all() and (sim.parents == -1).sum() == 8  # a seed per touch


# ---- melting: local work, the same result as a scan of everything -------------------------


def melt_slow(sim: FrostSim, dead: np.ndarray):
    """What melting `dead` cuts, by scanning the whole skeleton (before the melt)."""
    live_orphan = sim.crystal_alive & ~np.isin(np.arange(len(sim.parents)), dead)
    orphans = np.flatnonzero(np.isin(sim.parents, dead) & live_orphan)
    cut = np.concatenate([dead, orphans])
    segs = np.flatnonzero(np.isin(sim.segments_link, cut) & sim.segments_alive)
    ups = np.flatnonzero(np.isin(sim.upsampled_link, cut) & sim.upsampled_alive)
    return orphans, segs, ups


@pytest.mark.parametrize("preset", ["c-2", "a-1", "c-1"])
def test_melts_cut_exactly_what_a_full_scan_cuts(preset):
    sim = grown(Params.preset(preset, replenish=True), [(380, 640), (300, 500)], 150)
    rng = np.random.default_rng(0)
    for x, y, r in rng.uniform((200, 400, 5), (500, 800, 60), (12, 3)):
        live = np.flatnonzero(sim.crystal_alive)
        c = sim.crystals[live].astype(np.float64)
        dead = live[np.hypot(c[:, 0] - x, c[:, 1] - y) < r]
        orphans, segs, ups = melt_slow(sim, dead)
        melted = sim.melt(x, y, r)
        assert melted.crystals.tolist() == dead.tolist()
        assert sorted(melted.orphans.tolist()) == orphans.tolist()
        assert sorted(melted.segments.tolist()) == segs.tolist()
        assert sorted(melted.upsampled.tolist()) == ups.tolist()
        sim.step()


def test_survivors_near_a_melt_are_all_live_segments_that_meet_the_box():
    sim = grown(Params.preset("c-1", replenish=True), [(380, 640)], 400)
    sim.melt(380, 640, 30)
    rng = np.random.default_rng(1)
    corners = rng.uniform((200, 450), (560, 830), (40, 2))
    boxes = [(x, y, x + s, y + s) for (x, y), s in zip(corners, rng.uniform(0.5, 30, 40), strict=True)]
    for box, w in zip([(0.0, 0.0, 760.0, 1280.0), *boxes], [1.5, *([1.5, 4.0] * 20)], strict=True):
        seg = sim.segments[sim.segments_alive]
        reach = w * np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1])
        meets = ((np.maximum(seg[:, 0], seg[:, 2]) + reach >= box[0])
                 & (np.minimum(seg[:, 0], seg[:, 2]) - reach <= box[2])
                 & (np.maximum(seg[:, 1], seg[:, 3]) + reach >= box[1])
                 & (np.minimum(seg[:, 1], seg[:, 3]) - reach <= box[3]))
        want = {tuple(s) for s in seg[meets].tolist()}
        got = {tuple(s) for s in _segments_in(sim, box, w).tolist()}
        assert got == want


def test_melted_water_never_takes_a_pool_above_humidity():
    params = Params.preset("c-2", humidity=800, active_radius=80.0, replenish=True)
    sim = grown(params, [(380, 640)], 120)
    assert len(sim.crystals) > 400
    sim.melt(380, 640, 60)
    assert len(sim.water_area) <= 800
    for _ in range(30):
        sim.step()
        sim.melt(380, 640, 45)
        assert len(sim.water_area) <= 800


def test_an_area_with_all_its_ice_melted_keeps_no_water():
    sim = grown(Params.preset("c-1"), [(380, 640), (380, 200)], 60)
    sim.melt(380, 640, 250)  # every crystal of the first area
    assert not sim.crystal_alive[sim.crystal_area == 0].any()
    assert (sim.water_area != 0).all()
    assert (sim.water_area == 1).sum() > 0


# ---- the per-cell cap -------------------------------------------------------------------------


def test_no_cell_ever_lists_more_than_the_cap():
    sim = FrostSim(Params.preset("c-2", humidity=10000, replenish=True, active_radius=120.0), seed=0)
    sim.touch(380, 640)
    for _ in range(80):
        full = sim.candidates.count >= frost.CELL_CAP
        sim.step()
        assert sim.candidates.count.max() <= frost.CELL_CAP
        # Water that walked into a full cell is gone, and none is placed there. (A cell
        # that fills during the tick may still hold water: it goes at the next walk.)
        keys = sim.grid.keys(sim.water[:, 0], sim.water[:, 1])
        assert not full[keys].any()
    assert sim.candidates.count.max() == frost.CELL_CAP  # it was reached


def listed_slow(sim: FrostSim, cells: np.ndarray | None = None) -> np.ndarray:
    """Live crystals listed in each cell (or each of `cells`), by brute force: those whose
    freezing disc (hc, and the grid's listing margin) meets the cell's rectangle."""
    x0, y0 = cell_corners(sim, cells)
    c = sim.crystals[sim.crystal_alive].astype(np.float64)
    return meets(sim, c[:, :1], c[:, 1:], x0[None], y0[None]).sum(axis=0)


def disc_cells_slow(sim: FrostSim, x: float, y: float) -> np.ndarray:
    """The cells a seed at (x, y) would be listed in, by the same brute force."""
    x0, y0 = cell_corners(sim)
    return np.flatnonzero(meets(sim, x, y, x0, y0))


def cell_corners(sim: FrostSim, cells: np.ndarray | None = None):
    grid = sim.grid
    cells = np.arange(grid.size) if cells is None else cells
    return cells % grid.cols * grid.cell, cells // grid.cols * grid.cell


def meets(sim: FrostSim, x, y, x0, y0) -> np.ndarray:
    """Whether the disc at (x, y) meets the cell with corner (x0, y0)."""
    s, r = sim.grid.cell, sim.params.hc + CELL_MARGIN
    gx = np.maximum(np.maximum(x0 - x, 0), x - (x0 + s))
    gy = np.maximum(np.maximum(y0 - y, 0), y - (y0 + s))
    return gx ** 2 + gy ** 2 < r * r


FINEST = {"hc": 16.0, "D": 1.0, "grid_spacing": 2}  # the most work a crystal can bring


def test_a_touch_where_its_cells_are_full_plants_nothing():
    # A page tapping one spot 20 times a tick: from version 9 a touch plants its seed (and
    # brings water) exactly when every cell its disc meets lists fewer than CELL_CAP, and
    # no cell ever lists more, fern crystals (grown hc from their walker) included.
    sim = FrostSim(Params.preset("fern", **FINEST), seed=0)
    cells, refused = disc_cells_slow(sim, 380.0, 640.0), 0
    for _ in range(120):
        for _k in range(20):
            room = (listed_slow(sim, cells) < frost.CELL_CAP).all()
            crystals, water = len(sim.crystals), len(sim.water_area)
            area = sim.touch(380.0, 640.0)
            assert (area >= 0) == room
            if not room:
                refused += 1
                assert (len(sim.crystals), len(sim.water_area)) == (crystals, water)
        sim.step()
        assert listed_slow(sim).max() <= frost.CELL_CAP
        assert np.array_equal(listed_slow(sim), sim.candidates.count)
    assert refused > 2000  # the cells filled early, and the rest planted nothing


def test_a_session_of_version_8_still_piles_touches_into_one_cell():
    sim = FrostSim(Params.preset("fern", **FINEST), seed=0, version=8)
    for _ in range(3):
        for _k in range(50):
            assert sim.touch(380.0, 640.0) >= 0
        sim.step()
    assert listed_slow(sim).max() > frost.CELL_CAP  # as it grew when it was recorded


@pytest.mark.parametrize("preset", ["a-1", "c-3"])
def test_the_cap_leaves_table_1_frost_unchanged(preset, monkeypatch):
    capped = grown(Params.preset(preset), [(380, 640)], 200)
    monkeypatch.setattr(budget, "CELL_CAP", 10**9)
    free = grown(Params.preset(preset), [(380, 640)], 200)
    assert np.array_equal(capped.crystals, free.crystals)
    assert np.array_equal(capped.parents, free.parents)


def test_freezes_that_would_overflow_a_cell_are_dropped_in_walker_order(monkeypatch):
    monkeypatch.setattr(budget, "CELL_CAP", 3)
    sim = FrostSim(Params(hc=7.0, step=1e-6), seed=0)
    sim.touch(100.0, 100.0)  # listed in its cells: count 1 there
    # all within hc of the seed, in its cell
    sim.set_water([(x, 100.0) for x in (103.0, 104.0, 105.0, 102.0)])
    sim.step()
    # cap 3, one listed: the first two walkers freeze, the other two are dropped.
    np.testing.assert_allclose(sim.crystals[1:], [[103.0, 100.0], [104.0, 100.0]], atol=1e-4)
    assert len(sim.water_area) == 0


def admitted_slow(points, count, grid, hc, take):
    """Which of the first `take` freezes a walker-order pass admits: each one's disc cells
    must all hold fewer than CELL_CAP, counting the freezes admitted before it."""
    count = count.copy()
    kept = []
    for i, p in enumerate(points[:take]):
        cells, _ = grid.disc_cells(p[None], hc)
        if (count[cells] < budget.CELL_CAP).all():
            count[cells] += 1
            kept.append(i)
    return kept


def test_the_cap_holds_when_each_crystal_brings_much_work():
    # hc 16, D 1, grid_spacing 2: a crystal's work admits 69 freezes a tick, so 69 + 10 stays
    # under the cap, yet one cell already holds 127: only one of the ten may freeze there.
    hc = 16.0
    work = budget.work_per_crystal(hc, 2, 1.0)
    assert budget.FREEZE_WORK // work + 10 <= budget.CELL_CAP
    grid = HashGrid(760, 1280, hc)
    points = np.array([(100.0 + i, 100.0) for i in range(10)], np.float32)
    count = np.zeros(grid.size, np.int32)
    cells, _ = grid.disc_cells(points[:1], hc)
    count[cells] = 127
    frozen, parents = np.arange(10), np.zeros(10, np.int32)
    kept, _, over = budget.admit(frozen, parents, count, grid, lambda i: points[i], hc, work,
                                 count_bound=int(count.max()))
    expected = admitted_slow(points, count, grid, hc, 10)
    assert kept.tolist() == expected == [0]
    assert over.tolist() == list(range(1, 10))


def test_a_crystal_that_alone_brings_more_than_the_ticks_work_still_freezes_one_a_tick():
    # work beyond FREEZE_WORK: the tick takes the first walker in order (the rest wait a
    # tick), never none, or the frost would stop growing for good.
    hc = 7.0
    grid = HashGrid(760, 1280, hc)
    points = np.array([(100.0 + i, 100.0) for i in range(3)], np.float32)
    count = np.zeros(grid.size, np.int32)
    frozen, parents = np.array([5, 6, 7]), np.array([0, 0, 1], np.int32)
    kept, kept_parents, over = budget.admit(frozen, parents, count, grid,
                                            lambda i: points[i - 5], hc, 2 * budget.FREEZE_WORK)
    assert kept.tolist() == [5] and kept_parents.tolist() == [0] and len(over) == 0


def level_slow(counts, need: int, floor: int) -> int:
    """The water-filling level by trying every level from the top down."""
    for level in range(max(counts, default=0), floor - 1, -1):
        if sum(max(c - level, 0) for c in counts) >= need:
            return max(level, floor)
    return floor


def test_the_cut_level_frees_exactly_what_is_needed_where_it_can():
    # Pools of 10 and 20, 5 to free: cut to 15 frees exactly 5 (16 would free 4).
    assert budget.level(np.array([10, 20]), 5, 0) == 15
    rng = np.random.default_rng(3)
    for _ in range(300):
        counts = rng.integers(0, 40, rng.integers(1, 6))
        need, floor = int(rng.integers(1, 60)), int(rng.integers(0, 20))
        assert budget.level(counts, need, floor) == level_slow(counts.tolist(), need, floor), (
            counts, need, floor)


# ---- input spread over ticks -------------------------------------------------------------------


def _timed(now: list[float], cost: float, applied: list):
    def apply(item):
        applied.append(item)
        now[0] += cost
    return apply


# A unit of time (about 1 ms) whose sums are exact in binary floating point.
MS = 2.0 ** -10


def test_backlog_takes_items_while_the_next_one_should_still_fit():
    now, applied = [0.0], []
    backlog = Backlog(budget_s=10 * MS, clock=lambda: now[0])
    backlog.extend(range(10))
    # 4 units an item: at 0 and at 4 (it ends at 8 < 10); a third would end at 12.
    assert backlog.run(_timed(now, 4 * MS, applied)) == 2
    assert applied == [0, 1] and len(backlog) == 8
    # 1 unit an item, learnt from the start: nine (a tenth would end at the budget, not under).
    now = [0.0]
    cheap = Backlog(budget_s=10 * MS, clock=lambda: now[0])
    cheap.extend(range(20))
    assert cheap.run(_timed(now, MS, [])) == 9


def test_backlog_leaves_room_for_the_median_of_the_last_steps():
    now = [0.0]
    backlog = Backlog(budget_s=10 * MS, clock=lambda: now[0])
    backlog.extend(range(40))
    backlog.stepped(6 * MS)  # 4 left: 1-unit items go at 0, 1 and 2 (ending under 4)
    assert backlog.run(_timed(now, MS, [])) == 3
    backlog.stepped(2 * MS)  # the median of 6 and 2: 4 units, 6 left
    assert backlog.run(_timed(now, MS, [])) == 5
    backlog.stepped(20 * MS)  # one slow step (a rebuild's): the median of 6, 2, 20 is 6
    assert backlog.step_s == 6 * MS and backlog.run(_timed(now, MS, [])) == 3
    for _ in range(STEP_SAMPLES):
        backlog.stepped(MS)  # older steps are forgotten
    assert backlog.step_s == MS


def test_input_keeps_its_least_share_beside_a_long_step():
    now = [0.0]
    backlog = Backlog(budget_s=10 * MS, clock=lambda: now[0])
    backlog.extend(range(40))
    backlog.stepped(30 * MS)  # a step three times the budget: MIN_INPUT_S is left
    assert MIN_INPUT_S == 0.003  # 3.07 units: 1-unit items end at 1, 2 and 3 units
    assert backlog.run(_timed(now, MS, [])) == 3


def test_an_items_learnt_cost_follows_its_latest_by_a_quarter():
    """COST_WEIGHT: one slow item (8 units) is remembered, each later cost moving the mean a
    quarter of the way (hand-worked: 8, 6.25, 4.9375, ...), so 1-unit items in a 4-unit
    budget go one a tick until the mean is under 3 units (the fifth tick), then two."""
    now = [0.0]
    backlog = Backlog(budget_s=4 * MS, clock=lambda: now[0])
    backlog.extend([0])
    assert backlog.run(_timed(now, 8 * MS, [])) == 1
    backlog.extend(range(20))
    counts = [backlog.run(_timed(now, MS, [])) for _ in range(5)]
    assert counts == [1, 1, 1, 1, 2]
    assert backlog.item_s[None] == 2.245849609375 * MS


def test_backlog_learns_each_kind_of_item_apart():
    now, applied = [0.0], []
    costs = {"slow": 8 * MS, "fast": MS}

    def apply(item):
        applied.append(item)
        now[0] += costs[item]

    backlog = Backlog(budget_s=11 * MS, clock=lambda: now[0], kind=lambda item: item)
    backlog.extend(["slow", "fast", "fast", "fast", "slow", "fast", "fast"])
    # slow ends at 8; fast, not yet seen, goes (9); fast again ends at 10 < 11; no more
    assert backlog.run(apply) == 3
    # fast (1), slow (ends at 9), fast (10): a slow kind does not hold up fast ones
    assert backlog.run(apply) == 3 and len(backlog) == 1
    assert backlog.item_s == {"slow": 8 * MS, "fast": MS}


def test_backlog_always_applies_one_item():
    now, applied = [0.0], []
    spent = Backlog(budget_s=0.0, clock=lambda: now[0])
    spent.extend(["a", "b"])
    assert spent.run(_timed(now, 0.004, applied)) == 1  # however little time is left
    spent.stepped(1.0)  # a step longer than the budget still lets one through
    assert spent.run(_timed(now, 0.004, applied)) == 1 and applied == ["a", "b"]
    assert Backlog().run(_timed(now, 0.004, applied)) == 0
    still = Backlog(budget_s=0.0, clock=lambda: 0.0)  # free items on a still clock
    still.extend([1, 2])
    assert still.run(lambda item: None) == 1


def test_a_scribble_keeps_walkers_and_cells_bounded_and_replays():
    params = Params.preset("c-2")
    schedule = scribble(params, seed=2, seconds=10)
    kinds = {e["kind"] for tick in schedule for e in tick}
    assert kinds == {"touch", "melt", "params"}
    timeline = Timeline(params, 0)
    for events in schedule:
        timeline.apply(events)
        timeline.step()
        assert len(timeline.sim.water_area) <= timeline.params.water_budget
        assert timeline.sim.candidates.count.max() <= frost.CELL_CAP


def test_a_storm_has_the_asked_number_of_touches_and_melts():
    schedule = storm(seed=0, events=2000, seconds=10)
    assert len(schedule) == 250
    events = [e for tick in schedule for e in tick]
    assert len(events) == 2000
    assert sum(e["kind"] == "melt" for e in events) == 1000
    assert all(0 <= e["x"] < 760 and 0 <= e["y"] < 1280 for e in events)


def test_freezes_beyond_the_tick_s_work_wait_as_water(monkeypatch):
    params = Params(hc=7.0, step=1e-6)
    sim = FrostSim(params, seed=0)
    per_crystal = sim.work_per_crystal
    assert per_crystal == 1 * (2 * (2 + 1) + 1) ** 2  # D = hc: one segment; 7x7 stencil at 4 px
    monkeypatch.setattr(budget, "FREEZE_WORK", 2 * per_crystal + 1)  # room for two a tick
    sim.touch(100.0, 100.0)
    xs = [103.0, 97.0, 100.0, 104.0]
    sim.set_water(list(zip(xs, [104.0, 104.0, 95.0, 96.0], strict=True)))
    sim.step()
    assert len(sim.crystals) == 3 and sim.crystals[1:, 0].tolist() == pytest.approx(xs[:2], abs=1e-4)
    assert len(sim.water_area) == 2  # the other two are still water, not dropped
    sim.step()
    assert len(sim.crystals) == 5 and len(sim.water_area) == 0


@pytest.mark.parametrize("refused, named, allowed", [
    ({"D": 0.4}, "D=0.4", {"D": 7.0 / 16}),
    ({"hc": 16.5, "D": 16.5}, "hc=16.5", {"hc": 16.0, "D": 16.0}),
    ({"grid_spacing": 1, "hc": 12.5, "D": 7.0}, "grid_spacing=1", {"grid_spacing": 1, "hc": 12.0}),
    ({"water_budget": 30_001}, "water_budget=30001", {"water_budget": 30_000}),
    ({"humidity": 100_001}, "humidity=100001", {"humidity": 100_000})])
def test_settings_whose_tick_work_is_unbounded_are_refused_by_name(refused, named, allowed):
    with pytest.raises(ValueError, match=named.replace(".", r"\.")):
        Params(**refused)
    Params(**allowed)  # the largest allowed value of the same kind is fine


def test_an_item_replaces_the_last_waiting_only_where_told():
    backlog = Backlog()
    same = lambda a, b: a[0] == b[0] == "params"  # noqa: E731
    assert backlog.extend([("params", 1), ("params", 2), ("touch", 3), ("params", 4)], same) == 1
    assert backlog.extend([("params", 5)], same) == 1
    assert list(backlog) == [("params", 2), ("touch", 3), ("params", 5)]
    assert backlog.extend([("params", 6)]) == 0 and len(backlog) == 4
