"""The frond rules (docs/method.md, section 8; sim/rules/fronds.py, sim/rules/openglass.py) and the pane's
measures (app/bench/measures.py), against stored pre-change hashes, hand-worked cases and
brute-force oracles."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from app.bench.measures import (
    END_GAIN,
    END_TICKS,
    MAIN_PX,
    clear_boxes,
    frame_mid,
    frosted_end,
    skeleton_measures,
    stems,
)
from sim import FrostSim, Params
from sim.params import FROND_RULES
from sim.rules.fern import SIDE, SLOT_KIND
from sim.rules.fronds import FRAME_PX, Fronds
from sim.rules.openglass import OpenGlass, ring_distance
from tests import frozen_runs

WINDOW = Params.preset("window")
# The window preset without the frond rules, as an old session file holds it: no frond keys.
OLD_WINDOW = {"tip_hits": 3, "side_hits": 6, "humidity": 3000, "water_budget": 6000,
              **{k: getattr(Params, k) for k in FROND_RULES}}
W, H = 300, 400  # a small pane: a few hundred ticks frost it


def side_spacing(crystals, parents, alive) -> float:
    """Median over main stems (MAIN_PX or more) with side stems of their length per side
    stem leaving them, px: how far apart side branches are (nan if none)."""
    head, length, _, parent_stem, link = stems(crystals, parents, alive)
    n = len(crystals)
    L = np.bincount(head[link], weights=length[link], minlength=n)
    ids = np.flatnonzero(L > 0)
    kid = ids[parent_stem[ids] >= 0]
    k_n = np.bincount(parent_stem[kid], minlength=n)
    fed = ids[(L[ids] >= MAIN_PX) & (k_n[ids] > 0)]
    return float(np.median(L[fed] / k_n[fed])) if len(fed) else float("nan")


# ---- the looks that must not change ----------------------------------------------------------

def test_params_table1_fern_and_the_old_window_grow_bit_identical_frost():
    """The unprefixed set: Table 1, fern and the window without and with its frond rules."""
    stored = json.loads((Path(__file__).parent / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.hashes(OLD_WINDOW) == {k: v for k, v in stored.items() if "/" not in k}


def test_version_6_grows_the_frost_stored_for_it():
    """The "v5/" set: every preset, the paper's modes, a replant, a wrap tile, a scribble."""
    stored = json.loads((Path(__file__).parent / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.hashes_v5() == {k: v for k, v in stored.items() if k.startswith("v5/")}


def test_the_frond_rules_are_off_by_default_and_on_in_window_only():
    for name in ("fern", "c-2", "a-1"):
        p = Params.preset(name)
        assert all(getattr(p, k) == getattr(Params, k) for k in FROND_RULES)
    assert all(getattr(WINDOW, k) != getattr(Params, k) for k in FROND_RULES if k != "near_water")


def test_an_old_window_session_replays_the_old_window():
    from sim.io.session import FORMAT, SessionLog
    old = {k: v for k, v in Params.preset("window", **OLD_WINDOW).as_dict().items()
           if k not in FROND_RULES}
    log = SessionLog.from_json({"format": FORMAT, "seed": 3, "params": old, "events": [],
                                "steps": 10})
    assert Params(**log.params) == Params.preset("window", **OLD_WINDOW)


@pytest.mark.parametrize("changes, named", [
    ({"order_hits": 2.0}, "grains"), ({"max_order": 2}, "grains"),
    ({"water_far": 2}, "window_frost"), ({"frame_chill": 1.0}, "window_frost"),
    ({"grains": True, "window_frost": True, "vapour_var": 1.0}, "water_far"),
    ({"grains": True, "window_frost": True, "water_far": 9}, "water_far"),
    ({"grains": True, "order_hits": 0.5}, "order_hits"),
])
def test_frond_parameters_are_validated(changes, named):
    with pytest.raises(ValueError, match=named):
        Params(**changes)


# ---- rule 1: branch order ---------------------------------------------------------------------

def order_oracle(sim):
    """Each crystal's branch order walked down from its root: +1 per link that leaves a
    non-seed parent through a side slot (the growth rule's slot record and seed flags)."""
    g = sim.growth
    slot, seed, parents = g.slot.view(), g.seed.view(), sim.parents
    out = np.zeros(len(parents), np.int64)
    for i in range(len(parents)):  # a parent's index is below its child's
        p = parents[i]
        if p >= 0:
            out[i] = out[p] + int(SLOT_KIND[slot[i]] == SIDE and not seed[p])
    return out


def test_order_rises_only_on_side_branches_and_resets_at_a_melts_edge_which_keeps_its_slots():
    sim = FrostSim(WINDOW.replace(frame_chill=0.0), W, H, seed=4)
    for _ in range(250):
        sim.step()
    order = sim.growth.order.view().astype(np.int64)
    assert (order == order_oracle(sim)).all()
    assert order.max() >= 2  # side branches of side branches grew
    before, seeds = order.copy(), sim.growth.seed.view().copy()
    sim.melt(150.0, 200.0, 30.0)
    c = sim.crystals.astype(np.float64)
    edge = sim.crystal_alive & (np.hypot(c[:, 0] - 150, c[:, 1] - 200) < 30 + sim.ice.longest_link + 1)
    assert edge.sum() > 3 and (before[edge] > 0).any()
    after = sim.growth.order.view()
    assert (after[edge] == 0).all() and (after[~edge] == before[~edge]).all()
    assert (sim.growth.seed.view() == seeds).all()  # (without the fronds: six open slots)


def test_a_slot_needs_hits_times_order_hits_to_the_order_and_max_order_closes_side_slots():
    f = Fronds(Params(grains=True, order_hits=3.0, max_order=2))
    order = np.array([0, 1, 2, 1, 2, 0])
    side = np.array([False, True, True, False, False, True])
    need = np.array([1, 3, 3, 1, 1, -1])
    at = np.full((6, 2), 380.0)
    assert f.need((760, 1280), order, side, need, at).tolist() == [1, 9, -1, 3, 9, -1]


def test_the_frame_divides_the_hits():
    f = Fronds(Params(grains=True, window_frost=True, frame_chill=3.0))
    at = np.array([[0.0, 640.0], [150.0, 640.0], [380.0, 640.0]])
    got = f.need((760, 1280), np.zeros(3, int), np.zeros(3, bool), np.full(3, 12), at)
    hand = [round(12 / (1 + 3 * math.exp(-d / FRAME_PX))) for d in (0.0, 150.0, 380.0)]
    assert got.tolist() == hand == [3, 6, 10]


def test_order_hits_make_side_branches_rarer():
    """The same pane with and without the order factor: side stems per crystal fall."""
    def side_share(params):
        sim = FrostSim(params, W, H, seed=5)
        for _ in range(300):
            sim.step()
        return (sim.growth.order.view() > 0).mean()
    assert side_share(WINDOW) < side_share(WINDOW.replace(order_hits=1.0, max_order=0))


# ---- rules 2 and 3: water on open glass, humidity field ------------------------------------

def brute_rings(sim):
    """Each cell's Chebyshev distance in cells to the nearest candidate cell, by brute force."""
    g = sim.grid
    cand = np.flatnonzero(sim.candidates.count > 0)
    cy, cx = np.divmod(np.arange(g.size), g.cols)
    qy, qx = np.divmod(cand, g.cols)
    return np.maximum(np.abs(cx[:, None] - qx), np.abs(cy[:, None] - qy)).min(axis=1)


def test_ring_distance_matches_brute_force():
    rng = np.random.default_rng(0)
    for density in (0.01, 0.05, 0.3):
        mask = rng.random(12 * 17) < density
        mask[5] = True
        cy, cx = np.divmod(np.arange(mask.size), 17)
        qy, qx = np.divmod(np.flatnonzero(mask), 17)
        brute = np.maximum(np.abs(cx[:, None] - qx), np.abs(cy[:, None] - qy)).min(axis=1)
        assert (ring_distance(mask, 12, 17, 3) == np.minimum(brute, 3)).all()


def test_water_lands_on_open_glass_not_beside_the_ice():
    params = WINDOW.replace(frame_chill=0.0, near_water=0.0)
    sim = FrostSim(params, 400, 600, seed=2)
    for _ in range(40):
        sim.step()
    assert isinstance(sim.pane, OpenGlass)
    rings = brute_rings(sim)
    assert (rings >= params.water_far).any() and (rings < params.water_far).any()
    x, y, ok = sim.pane.place(2000)
    cell = sim.grid.keys(x[ok], y[ok])
    assert ok.all() and (rings[cell] >= params.water_far).all()


def test_nearer_glass_gets_near_water_of_a_far_cells_share():
    params = WINDOW.replace(frame_chill=0.0, vapour_var=0.0)
    sim = FrostSim(params, 400, 600, seed=2)
    for _ in range(40):
        sim.step()
    rings = brute_rings(sim)
    x, y, ok = sim.pane.place(40_000)
    r = rings[sim.grid.keys(x[ok], y[ok])]
    n_far, n_near = (rings >= 2).sum(), (rings == 1).sum()
    expect = params.near_water * n_near / (params.near_water * n_near + n_far)
    assert (r == 0).sum() == 0
    assert abs((r == 1).mean() - expect) < 0.02


def test_a_melts_clearing_gets_water_at_once():
    """Candidate cells (ring 0 by brute force) get water only while wet: the cells whose
    crystals melted, until they hold a crystal again."""
    sim = FrostSim(WINDOW.replace(frame_chill=0.0), W, H, seed=3)
    for _ in range(400):
        sim.step()
    rings = brute_rings(sim)
    x, y, ok = sim.pane.place(4000)
    assert (rings[sim.grid.keys(x[ok], y[ok])] == 0).sum() == 0
    sim.melt(150.0, 200.0, 25.0)
    rings = brute_rings(sim)
    x, y, ok = sim.pane.place(4000)
    inside = np.hypot(x[ok] - 150.0, y[ok] - 200.0) < 25.0
    assert (rings[sim.grid.keys(x[ok][inside], y[ok][inside])] == 0).sum() > 10


def test_the_humidity_field_weights_where_far_water_lands():
    sim = FrostSim(WINDOW.replace(frame_chill=0.0, near_water=0.0, vapour_var=2.0), W, H, seed=6)
    v = sim.pane.vapour
    assert abs(np.log(v).var() - 2.0) < 0.1 and v.max() / v.min() > 10
    rings = brute_rings(sim)
    x, y, ok = sim.pane.place(50_000)
    counts = np.bincount(sim.grid.keys(x[ok], y[ok]), minlength=sim.grid.size)
    g = sim.grid
    cy, cx = np.divmod(np.arange(g.size), g.cols)
    whole = ((cx + 1) * g.cell <= W) & ((cy + 1) * g.cell <= H)  # (no part off the screen)
    far = (rings >= 2) & whole
    expect = ok.sum() * v[far] / v[rings >= 2].sum()
    big = expect > 50
    assert big.sum() > 20
    # every well-filled far cell within 5 sigma of its share (cells lose a few spots near
    # ice to the hc / 2 glass test, so a one-sided allowance of 10 % below)
    assert (counts[far][big] > 0.9 * expect[big] - 5 * np.sqrt(expect[big])).all()
    assert (counts[far][big] < expect[big] + 5 * np.sqrt(expect[big])).all()


# ---- rule 4 and the temperature -----------------------------------------------------------------

def test_the_frame_band_is_denser_with_the_chill():
    def ratio(chill):
        sim = FrostSim(WINDOW.replace(frame_chill=chill), 600, 800, seed=1)
        for _ in range(600):
            sim.step()
        nodes = np.vstack((sim.crystals[sim.crystal_alive], sim.upsampled[sim.upsampled_alive]))
        return frame_mid(nodes.astype(np.float64), 600, 800)
    assert ratio(3.0) > 1.1 * ratio(0.0)


def grown_to(params, share, seed=0, limit=3000):
    sim = FrostSim(params, seed=seed)  # the whole screen (a small pane's pool floods it)
    held = np.zeros(sim.grid.size, bool)
    while sim.tick < limit and held.mean() < share:
        new = sim.step().crystals
        c = sim.crystals[new]
        held[sim.grid.keys(c[:, 0], c[:, 1])] = True
    return sim


@pytest.mark.validation  # a statistical comparison of looks, seconds: `make test-deep`
def test_colder_is_faster_and_its_side_branches_closer():
    """-20, -10, -4 C to 40 % of the cells: fewer ticks on every seed, and side branches
    closer together along the main stems (at the same coverage) on the mean of three
    seeds: one seed's -10 and -4 C can come within a px of each other."""
    gaps = []
    for seed in (0, 1, 2):
        sims = [grown_to(WINDOW.replace(temperature=c), 0.4, seed) for c in (20.0, 10.0, 4.0)]
        t = [s.tick for s in sims]
        assert t[0] < t[1] < t[2] < 3000, (seed, t)
        gaps.append([side_spacing(s.crystals, s.parents, s.crystal_alive) for s in sims])
    gap = np.mean(gaps, axis=0)
    assert gap[0] < gap[1] < gap[2], gaps


# ---- the measures -----------------------------------------------------------------------------

def test_stem_measures_of_a_hand_built_feather():
    """A stem of 10 links of 10 px along x from a seed, two side branches of 2 links of
    10 px at 60 degrees from its 3rd and 6th crystals, one side branch of that (1 link).
    Stems: main 100 px, sides 20 and 20 px, one side-of-side of 10 px."""
    pts = [(0.0, 0.0)] + [(10.0 * k, 0.0) for k in range(1, 11)]
    parents = [-1] + list(range(10))
    a = math.radians(60)
    for start in (3, 6):
        base = len(pts)
        x0 = 10.0 * start
        pts += [(x0 + 10 * math.cos(a), 10 * math.sin(a)), (x0 + 20 * math.cos(a), 20 * math.sin(a))]
        parents += [start, base]
    pts.append((pts[-2][0] + 10 * math.cos(2 * a), pts[-2][1] + 10 * math.sin(2 * a)))
    parents.append(len(pts) - 3)  # from the first crystal of the second side branch
    m = skeleton_measures(np.array(pts, np.float32), np.array(parents), np.ones(len(pts), bool))
    lengths, orders = np.array([100, 20, 20, 10]), np.array([0, 1, 1, 2])
    assert m["stem_lw"] == pytest.approx((lengths ** 2).sum() / lengths.sum(), rel=1e-5)
    assert m["main_frac"] == pytest.approx(100 / 150, rel=1e-5)
    assert m["pinnate"] == pytest.approx(100 / 20, rel=1e-5)
    assert m["order"] == pytest.approx((lengths * orders).sum() / 150, rel=1e-5)
    spacing = side_spacing(np.array(pts, np.float32), np.array(parents), np.ones(len(pts), bool))
    assert spacing == pytest.approx(100 / 2, rel=1e-5)  # the one main stem, two sides


def test_clear_boxes_and_frame_mid_by_hand():
    nodes = np.array([[1.0, 1.0], [30.0, 1.0], [50.0, 30.0], [50.0, 50.0]])  # the last: off
    assert clear_boxes(nodes, 63, 42, box=21) == pytest.approx(1 - 3 / 6)
    # 760 x 1280: frame area 760*1280 - 560*1080, middle 360*880
    frame = np.array([[10.0, 500.0]] * 4)
    mid = np.array([[380.0, 640.0]] * 2)
    want = (4 / (760 * 1280 - 560 * 1080)) / (2 / (360 * 880))
    assert frame_mid(np.vstack((frame, mid)), 760, 1280) == pytest.approx(want)


def test_the_frosted_end_is_the_first_slow_stretch():
    cover = np.minimum(np.arange(2000) * 0.001, 0.6)  # 0.25 per 250 ticks, flat from 600
    end = frosted_end(cover)
    slow = [t for t in range(END_TICKS + 1, 2001)
            if cover[t - 1] - cover[t - 1 - END_TICKS] < END_GAIN]
    assert end == slow[0]
    assert frosted_end(np.arange(2000) * 0.001) is None


def test_only_the_straightest_child_continues_a_stem():
    """seed -> a -> b straight on, and a -> c turning 20 degrees (under 30, but not the
    straightest): stems seed-a-b (20 px) and a-c (10 px)."""
    c = math.radians(20)
    pts = np.array([(0, 0), (10, 0), (20, 0), (10 + 10 * math.cos(c), 10 * math.sin(c))],
                   np.float32)
    m = skeleton_measures(pts, np.array([-1, 0, 1, 1]), np.ones(4, bool))
    assert m["stem_lw"] == pytest.approx((20 ** 2 + 10 ** 2) / 30, rel=1e-5)
    assert m["order"] == pytest.approx(10 / 30, rel=1e-5)


def tree_of(sim, root):
    """The live crystals descending from `root`, walked down the parent links."""
    mine = np.zeros(len(sim.parents), bool)
    mine[root] = True
    for i in range(root + 1, len(sim.parents)):  # a parent's index is below its child's
        p = sim.parents[i]
        mine[i] = p >= 0 and mine[p]
    return mine & sim.crystal_alive


@pytest.mark.validation  # a statistical comparison of looks, seconds: `make test-deep`
def test_a_touch_in_window_mode_grows_a_frond():
    """A touch on open glass, then 400 ticks: its tree's stems, against the same touch on
    the window without the frond rules (off), are longer and more of its ice lies
    on main stems; medians of three seeds (one tree is a small sample: a single seed's
    main_frac ranged 0.23-0.58 with the rules on, 0-0.25 off)."""
    def grown(params, seed):
        sim = FrostSim(params, seed=seed)
        for _ in range(150):
            sim.step()
        root = len(sim.crystals)
        sim.touch(380.0, 640.0)
        for _ in range(400):
            sim.step()
        mine = tree_of(sim, root)
        return {**skeleton_measures(sim.crystals, sim.parents, mine), "n": mine.sum()}

    def medians(params):
        runs = [grown(params, seed) for seed in (5, 6, 7)]
        return {k: float(np.median([r[k] for r in runs])) for k in runs[0]}
    fronds = medians(WINDOW)
    before = medians(Params.preset("window", **OLD_WINDOW))
    assert fronds["n"] > 30
    assert fronds["stem_lw"] > before["stem_lw"], (fronds, before)
    assert fronds["main_frac"] > before["main_frac"], (fronds, before)


def test_version_7_grows_the_frost_stored_for_it():
    """The runs of the v5 set by version 7's rules, each part drawing from its own stream."""
    stored = json.loads((Path(__file__).parent / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.hashes_v7() == {k: v for k, v in stored.items() if k.startswith("v7/")}


def test_version_8_grows_the_frost_stored_for_it():
    """The runs of the v5 set by version 8's rules: a touch opening an area rings its seed."""
    stored = json.loads((Path(__file__).parent / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.hashes_v8() == {k: v for k, v in stored.items() if k.startswith("v8/")}


def test_version_9_grows_the_frost_stored_for_it():
    """One spot tapped past the cells' cap (version 9's own run), and the looks people grow
    (fern, the window, a scribble), which fill no cell, as version 8 grew them."""
    stored = json.loads((Path(__file__).parent / "data" / "frozen_runs.json").read_text(encoding="utf-8"))
    assert frozen_runs.hashes_v9() == {k: v for k, v in stored.items() if k.startswith("v9/")}
    for name, preset, overrides, ticks in frozen_runs.RUNS_V5:
        if name in ("fern", "window"):
            sim = frozen_runs.run(preset, overrides, ticks, version=9)
            assert frozen_runs.state_hash(sim) == stored[f"v8/{name}"]
    assert frozen_runs.state_hash(frozen_runs.scribble(version=9)) == stored["v8/scribble"]


def test_version_8_leaves_the_windows_touches_as_version_7_grew_them():
    # The window's pane is one area: every touch joins it and was ringed already, so
    # version 8 (which rings a touch opening an area) grows the very same frost.
    def grown(version: int) -> str:
        sim = FrostSim(Params.preset("window"), seed=4, version=version)
        for k in range(60):
            if k % 6 == 0:
                sim.touch(100.0 + 9.0 * k, 300.0 + 11.0 * k)
            sim.step()
        return frozen_runs.state_hash(sim)

    assert grown(8) == grown(7)
