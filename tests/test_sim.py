"""The simulation core against brute-force oracles (docs/method.md; the paper's Sec. 3.3-3.4)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim import FrostSim, Params, upsample, walk_displacements
from sim.index.grid import CELL_MARGIN, HashGrid

W, H = 760, 1280


def grown(params=None, touches=((380.0, 640.0),), ticks=150, seed=3):
    sim = FrostSim(params or Params.preset("c-2"), seed=seed)
    for x, y in touches:
        sim.touch(x, y)
    for _ in range(ticks):
        sim.step()
    return sim


def record_ticks(sim, ticks):
    """Run `ticks` ticks, capturing for each the walkers after the walk, the crystals at
    the tick's start, and which walkers froze to which parents."""
    log = []
    real = sim.crystallize

    def spy(keys=None):
        frozen, parents = real(keys)
        log.append((sim.water.astype(np.float64), sim.crystals.astype(np.float64).copy(),
                    frozen.copy(), parents.copy()))
        return frozen, parents

    sim.crystallize = spy
    for _ in range(ticks):
        sim.step()
    return log


# ---- Eq. 1 -------------------------------------------------------------------------

@pytest.mark.parametrize("hc,cols,rows", [(7.0, 55, 92), (10.0, 38, 64), (3.0, 127, 214),
                                          (6.5, 59, 99)])
def test_grid_size_is_eq1_rounded_up(hc, cols, rows):
    g = HashGrid(W, H, hc)
    assert (g.cols, g.rows) == (math.ceil(W / (2 * hc)), math.ceil(H / (2 * hc))) == (cols, rows)
    assert g.cols * g.cell >= W and g.rows * g.cell >= H


# ---- candidate cells (Sec. 3.4.1) -----------------------------------------------------

def cell_disc_distances(g, cells, pts):
    """Distance from each point to each cell's rectangle (cells x points), the slow way."""
    cy, cx = np.divmod(cells, g.cols)
    x0, y0 = (cx * g.cell)[:, None], (cy * g.cell)[:, None]
    gx = np.maximum(np.maximum(x0 - pts[:, 0], 0.0), pts[:, 0] - (x0 + g.cell))
    gy = np.maximum(np.maximum(y0 - pts[:, 1], 0.0), pts[:, 1] - (y0 + g.cell))
    return np.hypot(gx, gy)


@pytest.mark.parametrize("preset", ["c-2", "b-1", "a-1"])
def test_candidate_cells_match_brute_force(preset):
    sim = grown(Params.preset(preset), touches=((380, 640), (5, 5), (755, 1275)), ticks=200)
    g, hc = sim.grid, sim.params.hc
    crystals = sim.crystals.astype(np.float64)
    assert len(crystals) > 50
    for lo in range(0, g.size, 512):
        cells = np.arange(lo, min(lo + 512, g.size))
        dist = cell_disc_distances(g, cells, crystals)
        for cell, row in zip(cells, dist, strict=True):
            listed = sim.candidates.items[cell, :sim.candidates.count[cell]]
            assert np.all(np.diff(listed) > 0), "lists are ascending, without duplicates"
            must = set(np.flatnonzero(row < hc).tolist())  # the disc truly meets the cell
            may = set(np.flatnonzero(row < hc + CELL_MARGIN).tolist())
            assert must <= set(listed.tolist()) <= may, f"cell {cell}"
    state = sim.candidates.count > 0
    assert state.sum() < g.size  # not everything marked: the update is local


# ---- Eq. 2 ---------------------------------------------------------------------------

def test_walk_steps_uniform_in_length_and_angle():
    dx, dy = walk_displacements(np.random.default_rng(11), 200_000, 3.0)
    a = np.hypot(dx.astype(np.float64), dy.astype(np.float64))
    theta = np.mod(np.arctan2(dy, dx), 2 * np.pi)
    assert a.max() <= 3.0 + 1e-6 and a.min() >= 0
    # Uniform on [0, 3]: mean 1.5, variance 0.75; deciles each hold 10 %.
    assert abs(a.mean() - 1.5) < 0.01 and abs(a.var() - 0.75) < 0.01
    for values, top in ((a, 3.0), (theta, 2 * np.pi)):
        counts = np.histogram(values, bins=10, range=(0, top))[0] / len(values)
        assert np.all(np.abs(counts - 0.1) < 0.005)


def test_walk_moves_each_walker_by_eq2():
    sim = FrostSim(Params(humidity=500), seed=5)
    sim.touch(380, 640)
    before = sim.water.copy()
    rng = np.random.default_rng()
    rng.bit_generator.state = sim.streams.walk.bit_generator.state  # replay the sim's own draws
    u = rng.random((2, len(before)), dtype=np.float32).astype(np.float64)
    a, theta = u[0] * sim.params.step, u[1] * 2 * np.pi  # Eq. 2, worked out in float64
    ex, ey = a * np.cos(theta), a * np.sin(theta)
    sim.walk()
    after = sim.water
    stayed = np.hypot(*(after - before).T) <= sim.params.step + 1e-4  # not respawned
    assert stayed.sum() > 0.9 * len(before)
    np.testing.assert_allclose((after - before)[stayed, 0], ex[stayed], atol=1e-4)
    np.testing.assert_allclose((after - before)[stayed, 1], ey[stayed], atol=1e-4)


# ---- crystallization (Sec. 3.4.3) ------------------------------------------------------

@pytest.mark.parametrize("preset", ["c-2", "a-1"])
def test_crystallization_matches_brute_force_every_tick(preset, deep):
    sim = FrostSim(Params.preset(preset), seed=7)
    sim.touch(380, 640)
    sim.touch(200, 300)
    hc = sim.params.hc
    # (every walker against every crystal each tick: 160 ticks of c-2 took 25 s)
    log = record_ticks(sim, 160 if deep else 60)
    froze_total = 0
    for water, crystals, frozen, parents in log:
        if len(water) == 0:
            continue
        d = np.hypot(water[:, None, 0] - crystals[None, :, 0], water[:, None, 1] - crystals[None, :, 1])
        dmin = d.min(axis=1)
        stays = np.ones(len(water), bool)
        stays[frozen] = False
        assert np.all(dmin[stays] >= hc - 1e-3), "a walker within hc stayed water"
        assert np.all(dmin[frozen] < hc + 1e-3)
        # linked to the nearest crystal that existed at the tick's start
        assert np.all(parents < len(crystals))
        np.testing.assert_allclose(d[frozen, parents], dmin[frozen], atol=1e-4)
        froze_total += len(frozen)
    assert froze_total > 100
    assert froze_total == len(sim.crystals) - 2


def assert_forest(sim, n_seeds):
    parents = sim.parents
    idx = np.arange(len(parents))
    roots = np.flatnonzero(parents == -1)
    assert len(roots) == n_seeds
    # every link points to an older crystal, so following parents always ends at a root
    assert np.all(parents[parents >= 0] < idx[parents >= 0])


def test_skeleton_is_a_forest_with_one_root_per_seed():
    touches = [(380, 640), (390, 650), (100, 100), (700, 1200)]
    sim = grown(touches=touches, ticks=200)
    assert_forest(sim, len(touches))
    # each crystal's new position is within hc of its parent
    p = sim.parents
    child = np.flatnonzero(p >= 0)
    gap = np.hypot(*(sim.crystals[child] - sim.crystals[p[child]]).T)
    assert np.all(gap < sim.params.hc + 1e-3)


# ---- upsampling (Eq. 3-4) -------------------------------------------------------------

def test_upsample_hand_worked():
    p = np.array([[0.0, 0.0], [10.0, 10.0], [0.0, 0.0]], np.float32)
    q = np.array([[9.5, 0.0], [10.0, 13.0], [4.0, 3.0]], np.float32)
    pts, link, segs, seg_link = upsample(p, q, 3.0)
    # link 0: L = 9.5, Nu = 3 -> 2 points at 1/3 and 2/3; link 1: L = 3, Nu = 1 -> none;
    # link 2: L = 5, Nu = 1 -> none.
    np.testing.assert_allclose(pts, [[9.5 / 3, 0], [19.0 / 3, 0]], atol=1e-5)
    assert link.tolist() == [0, 0]
    assert seg_link.tolist() == [0, 0, 0, 1, 2]
    np.testing.assert_allclose(segs[:3], [[0, 0, 9.5 / 3, 0], [9.5 / 3, 0, 19 / 3, 0],
                                          [19 / 3, 0, 9.5, 0]], atol=1e-5)
    np.testing.assert_array_equal(segs[3], [10, 10, 10, 13])


@pytest.mark.parametrize("D", [0.7, 1.0, 2.5, 9.0, 20.0])
def test_upsample_counts_and_even_spacing(D):
    rng = np.random.default_rng(2)
    p = rng.uniform(0, 100, (300, 2)).astype(np.float32)
    q = (p + rng.uniform(-10, 10, (300, 2))).astype(np.float32)
    pts, link, segs, seg_link = upsample(p, q, D)
    for i in range(len(p)):
        L = float(np.hypot(*(q[i].astype(np.float64) - p[i])))
        nu = math.floor(L / D)
        want = nu - 1 if nu >= 2 else 0
        mine = pts[link == i]
        assert len(mine) == want
        chain = segs[seg_link == i]
        assert len(chain) == max(want + 1, 1)
        np.testing.assert_allclose(chain[0, :2], p[i], atol=1e-5)
        np.testing.assert_allclose(chain[-1, 2:], q[i], atol=1e-5)
        np.testing.assert_allclose(chain[1:, :2], chain[:-1, 2:], atol=1e-6)  # a chain
        np.testing.assert_allclose(np.hypot(*(chain[:, 2:] - chain[:, :2]).T), L / max(nu, 1) if want else L,
                                   rtol=1e-4, atol=1e-4)


def upsample_slow(p, q, D):
    """Eq. 3-4 link by link in Python floats (float64), stored float32."""
    pts, link, segs, seg_link = [], [], [], []
    for i, (a, b) in enumerate(zip(p.astype(np.float64), q.astype(np.float64), strict=True)):
        d = b - a
        nu = math.floor(math.hypot(d[0], d[1]) / D)
        k = nu if nu >= 2 else 1
        nodes = [(a[0] + (j / k) * d[0], a[1] + (j / k) * d[1]) for j in range(k + 1)]
        pts += nodes[1:-1]
        link += [i] * (k - 1)
        segs += [nodes[j] + nodes[j + 1] for j in range(k)]
        seg_link += [i] * k
    return (np.array(pts, np.float32).reshape(-1, 2), np.array(link, np.int64),
            np.array(segs, np.float32).reshape(-1, 4), np.array(seg_link, np.int64))


@pytest.mark.parametrize("length", [7.0, 2.4, 12.6, None])
def test_upsample_matches_a_link_by_link_loop_bit_for_bit(length):
    """Links all of one length (a fern's are one hc: one grid of nodes) or of any."""
    rng = np.random.default_rng(5)
    p = rng.uniform(0, 700, (40, 2)).astype(np.float32)
    turn = rng.uniform(0, 2 * np.pi, 40)
    size = rng.uniform(0.5, 20, 40) if length is None else length
    q = (p + np.column_stack((size * np.cos(turn), size * np.sin(turn)))).astype(np.float32)
    for mine, slow in zip(upsample(p, q, 2.5), upsample_slow(p, q, 2.5), strict=True):
        np.testing.assert_array_equal(mine, slow)
        assert mine.shape == slow.shape


def test_sim_upsamples_links_and_upsampled_make_no_freezing_area():
    sim = grown(Params.preset("a-1"), ticks=150)  # D = 1, hc = 10: many upsample points
    assert len(sim.upsampled) > 3 * len(sim.crystals)
    listed = set(sim.candidates.items[sim.candidates.count > 0].ravel().tolist()) - {-1}
    assert listed <= set(range(len(sim.crystals)))
    p = sim.parents
    n_links = int((p >= 0).sum())
    assert len(np.unique(sim.segments_link)) == n_links


# ---- neighbour search: grid9 baseline ---------------------------------------------------

@pytest.mark.parametrize("preset,touches", [
    ("c-2", [(380, 640)]),
    ("b-1", [(380, 640), (390, 600)]),
    ("a-1", [(0, 0), (759.5, 1279.5), (380, 640)]),
])
def test_grid9_gives_bit_identical_frost(preset, touches):
    runs = [grown(Params.preset(preset, neighbor_search=mode), touches=touches, ticks=220)
            for mode in ("candidate", "grid9")]
    a, b = runs
    assert len(a.crystals) > 20
    for name in ("crystals", "parents", "upsampled", "segments", "water"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


# ---- water: respawn, spending, replenish --------------------------------------------------

def test_respawned_water_is_inside_its_area_and_outside_candidate_cells():
    sim = FrostSim(Params.preset("c-2", active_radius=60), seed=4)
    sim.touch(30, 30)   # the area pokes off the screen
    sim.touch(60, 40)
    placed = []
    real = sim.placer.place

    def spy(area, ice):
        x, y, ok = real(area, ice)
        px, py, c = x[ok], y[ok], sim.areas[area[ok]]
        assert np.all(np.hypot(px - c[:, 0], py - c[:, 1]) <= c[:, 2] + 1e-3)
        assert np.all((px >= 0) & (px < W) & (py >= 0) & (py < H))
        assert np.all(sim.candidates.count[sim.grid.keys(px, py)] == 0)
        placed.append(len(px))
        return x, y, ok

    sim.placer.place = spy
    for _ in range(100):
        sim.step()
    assert sum(placed) > 100
    assert sim.water_created > 0


def test_water_is_spent_and_replenish_keeps_the_pool():
    spent = grown(Params.preset("c-2"), ticks=60)
    assert len(spent.water) + spent.water_frozen + spent.water_dropped == spent.water_created
    assert spent.water_frozen == len(spent.crystals) - 1
    full = grown(Params.preset("c-2", replenish=True), ticks=60)
    assert full.water_frozen > 0
    assert len(full.water) == 3000 - full.water_dropped


def test_filled_active_area_gives_up_placement_without_hanging():
    sim = FrostSim(Params(hc=7.0, humidity=4000, active_radius=25.0), seed=1)
    sim.touch(380, 640)
    for _ in range(400):
        sim.step()
    # The disc of radius 25 is covered by candidate cells: water can no longer be placed.
    assert len(sim.water) == 0
    assert sim.water_dropped > 0
    x, y, ok = sim.place(np.zeros(100, np.int32))
    assert not ok.any()


# ---- touches, edges, determinism --------------------------------------------------------

@pytest.mark.parametrize("x,y", [(-1, 5), (760, 5), (5, 1280), (5, -0.01), (math.nan, 3),
                                 (3, math.inf)])
def test_touch_off_screen_is_a_value_error(x, y):
    sim = FrostSim()
    with pytest.raises(ValueError, match="off the 760x1280 screen"):
        sim.touch(x, y)
    assert len(sim.crystals) == 0


def test_seeds_at_corners_edges_and_many_overlapping():
    touches = [(0, 0), (759.99, 0), (0, 1279.99), (759.99, 1279.99), (380, 0), (0, 640)]
    touches += [(380 + 5 * i, 640 + 3 * i) for i in range(20)]
    sim = grown(Params.preset("c-1"), touches=touches, ticks=120)
    c = sim.crystals
    assert np.all((c[:, 0] >= 0) & (c[:, 0] < W) & (c[:, 1] >= 0) & (c[:, 1] < H))
    assert_forest(sim, len(touches))
    assert len(c) > len(touches)


def test_same_seed_same_touches_same_frost_bit_for_bit():
    def run(seed):
        sim = FrostSim(Params.preset("c-3"), seed=seed)
        sim.touch(380, 640)
        for t in range(150):
            if t == 40:
                sim.touch(200, 500)
            sim.step()
        return sim
    a, b, c = run(9), run(9), run(10)
    for name in ("crystals", "parents", "upsampled", "segments", "water"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes()
    assert a.crystals.tobytes() != c.crystals.tobytes()


def test_added_slices_cover_exactly_the_new_particles():
    sim = FrostSim(Params.preset("a-2"), seed=2)
    sim.touch(380, 640)
    seen_c = seen_u = seen_s = 0
    for _ in range(120):
        added = sim.step()
        assert added.crystals.start == seen_c and added.upsampled.start == seen_u
        assert added.segments.start == seen_s
        seen_c, seen_u, seen_s = added.crystals.stop, added.upsampled.stop, added.segments.stop
    assert (seen_c, seen_u, seen_s) == (len(sim.crystals), len(sim.upsampled), len(sim.segments))


def test_output_arrays_are_contiguous_float32_and_read_only():
    sim = grown(ticks=80)
    for name in ("crystals", "upsampled", "segments", "water"):
        arr = getattr(sim, name)
        assert arr.dtype == np.float32 and arr.flags.c_contiguous
    assert sim.parents.dtype == np.int32
    with pytest.raises(ValueError):
        sim.crystals[0, 0] = 1.0


# ---- growth mode (beyond the paper) -------------------------------------------------------

def test_growth_mode_frosts_the_whole_screen_from_one_touch():
    sim = FrostSim(Params.preset("c-2", grow=True), seed=2)
    sim.touch(380, 640)
    for _ in range(700):
        sim.step()
    marked = sim.candidates.count.reshape(sim.grid.rows, sim.grid.cols) > 0
    assert marked.mean() > 0.97
    assert marked[0, 0] and marked[-1, -1] and marked[0, -1] and marked[-1, 0]
    assert_forest(sim, 1)
    # the area's annulus rides on the farthest ice: reach is the true farthest distance
    cx, cy, outer, inner, reach = sim.areas[0]
    far = np.hypot(*(sim.crystals - [cx, cy]).T).max()
    assert reach == pytest.approx(far, abs=1e-3)
    assert outer == pytest.approx(max(200.0, far + 100.0), abs=1e-2)
    assert inner == pytest.approx(max(0.0, far - 100.0), abs=1e-2)


def test_growth_mode_places_water_on_the_annulus_near_the_ice():
    sim = FrostSim(Params.preset("c-2", grow=True), seed=3)
    sim.touch(380, 640)
    for _ in range(120):
        sim.step()
    cx, cy, outer, inner, _ = sim.areas[0]
    assert inner > 0
    x, y, ok = sim.place(np.zeros(2000, np.int32))
    r = np.hypot(x[ok] - cx, y[ok] - cy)
    assert ok.sum() > 500
    assert r.min() >= inner - 1e-3 and r.max() <= outer + 1e-3
    assert len(sim.water) == 3000 - sim.water_dropped


# ---- melting (beyond the paper) -------------------------------------------------------

def check_candidate_cells(sim):
    """The candidate-cell oracle over live crystals only."""
    g, hc = sim.grid, sim.params.hc
    live = np.flatnonzero(sim.crystal_alive)
    pts = sim.crystals[live].astype(np.float64)
    dist = cell_disc_distances(g, np.arange(g.size), pts)
    for cell in range(g.size):
        listed = set(sim.candidates.items[cell, :sim.candidates.count[cell]].tolist())
        must = set(live[dist[cell] < hc].tolist())
        may = set(live[dist[cell] < hc + CELL_MARGIN].tolist())
        assert must <= listed <= may, f"cell {cell}"


@pytest.mark.parametrize("mode", ["candidate", "grid9"])
def test_melting_clears_the_patch_keeps_a_forest_and_regrows(mode):
    sim = grown(Params.preset("a-2", neighbor_search=mode), ticks=250, seed=5)
    before = int(sim.crystal_alive.sum())
    m = sim.melt(380, 640, 40.0)
    live = sim.crystal_alive
    c = sim.crystals.astype(np.float64)
    # exactly the crystals within the radius melted (brute force over all of them)
    near = np.flatnonzero(np.hypot(c[:, 0] - 380, c[:, 1] - 640) < 40.0)
    assert set(m.crystals.tolist()) == set(near.tolist()) and len(near) > 5
    assert not live[near].any() and live.sum() == before - len(near)
    check_candidate_cells(sim)
    # the skeleton stays a forest: live links point at live, older crystals
    p = sim.parents
    linked = np.flatnonzero(live & (p >= 0))
    assert np.all(live[p[linked]]) and np.all(p[linked] < linked)
    assert np.all(p[m.orphans] == -1) and len(m.orphans) > 0
    # no live segment or upsample particle belongs to a cut link
    cut = set(m.crystals.tolist()) | set(m.orphans.tolist())
    assert not set(sim.segments_link[sim.segments_alive].tolist()) & cut
    assert not set(sim.upsampled_link[sim.upsampled_alive].tolist()) & cut
    assert sim.water_melted == len(near)
    # frost regrows into the cleared patch from its edges
    for _ in range(150):
        sim.step()
    c = sim.crystals
    back = sim.crystal_alive & (np.hypot(c[:, 0] - 380, c[:, 1] - 640) < 40.0)
    assert back.sum() > 0
    check_candidate_cells(sim)


def test_melt_is_identical_in_both_neighbour_searches_and_rejects_bad_input():
    runs = []
    for mode in ("candidate", "grid9"):
        sim = grown(Params.preset("c-3", neighbor_search=mode), ticks=60, seed=8)
        sim.melt(380, 640, 30.0)
        for _ in range(60):
            sim.step()
        runs.append(sim)
    assert runs[0].crystals.tobytes() == runs[1].crystals.tobytes()
    assert runs[0].crystal_alive.tobytes() == runs[1].crystal_alive.tobytes()
    with pytest.raises(ValueError, match="radius"):
        runs[0].melt(10, 10, -1.0)
    with pytest.raises(ValueError, match="radius"):
        runs[0].melt(math.nan, 10, 5.0)
    alive = runs[0].crystal_alive.tobytes()
    for discs in ([(380, 640, 0.0)], [(380, 640, 30.0), (100, 100, 0.0)]):  # a radius of 0 melts nothing
        with pytest.raises(ValueError, match="radius 0.0: need finite values, radius > 0"):
            runs[0].melt_many(discs)
        assert runs[0].crystal_alive.tobytes() == alive  # refused whole: the ice as it was


def test_set_water_replaces_every_walker_and_refuses_an_area_that_does_not_exist():
    sim = FrostSim(Params.preset("c-2"), seed=0)
    sim.touch(380.0, 640.0)
    sim.touch(100.0, 200.0)  # outside the first area: a second one
    sim.set_water([(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)], [1, 0, 1])
    assert sim.water.tolist() == [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]
    assert sim.water_area.tolist() == [1, 0, 1]
    sim.set_water(np.zeros((0, 2)))
    assert len(sim.water) == 0 and len(sim.water_area) == 0
    with pytest.raises(ValueError, match="area 2 does not exist"):
        sim.set_water([(1.0, 2.0)], 2)


def test_one_melt_of_several_discs_takes_the_ice_in_any_of_them():
    sim = FrostSim(Params.preset("fern"), seed=2)
    sim.touch(380.0, 640.0)
    for _ in range(120):
        sim.step()
    discs = [(600.0, 100.0, 30.0), (370.0, 630.0, 15.0), (395.0, 640.0, 15.0)]  # one on glass
    c = sim.crystals.astype(np.float64)
    alive, parents = sim.crystal_alive.copy(), sim.parents.copy()
    inside = np.zeros(len(c), bool)
    for x, y, r in discs:  # brute force over every crystal
        inside |= np.hypot(c[:, 0] - x, c[:, 1] - y) < r
    melted = sim.melt_many(discs)
    expected_dead = np.flatnonzero(inside & alive)
    assert len(expected_dead) > 10 and np.array_equal(np.sort(melted.crystals), expected_dead)
    assert not sim.crystal_alive[expected_dead].any()
    orphans = np.flatnonzero(alive & ~inside & np.isin(parents, expected_dead))
    assert len(orphans) > 0 and np.array_equal(np.sort(melted.orphans), orphans)
    assert (sim.parents[orphans] == -1).all()
    kept = alive & ~inside & ~np.isin(np.arange(len(c)), orphans)
    assert np.array_equal(sim.parents[kept], parents[kept])


@given(st.lists(st.integers(0, 4), max_size=30), st.lists(st.integers(0, 6), max_size=8))
def test_a_links_rows_are_found_as_a_scan_finds_them(counts, crystals):
    """`rows` (binary search over each row's crystal, which ascends) against a scan: the
    rows of each given crystal's link in turn, ascending; crystals with no rows (seeds,
    or past the last) give none."""
    from sim.core.skeleton import rows
    link = np.repeat(np.arange(len(counts)), counts).astype(np.int32)
    want = [i for c in crystals for i in range(len(link)) if link[i] == c]
    assert rows(link, np.array(crystals, np.int64)).tolist() == want
