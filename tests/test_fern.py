"""Fern growth (docs/method.md, section 6) against independent oracles: geometry recomputed from
the positions, hand-placed walkers, brute-force clearances and off-lattice DLA's dimension."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from support.simoracle import gyration_dimension

from app.bench.morphology import link_angles
from app.cli.parser import build_parser
from app.cli.shared_options import params_from
from sim import PRESETS, FrostSim, Params, preset_name, tuning
from sim.rules.fern import SIXTH, FernGrowth, _first_apart

CENTRE = (380.0, 640.0)
FERN = Params.preset("fern")


def grown(params=FERN, touches=(CENTRE,), ticks=250, seed=1, melt_at=None):
    sim = FrostSim(params, seed=seed)
    for x, y in touches:
        sim.touch(x, y)
    for t in range(ticks):
        if melt_at is not None and t == melt_at[0]:
            sim.melt(*melt_at[1:])
        sim.step()
    return sim


def slot_of_links(sim):
    """(children, parents, slot k, leftover turn) of every live link, from positions alone:
    k is the nearest multiple of 60 degrees between the link and the parent's axis."""
    live, p = sim.crystal_alive, sim.parents
    child = np.flatnonzero(live & (p >= 0))
    c = sim.crystals.astype(np.float64)
    d = c[child] - c[p[child]]
    turn = (np.arctan2(d[:, 1], d[:, 0]) - sim.growth.axis.view()[p[child]]) / SIXTH
    k = np.rint(turn)
    return child, p[child], k.astype(int) % 6, (turn - k) * SIXTH


# ---- parameters ------------------------------------------------------------------------

def test_fern_is_an_extra_preset_and_table_1_is_untouched():
    assert "fern" not in PRESETS and len(PRESETS) == 9
    p = Params.preset("fern", humidity=100)
    assert p.grains and p.long_jumps and p.launch > 0 and p.humidity == 100
    paper = Params()
    assert not paper.grains and not paper.long_jumps and paper.launch == 0
    assert (paper.tip_hits, paper.side_hits, paper.drift) == (1, 1, 0.0)


def test_the_demo_defaults_to_fern_and_one_key_brings_back_the_paper():
    assert params_from(build_parser().parse_args([])) == FERN
    assert params_from(build_parser().parse_args(["--preset", "c-2"])) == Params.preset("c-2")
    assert params_from(build_parser().parse_args(["--hc", "6"])).hc == 6.0
    paper = tuning.preset(FERN.replace(bump=2.0), "c-2")  # key 8 from the fern look
    assert paper == Params.preset("c-2", bump=2.0) and preset_name(paper) == "b-2/c-2"
    back = tuning.preset(Params.preset("c-1", grow=True), "fern")
    assert back == FERN and preset_name(back) == "fern"
    assert tuning.preset(Params.preset("c-1", grow=True), "a-1").grow  # Table 1 keeps G
    assert preset_name(Params.preset("a-3")) == "a-3"
    assert preset_name(FERN.replace(tip_hits=6)) == "custom"


@pytest.mark.parametrize("name,value", [("drift", 3.0), ("tip_hits", 5), ("side_hits", 2),
                                        ("side_gap", 2)])
def test_grain_rules_need_grains(name, value):
    with pytest.raises(ValueError, match=f"{name}={value!r} needs grains=True"):
        Params(**{name: value})


@pytest.mark.parametrize("name,value", [("drift", -1.0), ("tip_hits", 0), ("launch", -5.0),
                                        ("long_jumps", 1), ("side_gap", 0.5)])
def test_bad_fern_values_name_the_parameter(name, value):
    with pytest.raises(ValueError, match=name):
        Params(grains=True, **{name: value})


# ---- rule 1: snapping -------------------------------------------------------------------

@pytest.mark.parametrize("mode", ["candidate", "grid9"])
def test_every_link_is_one_hc_along_an_axis_of_its_parent(mode):
    sim = grown(FERN.replace(neighbor_search=mode), touches=(CENTRE, (200, 300), (20, 20)))
    child, parent, k, rest = slot_of_links(sim)
    assert len(child) > 300
    c = sim.crystals.astype(np.float64)
    length = np.hypot(*(c[child] - c[parent]).T)
    np.testing.assert_allclose(length, sim.params.hc, atol=2e-4)  # float32 positions
    assert np.abs(rest).max() < 1e-4  # on an axis, to float32 rounding of the positions
    # each child's axes = its link's direction + the drift it recorded: small turns
    link = np.arctan2(*(c[child] - c[parent]).T[::-1])
    drift = np.angle(np.exp(1j * (sim.growth.axis.view()[child] - link)))
    assert 0 < np.degrees(np.abs(drift)).max() < 6 * sim.params.drift
    assert abs(np.degrees(drift).std() - sim.params.drift) < 0.5
    # seeds grow on six axes; other crystals straight on or at +-60 degrees only
    seed = sim.parents[parent] < 0
    assert set(k[~seed].tolist()) <= {0, 1, 5} and set(k[seed].tolist()) <= set(range(6))


def test_no_two_crystals_closer_than_half_a_link_and_one_child_per_slot():
    sim = grown(touches=(CENTRE, (400, 660)), ticks=300)
    c = sim.crystals.astype(np.float64)
    d = np.hypot(c[:, None, 0] - c[None, :, 0], c[:, None, 1] - c[None, :, 1])
    np.fill_diagonal(d, np.inf)
    assert d.min() >= sim.params.hc / 2 - 1e-4
    _, parent, k, _ = slot_of_links(sim)
    pairs = parent * 6 + k
    assert len(np.unique(pairs)) == len(pairs)


def test_with_a_launch_circle_each_area_follows_its_own_ice():
    sim = grown(touches=((200, 300), (560, 980)), ticks=500, seed=2)
    area, p = sim.crystal_area, sim.parents
    child = np.flatnonzero(p >= 0)
    assert np.array_equal(area[child], area[p[child]])  # a tree's ice stays in its area
    c = sim.crystals.astype(np.float64)
    for a, (cx, cy, _, _, reach) in enumerate(sim.areas):
        mine = c[area == a]
        assert reach == pytest.approx(np.hypot(mine[:, 0] - cx, mine[:, 1] - cy).max(), abs=1e-3)
        # the other grain's fronds, farther out, do not carry it off
        assert reach < np.hypot(c[:, 0] - cx, c[:, 1] - cy).max() - 100


# ---- rule 2: hit counters ------------------------------------------------------------------

def hand_hits(sim, crystal, angle, n):
    """Replace all water by n walkers 3 px from `crystal` in direction `angle`, one step."""
    c = sim.crystals[crystal].astype(np.float64)
    sim.set_water(np.tile([c[0] + 3 * math.cos(angle), c[1] + 3 * math.sin(angle)], (n, 1)))
    sim.step()


def test_a_slot_grows_exactly_on_its_mth_hit():
    # A tiny step keeps hand-placed walkers where they are; water placed again lands far off.
    params = Params(humidity=1, step=0.01, grains=True, tip_hits=3, side_hits=5)
    sim = FrostSim(params, seed=4)
    sim.touch(*CENTRE)
    phi = float(sim.growth.axis.view()[0])
    for _ in range(2):
        hand_hits(sim, 0, phi + 2 * SIXTH, 1)  # a seed's six slots are all tips
    assert len(sim.crystals) == 1 and len(sim.water) == 1  # hits counted, walker kept
    hand_hits(sim, 0, phi + 2 * SIXTH, 1)
    want = np.array(CENTRE) + 7.0 * np.array([math.cos(phi + 2 * SIXTH), math.sin(phi + 2 * SIXTH)])
    assert len(sim.crystals) == 2 and sim.parents[1] == 0
    np.testing.assert_allclose(sim.crystals[1], want, atol=1e-4)
    a1 = float(sim.growth.axis.view()[1])
    hand_hits(sim, 1, a1 + SIXTH, 4)  # four hits on the child's +60 side slot in one tick
    assert len(sim.crystals) == 2
    for _ in range(3):
        hand_hits(sim, 1, a1 + 2 * SIXTH, 1)  # +120: a closed slot never grows
    hand_hits(sim, 1, a1 + SIXTH, 1)  # the fifth
    assert len(sim.crystals) == 3 and sim.parents[2] == 1
    want = sim.crystals[1].astype(np.float64) + 7.0 * np.array([math.cos(a1 + SIXTH),
                                                                math.sin(a1 + SIXTH)])
    np.testing.assert_allclose(sim.crystals[2], want, atol=1e-4)
    hand_hits(sim, 1, a1, 5)  # straight on needs 3: the third of five grows, once
    assert len(sim.crystals) == 4 and sim.parents[3] == 1
    assert sim.water_frozen == 3


# ---- rule 3: long jumps ------------------------------------------------------------------

def record_jumps(sim, ticks):
    """Per tick: walkers before the walk, their chosen clearance, after the walk, areas,
    and the crystals at the tick's start."""
    log, real_walk, real_radii = [], sim.walk, sim.clearance.radii
    seen = {}

    def radii(*a):
        seen["rho"] = real_radii(*a).copy()
        return seen["rho"]

    def walk():
        before, area = sim.water.astype(np.float64), sim.water_area.copy()
        live = sim.crystals[sim.crystal_alive].astype(np.float64)
        seen.pop("rho", None)
        real_walk()
        log.append((before, area, seen.get("rho"), sim.water.astype(np.float64),
                    sim.areas.astype(np.float64).copy(), live))

    sim.walk, sim.clearance.radii = walk, radii
    for _ in range(ticks):
        sim.step()
    return log


def test_long_jumps_stay_clear_of_ice_inside_the_area_and_below_the_true_clearance():
    sim = FrostSim(FERN.replace(humidity=800, grow=True), seed=2)
    sim.touch(*CENTRE)
    sim.touch(30, 40)  # an area poking off the screen's corner
    jumps = 0
    longest = 0.0
    for before, area, rho, after, areas, ice in record_jumps(sim, 700):
        jumped = np.flatnonzero(rho > sim.params.step)
        p, q, a = before[jumped], after[jumped], areas[area[jumped]]
        d = np.hypot(p[:, None, 0] - ice[None, :, 0], p[:, None, 1] - ice[None, :, 1]).min(axis=1)
        true = np.minimum.reduce([d - sim.params.hc, a[:, 2] - np.hypot(*(p - a[:, :2]).T),
                                  p[:, 0], W - p[:, 0], p[:, 1], H - p[:, 1]])
        assert np.all(rho[jumped] <= true), "a jump longer than the brute-force clearance"
        np.testing.assert_allclose(np.hypot(*(q - p).T), rho[jumped], atol=1e-3)
        land = np.hypot(q[:, None, 0] - ice[None, :, 0], q[:, None, 1] - ice[None, :, 1]).min(axis=1)
        assert np.all(land >= sim.params.hc), "a jump landed within hc of ice"
        assert np.all(np.hypot(*(q - a[:, :2]).T) <= a[:, 2])
        assert np.all((q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H))
        jumps += len(jumped)
        longest = max(longest, float(rho.max()))
    assert jumps > 10_000 and longest > 60
    assert len(sim.crystals) > 400


W, H = 760, 1280


# ---- statistics: jumps keep off-lattice DLA ------------------------------------------------

@pytest.mark.validation
def test_sparse_growth_with_long_jumps_is_off_lattice_dla():
    """Few walkers in flight (20), launched 10 px beyond the ice, jumping far from it:
    the mass-radius dimension of six 3 000-crystal clusters averages DLA's 1.71."""
    params = Params(hc=3.0, step=3.0, D=3.0, humidity=20, replenish=True, long_jumps=True,
                    launch=10.0, active_radius=600.0)
    dims, angles = [], []
    for seed in range(6):
        sim = FrostSim(params, seed=seed)
        sim.touch(*CENTRE)
        while len(sim.crystals) < 3000:
            sim.step()
        dims.append(gyration_dimension(sim.crystals.astype(np.float64)))
        angles.append(link_angles(sim.crystals, sim.parents)[1])
    assert abs(np.mean(dims) - 1.71) <= 0.08, dims
    # No preferred direction: the links' 2-, 4- (the square grid's) and 6-fold orders vanish.
    theta = np.concatenate(angles)
    order = [abs(np.exp(1j * n * theta).mean()) for n in (2, 4, 6)]
    assert max(order) < 0.03, order


# ---- determinism, both searches, melting, growth mode ----------------------------------------

def test_fern_is_deterministic_and_both_searches_agree_through_melts_and_growth_mode():
    runs = [grown(FERN.replace(neighbor_search=mode, grow=True), touches=(CENTRE, (500, 900)),
                  ticks=200, seed=seed, melt_at=(120, 380, 640, 30.0))
            for mode, seed in (("candidate", 6), ("candidate", 6), ("grid9", 6), ("candidate", 7))]
    a = runs[0]
    assert len(a.crystals) > 200
    for other in runs[1:3]:
        for name in ("crystals", "parents", "crystal_alive", "segments", "water"):
            assert getattr(a, name).tobytes() == getattr(other, name).tobytes(), name
        assert a.growth.hits.view().tobytes() == other.growth.hits.view().tobytes()
    assert a.crystals.tobytes() != runs[3].crystals.tobytes()


def test_a_melted_crystal_frees_its_parents_slot_and_takes_its_counters():
    sim = grown(ticks=150, seed=3)
    child, parent, k, _ = slot_of_links(sim)
    c = sim.crystals
    far = child[np.argmax(np.hypot(c[child, 0] - CENTRE[0], c[child, 1] - CENTRE[1]))]
    p = sim.parents[far]
    assert sim.growth.child.view()[p].tolist().count(far) == 1
    melted = sim.melt(*c[far], 0.5)
    assert melted.crystals.tolist() == [far]
    assert far not in sim.growth.child.view()[p]
    assert not sim.growth.hits.view()[far].any() and (sim.growth.child.view()[far] == -1).all()
    slot = int(k[child == far][0])
    assert sim.growth.hits.view()[p, slot] == 0
    for _ in range(150):
        sim.step()
    # regrowth keeps every rule: one live child per slot, no crystals closer than hc / 2
    _, parent, k, rest = slot_of_links(sim)
    pairs = parent * 6 + k
    assert len(np.unique(pairs)) == len(pairs) and np.abs(rest).max() < 1e-4
    live = sim.crystals[sim.crystal_alive].astype(np.float64)
    d = np.hypot(live[:, None, 0] - live[None, :, 0], live[:, None, 1] - live[None, :, 1])
    np.fill_diagonal(d, np.inf)
    assert d.min() >= sim.params.hc / 2 - 1e-4


# ---- what the user sees: the fern sheet -------------------------------------------------------

@pytest.mark.gl
def test_fern_row_shows_the_ice_growing_and_the_sheet_holds_every_cell(gl_ctx):
    from app.tools.figure8 import cell_box, sheet_size
    from app.tools.figure_fern import CELL, compose_grid, grow_row

    row = grow_row(gl_ctx, FERN, 0, [CENTRE], ticks=(0, 40, 120))
    assert [text.split(" (")[0] for text, _ in row] == ["tick 0", "tick 40", "tick 120"]
    frames = [f.astype(int) for _, f in row]
    # more frost each time: the frame drifts further from the bare glass of tick 0
    change = [np.abs(f - frames[0]).mean() for f in frames[1:]]
    assert 0 < change[0] < change[1]
    sheet = compose_grid([row, row], "t", CELL)
    assert sheet.shape == (sheet_size(3, 2, CELL)[1], sheet_size(3, 2, CELL)[0], 3)
    x0, y0, x1, y1 = cell_box(1, 2, CELL)
    assert y1 <= sheet.shape[0] and x1 <= sheet.shape[1] and sheet[y0:y1, x0:x1].std() > 10


def test_figure_names_other_than_fern_are_refused(tmp_path, capsys):
    from app.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["figure", "snow", str(tmp_path / "x.png")])
    assert stop.value.code == 2
    assert "invalid choice: 'snow' (choose from 'fern')" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


# ---- side_gap on a hand-made stem ----------------------------------------------------------

def stem_growth(gap: int) -> tuple[FernGrowth, np.ndarray]:
    """A seed 0 with a stem 0 -> 1 -> 2 -> 3 -> 4 -> 5 (each in its parent's slot 0), a side
    branch 6 in slot 1 of crystal 2, and 7 straight on from 6; returns (rule, parents)."""
    g = FernGrowth(Params.preset("fern", side_gap=gap), np.random.default_rng(0))
    parent = np.array([-1, 0, 1, 2, 3, 4, 2, 6])
    slot = np.array([-1, 0, 0, 0, 0, 0, 1, 0], np.int8)
    g.slot.append(slot)
    g.seed.append(parent < 0)
    g.child.append(np.full((len(parent), 6), -1, np.int32))
    for c, (p, k) in enumerate(zip(parent, slot, strict=True)):
        if p >= 0:
            g.child.raw()[p, k] = c
    return g, parent


def test_side_gap_blocks_a_side_slot_within_gap_minus_one_links_of_a_same_side_branch():
    # gap 3: two links up or down the stem. Crystal 2 holds a side branch in slot 1:
    # 1 (one down), 3 (one up) and 4 (two up) are blocked on that side, 5 (three up) is
    # not; slot 5 (the other side) is clear everywhere; 6, a side branch itself, does not
    # climb back into the stem it grew from (its slot is not 0), so it is clear too.
    g, parent = stem_growth(3)
    crystals = np.array([1, 3, 4, 5, 6])
    assert g.gap_clear(crystals, np.full(5, 1), parent).tolist() == [False, False, False, True,
                                                                    True]
    assert g.gap_clear(crystals, np.full(5, 5), parent).all()
    # gap 2: one link; only the stem's neighbours of crystal 2 are blocked.
    g, parent = stem_growth(2)
    assert g.gap_clear(crystals, np.full(5, 1), parent).tolist() == [False, False, True, True,
                                                                    True]


@given(st.lists(st.tuples(st.integers(0, 12), st.integers(0, 12)), max_size=12),
       st.sampled_from([1.0, 2.5, 3.5]))
def test_spots_too_close_keep_the_earliest_as_a_loop_does(spots, gap):
    """`_first_apart` against the rule written as a loop: in order, a spot is kept unless
    it lies closer than `gap` to a spot kept before it."""
    pts = np.array(spots, np.float32).reshape(-1, 2)
    kept: list[int] = []
    for i, (x, y) in enumerate(spots):
        if all(math.hypot(x - spots[j][0], y - spots[j][1]) >= gap for j in kept):
            kept.append(i)
    assert np.flatnonzero(_first_apart(pts, gap)).tolist() == kept


@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 5), st.integers(-1, 4)), max_size=14),
       st.lists(st.integers(0, 6), min_size=24, max_size=24),
       st.sets(st.tuples(st.integers(0, 3), st.integers(0, 5)), max_size=4))
def test_hits_count_in_walker_order_as_a_loop_counts_them(hits, before, taken):
    """`_count` against the rule as a loop: in walker order, a hit on an open, empty slot
    (need > 0, no child) counts, and the one that brings the slot's count to its need
    (or the first, where an earlier blocked attempt left it at or past the need) is due.
    Slots hit once and slots hit again in one tick."""
    growth = FernGrowth(Params.preset("fern"), np.random.default_rng(0))
    growth.add_seeds(4)
    growth.hits.raw()[:] = np.array(before, np.int32).reshape(4, 6)
    for p, k in taken:
        growth.child.raw()[p, k] = 9
    parents = np.array([h[0] for h in hits], np.int64)
    k = np.array([h[1] for h in hits], np.int64)
    need = np.array([h[2] for h in hits], np.int64)
    start = growth.hits.raw().copy()
    counts, due = start.copy(), []
    for p, s, n in hits:
        open_ = n > 0 and (p, s) not in taken
        due.append(open_ and counts[p, s] - start[p, s] == max(n - start[p, s] - 1, 0))
        counts[p, s] += open_
    assert growth._count(parents, k, need).tolist() == due
    assert growth.hits.raw().tolist() == counts.tolist()
