"""Storms of touches in the looks beyond the paper: placement from cells in one pass for
every area, bounded per tick, and a touch that brings water to its own seed
(docs/method.md, 4.3, 5.2, 5.3). Checked by brute force over every crystal, or against a
run driven step by step."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from app.bench import scribble as scribble_module
from app.bench.scribble import play, spread, storm
from app.simthread import backlog
from app.simthread.backlog import Backlog
from sim import FrostSim, Params
from sim.core import budget, frost, placement
from sim.io.session import SessionLog
from sim.io.timeline import Timeline, replay

SMALL = (240, 320)  # a small screen keeps a frosted pane cheap to grow


def frosted(name: str, touches: int, ticks: int, seed: int = 0, version: int = frost.VERSION,
            **over) -> FrostSim:
    """A small screen under `touches` random touches (one a tick), then quiet ticks."""
    sim = FrostSim(Params.preset(name, **over), *SMALL, seed=seed, version=version)
    for x, y in np.random.default_rng(seed).uniform((0, 0), SMALL, (touches, 2)):
        sim.touch(x, y)
        sim.step()
    for _ in range(ticks):
        sim.step()
    return sim


def nearest_slow(sim: FrostSim, pts: np.ndarray) -> np.ndarray:
    """Each point's distance to the nearest live crystal, over every crystal."""
    c = sim.crystals[sim.crystal_alive].astype(np.float64)
    return np.sqrt(((pts[:, None, :] - c[None, :, :]) ** 2).sum(axis=2)).min(axis=1)


def free_slow(sim: FrostSim, pts: np.ndarray) -> np.ndarray:
    """A point's cell lists no crystal: no live crystal's freezing disc (radius hc) meets
    the cell, by brute force over every crystal and the cell's box."""
    s, hc = sim.grid.cell, sim.params.hc
    x0, y0 = np.floor(pts[:, 0] / s) * s, np.floor(pts[:, 1] / s) * s
    c = sim.crystals[sim.crystal_alive].astype(np.float64)
    dx = np.clip(c[None, :, 0], x0[:, None], x0[:, None] + s) - c[None, :, 0]
    dy = np.clip(c[None, :, 1], y0[:, None], y0[:, None] + s) - c[None, :, 1]
    return ~((dx ** 2 + dy ** 2) <= hc * hc).any(axis=1)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_spots_placed_from_cells_lie_in_their_own_area_on_glass(seed):
    sim = frosted("fern", 15, 40, seed, active_radius=60.0)
    areas = np.repeat(np.arange(len(sim.areas)), 300).astype(np.int32)
    sim.placer.cell_work = len(areas)
    x, y, ok = sim.placer.cell_spots_all(areas, sim.ice_state())
    assert ok.sum() > len(areas) // 4  # a frosted screen still has glass between fronds
    pts = np.column_stack((x, y)).astype(np.float64)[ok]
    a = sim.areas[areas[ok]].astype(np.float64)
    d = np.hypot(pts[:, 0] - a[:, 0], pts[:, 1] - a[:, 1])
    assert (d <= a[:, 2] + 1e-3).all()  # in its own area's disc
    # Inside the annulus' hole only where the annulus has no free cell (growth mode).
    for k in np.unique(areas[ok][d < a[:, 3] - 1e-3]):
        assert not free_slow(sim, annulus_centres(sim, k)).any()
    assert ((pts >= 0) & (pts < SMALL)).all()
    # Outside candidate cells, or (an area all ice) on glass: hc / 2 clear of every crystal.
    glass = nearest_slow(sim, pts) >= sim.params.hc / 2 - 1e-3
    assert (free_slow(sim, pts) | glass).all()


def test_placement_from_cells_takes_two_passes_whatever_the_number_of_areas(monkeypatch):
    sim = frosted("fern", 40, 60, active_radius=40.0)
    assert len(sim.areas) >= 4
    calls = []
    real = sim.index.nearest_d2
    monkeypatch.setattr(sim.index, "nearest_d2", lambda p: calls.append(len(p)) or real(p))
    sim.placer.cell_work = 10_000
    sim.placer.cell_spots_all(np.repeat(np.arange(len(sim.areas)), 50).astype(np.int32),
                              sim.ice_state())
    assert 1 <= len(calls) <= 2  # one per round of draws, never one per area


def test_a_tick_places_at_most_cell_work_walkers_from_cells(monkeypatch):
    sim = frosted("fern", 40, 60, active_radius=40.0)
    placed = []
    real = sim.placer.cell_spots_all
    monkeypatch.setattr(sim.placer, "cell_spots_all",
                        lambda area, ice: placed.append(len(area)) or real(area, ice))
    monkeypatch.setattr(placement, "CELL_WORK", 150)
    sim.step()  # the budget is renewed at a tick's start
    totals = []
    for _ in range(5):
        placed.clear()
        sim.step()
        sim.touch(120.0, 160.0)  # touches between two steps count in the tick they follow
        sim.touch(60.0, 60.0)
        totals.append(sum(placed))
    assert max(totals) == 150  # the demand reached the cap, and went no further


def annulus_centres(sim: FrostSim, area: int) -> np.ndarray:
    """Centres of on-screen cells lying well inside an area's annulus (a cell's width
    from its rims), by brute force over the cells."""
    cx, cy, r_out, r_in = (float(v) for v in sim.areas[area, :4])
    s = sim.grid.cell
    pts = np.array([((c + 0.5) * s, (r + 0.5) * s) for r in range(sim.grid.rows)
                    for c in range(sim.grid.cols)])
    d = np.hypot(pts[:, 0] - cx, pts[:, 1] - cy)
    inside = (d >= r_in + s) & (d <= r_out - s) & (pts[:, 0] < sim.width) & (pts[:, 1] < sim.height)
    return pts[inside].reshape(-1, 2)


def test_a_full_area_skips_its_disc_draws():
    sim = frosted("fern", 40, 60, active_radius=40.0)
    sim.placer.cell_work = 10_000
    sim.placer.cell_spots_all(np.arange(len(sim.areas), dtype=np.int32),  # list every area's cells
                              sim.ice_state())
    full = sim.placer.annulus_full(np.arange(len(sim.areas)))
    assert full.any()
    for a in np.flatnonzero(full):  # brute force: no free cell well inside its annulus
        assert not free_slow(sim, annulus_centres(sim, a)).any()


# ---- a touch brings water to its seed ---------------------------------------------------


@pytest.mark.parametrize("version", [4, 5])
def test_a_touch_brings_water_to_glass_around_its_seed(version):
    params = Params.preset("fern")
    sim = frosted("fern", 3, 80, version=version)
    before = sim.water.copy()
    n = len(before)
    area = sim.touch(130.0, 150.0)
    seed = sim.crystals[-1].astype(np.float64)
    assert area < len(sim.areas)  # it joined an area that holds water
    moved = np.flatnonzero((sim.water[:n] != before).any(axis=1))
    # Its top-up filled the pool (the new walkers are that), so the touch moved its own.
    assert (sim.water_area == area).sum() == params.humidity
    assert 0 < len(moved) <= params.touch_water
    brought = moved
    assert (sim.water_area[brought] == area).all()
    pts = sim.water[brought].astype(np.float64)
    r = np.hypot(*(pts - seed).T)
    hc = params.hc
    assert ((r >= hc - 1e-3) & (r <= 2 * hc + 1e-3)).all()
    near = nearest_slow(sim, pts)
    assert (near >= hc / 2 - 1e-3).all()  # on glass
    # No crystal within hc of it (those it could freeze to) is nearer than the seed.
    assert ((r <= near + 1e-3) | (near >= hc - 1e-3)).all()


def ring(sim: FrostSim, x: float, y: float) -> int:
    """Walkers within 2 hc of (x, y)."""
    return int((np.hypot(sim.water[:, 0] - x, sim.water[:, 1] - y) <= 2 * sim.params.hc).sum())


def drained(version: int, keep: int = 0, **over) -> FrostSim:
    """A 60 x 60 px screen whose one area's launch circle lies off the screen, so its
    water is placed from cells, at most CELL_WORK a tick: the touch that opens it spends
    them all, and the tick's later top-ups place nothing. Its pool is then cut to its
    first `keep` walkers: an area whose water finds no spot, as in a long scribble."""
    sim = FrostSim(Params.preset("fern", launch=100.0, **over), 60, 60, seed=0,
                   version=version)
    sim.touch(30.0, 30.0)
    assert len(sim.water) == frost.CELL_WORK
    sim.set_water(sim.water[:keep])
    return sim


@pytest.mark.parametrize("version", [4, 5])
def test_a_touch_into_a_drained_area_brings_new_walkers_and_leaves_the_last_ring(version):
    sim = drained(version)
    created = sim.water_created
    sim.touch(30.0, 45.0)
    sim.touch(30.0, 15.0)  # a drag's next touch, 30 px on: the rings do not overlap
    if version == 4:  # nothing to move: neither seed gets water
        assert len(sim.water) == 0
        return
    assert ring(sim, 30.0, 45.0) == ring(sim, 30.0, 15.0) == 48
    assert len(sim.water) == 96 and sim.water_created - created == 96


def test_a_touch_brings_new_walkers_only_while_the_budget_has_room():
    sim = drained(5, keep=388, water_budget=400)
    created, before = sim.water_created, sim.water.copy()
    sim.touch(30.0, 45.0)  # room for 12: it creates 12 and moves 36 of the pool
    assert len(sim.water) == 400 and sim.water_created - created == 12
    moved = np.flatnonzero((sim.water[:388] != before).any(axis=1))
    assert len(moved) == 36
    r = np.hypot(*(sim.water[np.r_[moved, 388:400]].astype(np.float64) - (30.0, 45.0)).T)
    assert ((r >= 7.0 - 1e-3) & (r <= 14.0 + 1e-3)).all()


def test_a_touch_into_a_full_pool_creates_nothing():
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(380.0, 640.0)
    created, n = sim.water_created, len(sim.water)
    sim.touch(380.0, 700.0)
    assert sim.water_created == created and len(sim.water) == n == sim.params.humidity
    assert ring(sim, 380.0, 700.0) == 48


def listed_nearest_slow(sim: FrostSim, pts: np.ndarray) -> np.ndarray:
    """Each point's distance to the nearest live crystal listed in its cell (whose freezing
    disc, radius hc, meets the cell; inf if none), by brute force over every crystal."""
    s, hc = sim.grid.cell, sim.params.hc
    x0, y0 = np.floor(pts[:, 0] / s) * s, np.floor(pts[:, 1] / s) * s
    c = sim.crystals[sim.crystal_alive].astype(np.float64)
    dx = np.clip(c[None, :, 0], x0[:, None], x0[:, None] + s) - c[None, :, 0]
    dy = np.clip(c[None, :, 1], y0[:, None], y0[:, None] + s) - c[None, :, 1]
    listed = (dx ** 2 + dy ** 2) <= hc * hc
    d = np.hypot(pts[:, None, 0] - c[None, :, 0], pts[:, None, 1] - c[None, :, 1])
    return np.where(listed, d, np.inf).min(axis=1)


def test_a_seed_ringed_by_ice_fills_the_sliver_of_its_ring_it_is_nearest():
    # Twelve crystals 14.2 px around the spot: the seed is the nearest crystal only in a
    # thin band of its ring. Each walker the touch brings takes the first of TOUCH_TRIES
    # uniform draws in the ring at least hc/2 from ice where the seed is the nearest
    # crystal its cell lists, so the number placed is binomial with
    # p = 1 - (1 - f) ** TOUCH_TRIES, f that band's share of the ring (measured here by
    # brute force over 100 000 draws).
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(380.0, 640.0)
    sim.step()
    ang = np.deg2rad(30.0 * np.arange(12) + 5.0)
    sim.plant(np.column_stack((300.0 + 14.2 * np.cos(ang), 600.0 + 14.2 * np.sin(ang))),
              water=False)
    before = sim.water.copy()
    sim.touch(300.0, 600.0)
    moved = (sim.water[:len(before)] != before).any(axis=1).sum()
    hc, rng = sim.params.hc, np.random.default_rng(1)
    u = rng.random((2, 100_000))
    r, th = hc * np.sqrt(1.0 + 3.0 * u[0]), 2 * np.pi * u[1]
    p = np.column_stack((300.0 + r * np.cos(th), 600.0 + r * np.sin(th)))
    d = listed_nearest_slow(sim, p)  # (the seed is listed where it is within reach)
    f = ((d >= hc / 2) & (r <= d + 1e-6)).mean()
    assert 0.005 < f < 0.05  # a sliver
    q = 1 - (1 - f) ** frost.TOUCH_TRIES
    mean, sd = 48 * q, np.sqrt(48 * q * (1 - q))
    assert abs(moved - mean) < 4 * sd, (moved, mean, sd, f)


# (how the seed at (480, 640) came, version, whether its first hits count together)
SEEDS = [("joined", 5, True), ("joined", 4, False), ("opened", 5, False),
         ("opened", 7, False), ("opened", 8, True), ("without water", 8, False)]


@pytest.mark.parametrize("how, version, pooled", SEEDS)
def test_a_ringed_seeds_hits_count_together_until_its_first_child(how, version, pooled):
    # Five walkers just inside hc of a seed, 60 degrees apart: one hit on each of five
    # slots. A fern tip slot grows on its 5th hit. From version 5 the hits of a seed a
    # touch brought a ring of water (it joined an area; from version 8 it may open one
    # too) count together, so it grows one child, in the slot of the hit that made five;
    # up to version 7 a touch that opens an area, and the pane's seeds (planted without
    # water) always, count slot by slot.
    params = Params.preset("fern", step=0.01, long_jumps=False, drift=0.0)
    sim = FrostSim(params, seed=0, version=version)
    if how != "opened":
        sim.touch(380.0, 640.0)  # opens the area the seed joins
    sim.plant([(480.0, 640.0)], water=how != "without water")
    seed = len(sim.crystals) - 1
    hc = params.hc
    theta = np.deg2rad(10.0 + 60.0 * np.arange(5))
    sim.set_water(np.column_stack((480.0 + 0.8 * hc * np.cos(theta),
                                   640.0 + 0.8 * hc * np.sin(theta))))
    sim.step()
    grown = np.flatnonzero(sim.parents == seed)
    if not pooled:
        assert len(grown) == 0
        return
    assert len(grown) == 1
    d = sim.crystals[grown[0]].astype(np.float64) - (480.0, 640.0)
    assert np.hypot(*d) == pytest.approx(hc, abs=1e-3)
    # its slot is the axis nearest the last walker's direction: within 30 degrees of it
    turn = (np.arctan2(d[1], d[0]) - theta[-1] + np.pi) % (2 * np.pi) - np.pi
    assert abs(np.rad2deg(turn)) <= 30.0 + 1e-6
    six = np.deg2rad(10.0 + 60.0 * np.arange(6))
    sim.set_water(np.column_stack((480.0 + 0.8 * hc * np.cos(six),
                                   640.0 + 0.8 * hc * np.sin(six))))
    sim.step()  # with a child, each slot counts its own again: one hit each grows nothing
    assert len(np.flatnonzero(sim.parents == seed)) == 1


def test_without_touch_water_a_touch_moves_no_walker():
    sim = frosted("fern", 3, 80, touch_water=0)
    before = sim.water.copy()
    sim.touch(130.0, 150.0)
    assert (sim.water[:len(before)] == before).all()


@pytest.mark.parametrize("version", [7, 8])
def test_a_touch_that_opens_an_area_rings_its_seed_from_version_8(version):
    # Its new pool lies on the launch circle, `launch` (30 px) beyond its only ice, the
    # seed. Up to version 7 that is all; from version 8 the touch moves `touch_water` of
    # that pool into the ring from hc to 2 hc around its seed, and no other area's walker.
    params = Params.preset("fern")
    sim = FrostSim(params, seed=0, version=version)
    sim.touch(100.0, 100.0)
    before = sim.water.copy()
    sim.touch(600.0, 1100.0)  # far beyond the first area
    assert len(sim.areas) == 2
    assert (sim.water[:len(before)] == before).all()
    new = sim.water[len(before):].astype(np.float64)
    assert len(new) == params.humidity and (sim.water_area[len(before):] == 1).all()
    r = np.hypot(*(new - (600.0, 1100.0)).T)
    ringed = (r >= params.hc - 1e-3) & (r <= 2 * params.hc + 1e-3)
    on_circle = np.abs(r - params.launch) < 1e-3
    assert ringed.sum() == (params.touch_water if version >= 8 else 0)
    assert (ringed | on_circle).all()


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_with_touch_water_a_touch_beside_ice_grows_within_a_second(seed):
    sim = FrostSim(Params.preset("fern"), seed=seed)
    sim.touch(380.0, 640.0)
    for _ in range(150):
        sim.step()
    rng = np.random.default_rng(seed)
    glass = [p for p in rng.uniform((180, 440), (580, 840), (400, 2))
             if 2 * sim.params.hc < nearest_slow(sim, p[None])[0] < 40]
    area = sim.touch(*glass[0])  # open glass beside the ice, in its area
    assert area == 0 and len(sim.water_area)
    s = len(sim.crystals) - 1
    for _ in range(25):
        sim.step()
    assert s in sim.parents, "no child of the seed after 25 ticks"


def test_play_counts_each_touchs_wait_as_a_step_by_step_run_sees_it():
    params = Params.preset("fern")
    schedule = [*spread(0, 30, SMALL), *([[]] * 20)]
    played = play(params, schedule, size=SMALL)
    timeline = Timeline(params, 0, *SMALL)
    planted, born = {}, np.zeros(0, np.int64)
    for events in schedule:
        for e in events:
            sim = timeline.sim
            ice = sim.crystal_alive.any() and nearest_slow(sim, np.array([[e["x"], e["y"]]]))[0] < params.hc
            planted[len(sim.crystals)] = (timeline.tick, ice)
            timeline.apply([e])
        timeline.step()
        born = np.append(born, np.full(len(timeline.sim.crystals) - len(born), timeline.tick))
    parents = timeline.sim.parents
    waits = {s: int(born[parents == s].min(initial=timeline.tick)) - t for s, (t, _) in planted.items()}
    on_ice = {s for s, (_, ice) in planted.items() if ice}
    assert len(planted) == 30 and 0 < len(on_ice) < 30
    assert sorted(played.first_growth.tolist()) == sorted(w for s, w in waits.items() if s not in on_ice)
    assert sorted(played.first_growth_on_ice.tolist()) == sorted(waits[s] for s in on_ice)


def test_play_with_drain_applies_every_queued_event_and_counts_the_ticks(monkeypatch):
    # One event a tick (a budget of 0), 8 arriving a tick for 25 ticks: the 200th applies
    # at tick 199 (0-based), 175 ticks after the schedule's last (tick 24).
    monkeypatch.setattr(scribble_module, "Backlog", lambda **kw: Backlog(**kw, budget_s=0.0))
    schedule = [[{"kind": "touch", "x": e["x"], "y": e["y"]} for e in tick]  # (no melts)
                for tick in storm(0, events=200, seconds=1.0, size=SMALL)]
    assert len(schedule) == 25 and sum(map(len, schedule)) == 200
    played = play(Params.preset("fern"), schedule, size=SMALL, drain=True)
    assert len(played.tick_s) == 200 and played.drained == 175 and played.backlog_max == 200 - 25
    cut = play(Params.preset("fern"), schedule, size=SMALL, tail=10)
    # still waiting at its end: a lower bound, the 10 ticks played after the schedule + 1
    assert len(cut.tick_s) == 35 and cut.drained == 11 and cut.backlog_max == 200 - 25


def test_play_applies_a_ticks_melts_as_one_group_as_the_window_does(monkeypatch):
    # One item a tick (a budget of 0) and a drag's 8 melts arriving a tick (12 px apart,
    # radius 12: overlapping): one by one they would queue 175 behind; grouped (at most
    # MELT_GROUP) each tick's 8 apply in that tick.
    monkeypatch.setattr(scribble_module, "Backlog", lambda **kw: Backlog(**kw, budget_s=0.0))
    xs = 20.0 + 12.0 * np.arange(8)
    schedule = [[{"kind": "melt", "x": float(x), "y": 10.0 + 12 * t, "r": 12.0} for x in xs]
                for t in range(25)]
    played = play(Params.preset("fern"), schedule, size=SMALL, drain=True)
    assert backlog.MELT_GROUP >= 8
    assert len(played.tick_s) == 25 and played.drained == 0 and played.backlog_max == 0


# ---- session files: the placement of their version ---------------------------------------


@pytest.mark.parametrize("version, batched, at_once", [(2, False, False), (3, True, False),
                                                       (4, True, True), (5, True, True),
                                                       (6, True, True), (7, True, True)])
@pytest.mark.parametrize("preset", ["fern", "window"])
def test_a_session_file_places_water_as_its_version_did(version, batched, at_once, preset):
    log = SessionLog(0, Params.preset(preset).as_dict(),
                     events=[{"tick": 0, "kind": "touch", "x": 380.0, "y": 640.0}],
                     steps=30, version=version)
    timeline = replay(SessionLog.from_json(log.as_json()))
    rules = timeline.sim.rules
    assert (rules.batched_placement, rules.tries_at_once) == (batched, at_once)
    legacy = FrostSim(Params.preset(preset), seed=0, version=version)
    legacy.touch(380.0, 640.0)
    for _ in range(30):
        legacy.step()
    assert len(legacy.crystals) > 1
    assert (legacy.crystals == timeline.sim.crystals).all()


# ---- the budget's trim, worked by hand -----------------------------------------------------

@pytest.mark.parametrize("need, level", [(5, 5), (6, 5), (7, 4), (8, 4), (9, 4), (100, 4)])
def test_trim_cuts_the_largest_pools_to_one_level_no_lower_than_the_share(need, level):
    # Pools of 10, 6 and 3 walkers, area 2 being topped up (never cut), a fair share of 4.
    # Cutting the others to 5 frees 5 + 1 = 6, to 4 frees 6 + 2 = 8: the highest level
    # that frees `need` (6 frees exactly 6: still 5), never below the share (100: 4).
    counts = np.array([10, 6, 3])
    owner = np.array([0, 1, 2, 0, 0, 1, 0, 2, 0, 0, 1, 0, 1, 0, 0, 2, 1, 0, 1])
    keep = budget.trim(counts, np.array([2]), need, 4, owner)
    kept = [int(keep[owner == a].sum()) for a in range(3)]
    assert kept == [level, level, 3]
    for a in range(3):  # each area keeps its oldest walkers, in array order
        mine = keep[owner == a]
        assert mine[:kept[a]].all() and not mine[kept[a]:].any()
    assert budget.trim(counts, np.array([2]), 0, 4, owner) is None  # nothing needed: no cut


# ---- version 14: water is never lost to the tick's budget (issue 56) -----------------

STORM = Path(__file__).parent / "data" / "storm-2000-taps.json"


def stormed(seed: int, ticks: int, version: int = frost.VERSION) -> FrostSim:
    """The fern look under the 2 000 taps of tests/data/storm-2000-taps.json (each at its
    tick, 760 x 1280 px: a drag across the screen, then taps all over it), to `ticks`."""
    taps: dict[int, list[tuple[float, float]]] = {}
    for e in json.loads(STORM.read_text(encoding="utf-8")):
        taps.setdefault(e["tick"], []).append((e["x"], e["y"]))
    sim = FrostSim(Params.preset("fern"), seed=seed, version=version)
    while sim.tick < ticks:
        for x, y in taps.get(sim.tick, ()):
            sim.touch(x, y)
        sim.step()
    return sim


@pytest.mark.slow
def test_after_a_storm_of_taps_the_frost_grows_alike_whatever_the_seed():
    # Version 13 after this storm: seeds 1 and 9 stopped for good near 5 600 crystals
    # (their one area's launch circle beyond the screen's far corner: every draw missed,
    # the cell work took 400 a tick, the rest were dropped and nothing topped the pool
    # up), seeds 2 and 3 reached about 15 000. Now the seeds' counts at tick 1 600 lie
    # within 20 % of each other, and the frost still grew after the last tap.
    counts = {}
    for seed in (1, 2, 9):  # (frost bench sim --section storm-taps runs seeds 1-10)
        sim = stormed(seed, 1600)
        counts[seed] = int(sim.crystal_alive.sum())
        assert sim.water_dropped < sim.water_created // 2, seed
    assert max(counts.values()) <= 1.2 * min(counts.values()), counts


@pytest.mark.parametrize("seed", [1, 9])
def test_a_storm_session_of_version_13_stops_as_it_did(seed):
    # Older sessions replay as they grew: by version 13's rules these seeds stop.
    sim = stormed(seed, 700, version=13)
    at_700 = int(sim.crystal_alive.sum())
    for _ in range(100):
        sim.step()
    assert int(sim.crystal_alive.sum()) == at_700 and len(sim.water) == 0


def test_a_pool_the_storm_drained_returns_to_humidity_while_glass_remains():
    sim = stormed(1, 420)  # (version 13: 18 walkers left of 3 000 at tick 400)
    pool = len(sim.water) + sim.supply.waiting
    assert pool == sim.params.humidity
    spots = np.random.default_rng(0).uniform((0, 0), (760, 1280), (4000, 2))
    assert (nearest_slow(sim, spots) >= sim.params.hc / 2).any()  # glass remains


def test_walkers_the_cell_work_cuts_are_owed_and_placed_first_next_tick():
    # A fern touch on a 60 px screen: its launch circle (100 px out) lies beyond the
    # screen, so its water is placed from cells, CELL_WORK a tick; the touch's top-up
    # placed 400 and owes the rest of its 3 000 (no ring of water: touch_water 0).
    sim = FrostSim(Params.preset("fern", launch=100.0, touch_water=0), 60, 60, seed=0)
    sim.touch(30.0, 30.0)
    assert frost.CELL_WORK - 10 <= len(sim.water) <= frost.CELL_WORK  # (a few draws miss)
    assert len(sim.water) + sim.supply.waiting == sim.params.humidity
    n, owed, created, dropped = len(sim.water), sim.supply.waiting, sim.water_created, sim.water_dropped
    sim.placer.cell_work = 10
    lost = sim.supply.relocate(np.arange(25), sim.ice_state())
    sim.supply.spent(np.empty(0, np.int64), lost)
    # 10 placed, 15 cut by the cell work: owed, not dropped
    assert len(lost) == 15 and sim.supply.waiting - owed == 15
    assert sim.water_dropped == dropped and sim.water_created == created
    assert len(sim.water) == n - 15
    sim.placer.cell_work = frost.CELL_WORK  # a tick's start: the owed come first
    sim.supply.repay(sim.ice_state())
    assert owed + 15 - sim.supply.waiting >= frost.CELL_WORK - 10
    assert sim.water_created == created and sim.water_dropped == dropped
    sim.step()
    assert len(sim.water) + sim.supply.waiting + sim.water_frozen + sim.water_dropped == sim.water_created


@pytest.mark.parametrize("reach, beyond", [(1473.27, True), (1440.0, False), (1452.5, True),
                                           (1451.5, False)])
def test_a_launch_circle_past_the_far_corner_lies_beyond_the_screen(reach, beyond):
    # An area at (5, 5) on 760 x 1280: its farthest corner is (760, 1280),
    # hypot(755, 1275) = 1481.77 px away; the launch circle lies 30 px past the ice.
    sim = FrostSim(Params.preset("fern"), seed=0)
    assert sim.placer.beyond_screen(5.0, 5.0, reach) is beyond
    old = FrostSim(Params.preset("fern"), seed=0, version=13)
    assert old.placer.beyond_screen(5.0, 5.0, reach) is False


@pytest.mark.parametrize("preset, over", [("fern", {}), ("c-2", {}), ("c-2", {"replenish": True}),
                                          ("window", {})])
def test_every_walker_created_is_walking_owed_frozen_or_dropped(preset, over):
    # Conservation through a storm on a small screen, melts and a preset's replenish
    # included: water created = walkers + owed + frozen + dropped, tick after tick.
    sim = FrostSim(Params.preset(preset, **over), *SMALL, seed=3)
    rng = np.random.default_rng(3)
    for t in range(160):
        for x, y in rng.uniform((0, 0), SMALL, (12 if t < 60 else 0, 2)):
            sim.touch(x, y)
        if t % 25 == 24:
            sim.melt(*rng.uniform((0, 0), SMALL), 30.0)
        sim.step()
        held = len(sim.water) + sim.supply.waiting + sim.water_frozen + sim.water_dropped
        assert held == sim.water_created, (t, held, sim.water_created)


# ---- version 14's budget and bare areas, case by case (issue 56: mutants that survived) ---


def test_owed_walkers_repaid_never_take_the_water_past_its_budget():
    # A 60 px screen, the launch circle beyond it: a touch places CELL_WORK = 400 walkers
    # of its pool (500, the budget) and owes the other 100. Its ring of 48 then finds the
    # pool full, owed walkers counted (version 14), so it moves 48 of the pool's own and
    # brings none: walkers and owed stay within the budget.
    p = Params.preset("fern", launch=100.0, water_budget=500)
    sim = FrostSim(p, 60, 60, seed=0)
    sim.touch(30.0, 30.0)
    walking, owed = len(sim.water), sim.supply.waiting
    assert walking + owed == p.water_budget, (walking, owed)
    # Walkers put there by hand (more than the room left): the repay places only what
    # the budget has room for, and the rest stay owed.
    sim.set_water(np.tile(sim.water[:1], (450, 1)))
    sim.placer.cell_work = frost.CELL_WORK
    sim.supply.repay(sim.ice_state())
    assert len(sim.water) == p.water_budget
    assert sim.supply.waiting == owed - (p.water_budget - 450)
    for _ in range(5):
        sim.step()
        assert len(sim.water) <= p.water_budget


@pytest.mark.parametrize("preset", ["fern", "c-2"])
def test_walkers_and_owed_stay_within_the_water_budget_through_a_storm(preset):
    # Touches all over a small screen with a small budget: a touch's top-up and its ring
    # count the owed walkers, so walkers + owed never pass `water_budget`.
    p = Params.preset(preset, water_budget=900, humidity=600)
    sim = FrostSim(p, *SMALL, seed=5)
    rng = np.random.default_rng(5)
    for t in range(120):
        for x, y in rng.uniform((0, 0), SMALL, (6 if t < 50 else 0, 2)):
            sim.touch(x, y)
            assert len(sim.water) + sim.supply.waiting <= p.water_budget, t
        sim.step()
        assert len(sim.water) + sim.supply.waiting <= p.water_budget, t


def _bare_pool():
    """A fern touch whose pool lost 100 walkers (dropped), and whose area is then marked as
    last seen with no glass (`Placer._bare`, as `_missed` marks it) at the ice now."""
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(380.0, 640.0)
    sim.supply.spent(np.empty(0, np.int64), np.arange(100))
    return sim


def test_a_bare_areas_pool_is_not_topped_up_until_a_melt():
    sim = _bare_pool()
    short = len(sim.water)
    assert short == sim.params.humidity - 100
    # not bare: the tick's end tops the pool up to humidity
    sim.supply.top_up(sim.ice_state())
    assert len(sim.water) == sim.params.humidity
    sim = _bare_pool()
    sim.placer._bare[0] = sim.water_melted  # no glass left, nothing melted since
    work, created = sim.placer.cell_work, sim.water_created
    sim.supply.top_up(sim.ice_state())
    assert len(sim.water) == short and sim.water_created == created
    assert sim.placer.cell_work == work  # nothing tried in vain
    sim.water_melted += 1  # a melt made glass: topped up again
    sim.supply.top_up(sim.ice_state())
    assert len(sim.water) == sim.params.humidity


def test_a_bare_areas_owed_walkers_are_dropped_at_once():
    sim = _bare_pool()
    sim.supply.owed = np.array([40], np.int64)  # 40 walkers owed to the touch's area
    sim.supply.created += 40  # (created when they were cut)
    sim.placer._bare[0] = sim.water_melted
    n, dropped, work = len(sim.water), sim.water_dropped, sim.placer.cell_work
    sim.supply.repay(sim.ice_state())
    assert sim.supply.waiting == 0 and sim.water_dropped == dropped + 40
    assert len(sim.water) == n and sim.placer.cell_work == work  # none placed, none tried


@pytest.mark.parametrize("walkers, bare", [(8, True), (7, False), (9, True)])
def test_an_area_is_bare_after_bare_draws_all_missed(walkers, bare):
    # Each walker drew CELL_TRIES = 8 spots of its glass area: 8 walkers' 64 = BARE_DRAWS
    # draws all missed say the disc has no glass left (not owed: dropped); 7 walkers' 56
    # do not (owed, one entry each).
    assert placement.CELL_TRIES * 8 == placement.BARE_DRAWS
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(380.0, 640.0)
    placer = sim.placer
    placer.take_cut()
    placer._missed(np.array([0]), np.array([True]), np.zeros(walkers, np.int64),
                   np.zeros(walkers, bool), (5, 0))
    assert bool(placer.bare(1, (5, 0))[0]) is bare
    assert len(placer.take_cut()) == (0 if bare else walkers)
    assert not placer.bare(1, (5, 1))[0]  # a melt since: glass again


def test_a_replenished_pool_gets_back_water_it_lost_at_the_ticks_end():
    # Table 1's c-2 with replenish (no growth mode): a kept pool that lost walkers (here
    # 100 dropped) is topped up to humidity by the next tick's end.
    sim = FrostSim(Params.preset("c-2", replenish=True), *SMALL, seed=0)
    sim.touch(120.0, 160.0)
    sim.step()
    sim.supply.spent(np.empty(0, np.int64), np.arange(100))
    assert len(sim.water) + sim.supply.waiting == sim.params.humidity - 100
    sim.step()
    assert len(sim.water) + sim.supply.waiting == sim.params.humidity
