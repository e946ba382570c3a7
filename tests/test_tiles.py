"""Tiles (frost maps --tile): the periodic neighbour search against brute force across the
edges, and seams in the maps and the 2x2 preview."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from app.cli import main
from sim import FrostSim, Params

TILE = (96, 80)


def _brute_nearest(crystals: np.ndarray, x: np.ndarray, y: np.ndarray, hc: float, size):
    """Each walker's nearest crystal over the wrap (the nine images, float64), and whether
    it lies within hc: the obvious version."""
    best = np.full(len(x), np.inf)
    parent = np.full(len(x), -1)
    for i, (cx, cy) in enumerate(crystals.astype(np.float64)):
        for sx in (-size[0], 0, size[0]):
            for sy in (-size[1], 0, size[1]):
                d2 = (cx + sx - x) ** 2 + (cy + sy - y) ** 2
                closer = d2 < best
                best[closer], parent[closer] = d2[closer], i
    return best, parent, best < hc * hc


def _tile_sim(search: str, seed: int, hc: float = 7.0, **more) -> FrostSim:
    params = Params.preset("c-2", neighbor_search=search, hc=hc, step=min(hc, 5.0), **more)
    sim = FrostSim(params, *TILE, seed=seed, wrap=True)
    rng = np.random.default_rng(seed)
    # Seeds hugging the edges and corners, and a few inside.
    edge = np.array([[0.5, 40.0], [95.3, 12.0], [48.0, 0.2], [30.0, 79.6], [0.1, 0.1],
                     [95.9, 79.9], [2.0, 77.0]])
    sim.plant(np.vstack((edge, rng.uniform([0, 0], TILE, (6, 2)))), water=False)
    return sim


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("hc", [7.0, 9.0])  # 9: the last column and row are cells narrower than hc
def test_periodic_nearest_crystal_matches_brute_force(seed, hc):
    sim = _tile_sim("candidate", seed, hc)
    rng = np.random.default_rng(100 + seed)
    n = 4000
    near_edge = rng.uniform(-6, 6, (n // 2, 2)) % np.array(TILE, np.float64)
    x, y = (np.vstack((near_edge, rng.uniform([0, 0], TILE, (n // 2, 2)))).astype(np.float32).T)
    walkers, parents = sim.search.nearest(sim.crystals, x, y)
    best, parent, within = _brute_nearest(sim.crystals, x, y, sim.params.hc, TILE)
    sure = np.abs(best - sim.params.hc ** 2) > 1e-3  # float32 rounding decides the rest
    hit = np.zeros(n, bool)
    hit[walkers] = True
    assert np.array_equal(hit[sure], within[sure])
    across = within & ((x < 7) | (x > TILE[0] - 7) | (y < 7) | (y > TILE[1] - 7))
    assert across.sum() > 100  # the edges are what this is about
    assert np.array_equal(parents, parent[walkers])
    d2 = sim.index.nearest_d2(np.column_stack((x, y)))
    assert np.allclose(d2[within], best[within], atol=1e-3)


def _steps(img: np.ndarray, axis: int) -> np.ndarray:
    """Mean |step| between each line (along `axis`) and the next, the last one's step
    being the one across the wrap-around edge to the first."""
    a = np.moveaxis(img.astype(np.float64), axis, 0)
    return np.abs(np.diff(np.concatenate((a, a[:1])), axis=0)).reshape(len(a), -1).mean(axis=1)


def _seam_ok(steps: np.ndarray, at: int) -> tuple[bool, tuple]:
    """The step across the seam after line `at - 1` is no larger than a typical step inside:
    1.25 x the larger of the median step and the mean of the two steps on each side of
    it (a ridge may run along the seam, where the steps beside it are large too). Maps
    grown without wrapping fail it by 2-10x (measured on a 160x128 window frost)."""
    seam = steps[at - 1]
    beside = steps[[at - 3, at - 2, at % len(steps), (at + 1) % len(steps)]].mean()
    typical = max(float(np.median(steps)), float(beside))
    return bool(seam <= 1.25 * typical), (seam, beside, np.median(steps))


@pytest.fixture(scope="module")
def tiled(tmp_path_factory):
    out = tmp_path_factory.mktemp("tile") / "maps"
    assert main(["maps", str(out), "--preset", "window", "--size", "160x128", "--tile",
                 "--ticks", "250", "--seed", "4"]) == 0
    return {p.name: np.asarray(Image.open(p)) for p in out.glob("*.png")} | {
        "json": json.loads((out / "maps.json").read_text(encoding="utf-8"))}


@pytest.mark.parametrize("name", ["height.png", "normal.png", "alpha.png", "growth.png"])
def test_maps_have_no_seam(tiled, name):
    """Across the wrap-around edge the step is like a step inside, in both directions."""
    img = tiled[name]
    assert (img != img.flat[0]).mean() > 0.2  # frost, not a flat map
    for axis in (0, 1):
        ok, said = _seam_ok(_steps(img, axis), img.shape[axis])
        assert ok, (axis, said)


def test_the_2x2_preview_shows_no_seam(tiled):
    four, one = tiled["preview-2x2.png"], tiled["preview.png"]
    assert four.shape == (2 * one.shape[0], 2 * one.shape[1], 3)
    assert np.array_equal(four[:one.shape[0], :one.shape[1]], one)
    grey = four.astype(np.float64).mean(axis=-1)
    for axis in (0, 1):
        ok, said = _seam_ok(_steps(grey, axis), one.shape[axis])
        assert ok, (axis, said)


def test_an_unwrapped_frost_fails_the_seam_measure(tmp_path):
    """The measure's control: the same frost grown without --tile has seams."""
    out = tmp_path / "flat"
    assert main(["maps", str(out), "--preset", "window", "--size", "160x128", "--ticks",
                 "250", "--seed", "4"]) == 0
    for name in ("height.png", "alpha.png", "growth.png"):
        img = np.asarray(Image.open(out / name))
        assert not any(_seam_ok(_steps(img, axis), img.shape[axis])[0] for axis in (0, 1)), name


def test_a_window_tile_has_no_frame(tiled):
    info = tiled["json"]
    assert info["tiling"] == "both directions"
    assert info["parameters"]["frame_sites"] == 0 and info["parameters"]["frame_chill"] == 0
    # The frame's nuclei became pane sites: 4 + 3 per 100 px of the border.
    assert info["parameters"]["pane_sites"] == 4 + round(3 * 2 * (160 + 128) / 100)


def test_links_cross_the_edges_short():
    """On a tile a crystal grows from ice across the edge: its link runs to the parent's
    image beside it (as short as any link), never across the whole tile."""
    params = Params.preset("fern")
    sim = FrostSim(params, *TILE, seed=2, wrap=True)
    sim.plant([(1.0, 40.0), (48.0, 79.0)])
    for _ in range(80):
        sim.step()
    seg = sim.segments.astype(np.float64)
    length = np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1])
    assert length.max() <= params.hc + params.step
    xs, ys = seg[:, [0, 2]], seg[:, [1, 3]]
    off = (xs < 0) | (xs >= TILE[0]) | (ys < 0) | (ys >= TILE[1])
    assert off.any(axis=1).sum() >= 3  # links that cross an edge
    c = sim.crystals
    assert ((c >= 0) & (c < np.array(TILE, np.float32))).all()  # crystals stay on the tile
    w = sim.water
    assert ((w >= 0) & (w < np.array(TILE, np.float32))).all()


def _crossing_triangle(size) -> np.ndarray:
    """A flat triangle (x, y, z, normal rows) reaching 6 px past the right edge."""
    w = size[0]
    rows = [(w - 6.0, 10.0, 2.0), (w + 6.0, 10.0, 2.0), (w, 22.0, 2.0)]
    return np.array([(*r, 0.0, 0.0, 1.0) for r in rows], np.float32)


def test_a_ridge_crossing_an_edge_is_drawn_on_both_sides_of_the_maps():
    """By hand: a triangle from x = W - 6 to W + 6 raises pixels at both edges of the map."""
    from sim.look.maps import triangle_field

    tri = _crossing_triangle(TILE)
    wrapped = triangle_field(tri, *TILE, wrap=True)
    flat = triangle_field(tri, *TILE)
    assert wrapped[11, TILE[0] - 3] == 2.0 and wrapped[11, 2] == 2.0
    assert flat[11, TILE[0] - 3] == 2.0 and flat[11, 2] == 0.0
    assert wrapped[:, 8:TILE[0] - 8].max() == 0.0  # nothing in between
    aa = triangle_field(tri, *TILE, edge_aa=True, wrap=True)  # the glass look's edges
    assert aa[11, 2] == 2.0 and aa[11, TILE[0] - 3] == 2.0


def test_the_geometry_sends_a_copy_across_the_edge_for_the_renderer():
    from sim.look.geometry import FrostGeometry

    geometry = FrostGeometry(Params.preset("fern"), *TILE, wrap=True)
    tri = _crossing_triangle(TILE)
    sent = geometry._delta(1, slice(0, 0), tri).features
    assert len(sent) == 6
    assert np.allclose(sent[3:, 0], tri[:, 0] - TILE[0]) and np.allclose(sent[3:, 1:], tri[:, 1:])


def test_grid9_is_refused_on_a_tile(tmp_path, capsys):
    """Its 3 x 3 cells would miss ice across an edge whose last cell is narrow."""
    with pytest.raises(ValueError, match="grid9"):
        _tile_sim("grid9", 0)
    assert main(["maps", str(tmp_path / "m"), "--tile", "--size", "96x80",
                 "--neighbor-search", "grid9", "--ticks", "3"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("frost: error: ") and err.count("\n") == 1
    assert not (tmp_path / "m").exists()


def test_a_tiles_height_grid_wraps_against_the_obvious_sum():
    """Each vertex holds bump x falloff of every particle within hc over the wrap (the
    obvious double loop), capped; the last row and column repeat the first."""
    from sim.look.geometry import FrostGeometry, falloff

    params = Params.preset("fern")
    geometry = FrostGeometry(params, *TILE, wrap=True)
    rng = np.random.default_rng(7)
    pts = np.vstack((rng.uniform([0, 0], TILE, (40, 2)),
                     [[0.5, 0.5], [95.5, 3.0], [10.0, 79.5]])).astype(np.float32)
    geometry._raise(pts[:30])
    geometry._raise(pts[30:])
    gs = params.grid_spacing
    want = np.zeros_like(geometry.heights, np.float64)
    for r in range(geometry.rows):
        for c in range(geometry.cols):
            dx = (c * gs - pts[:, 0] + TILE[0] / 2) % TILE[0] - TILE[0] / 2
            dy = (r * gs - pts[:, 1] + TILE[1] / 2) % TILE[1] - TILE[1] / 2
            want[r, c] = (params.bump * falloff(np.hypot(dx, dy), params.hc)).sum()
    assert np.allclose(geometry.heights, np.minimum(want, params.max_height), atol=1e-5)
    assert (want[0] > 0).any() and (want[:, 0] > 0).any()


def test_a_window_tiles_sites_and_water_follow_its_size():
    """By hand, 2048 x 2048 (4.31 x the phone's 760 x 1280): 4 + 3 x 81.92 sites; the pool
    4 000 x 4.31; the budget 10 000 x 4.31, capped at 30 000; a value given is kept."""
    from app.tools.maps import tile_window

    p = tile_window(Params.preset("window"), (2048, 2048))
    area = 2048 * 2048 / (760 * 1280)
    assert (p.frame_sites, p.frame_chill) == (0.0, 0.0)
    assert p.pane_sites == 4 + round(3 * 4 * 2048 / 100)
    assert p.humidity == round(4000 * area) and p.water_budget == 30_000
    kept = tile_window(Params.preset("window", humidity=500), (2048, 2048), {"humidity"})
    assert kept.humidity == 500 and kept.water_budget == 30_000


def test_walkers_leaving_an_edge_come_in_at_the_opposite_one():
    """One walk of a window tile's pool against Eq. 2 done by hand with the same random
    draws, each position taken modulo the size: none is re-placed, some cross an edge."""
    import copy

    from sim.core.frost import walk_displacements
    from sim.index.periodic import wrap_into

    sim = FrostSim(Params.preset("window", frame_sites=0.0), *TILE, seed=3, wrap=True)
    x0, y0 = sim.water[:, 0], sim.water[:, 1]
    rng = copy.deepcopy(sim.streams.walk)
    dx, dy = walk_displacements(rng, len(x0), sim.params.step, sim.jumps(x0, y0))
    sim.walk()
    assert np.array_equal(sim.water[:, 0], wrap_into(x0 + dx, TILE[0]))
    assert np.array_equal(sim.water[:, 1], wrap_into(y0 + dy, TILE[1]))
    crossed = (x0 + dx < 0) | (x0 + dx >= TILE[0]) | (y0 + dy < 0) | (y0 + dy >= TILE[1])
    assert crossed.sum() >= 5


@pytest.mark.parametrize("hc", [7.0, 9.0])
def test_long_jumps_on_a_tile_never_reach_ice_across_an_edge(hc):
    """The clearance of every point (how far a walker may jump) is at most its distance
    over the wrap to the nearest freezing disc (brute force over the nine images), and
    points far from ice near an edge still jump (a tile has no edge to stop at)."""
    sims = [_tile_sim("candidate", 5, hc, long_jumps=True)]
    for seed in range(6):  # a few seeds anywhere: far jumps toward ice across an edge
        rng = np.random.default_rng(seed)
        sims.append(FrostSim(Params.preset("c-2", hc=hc, long_jumps=True), *TILE, seed=seed,
                             wrap=True))
        sims[-1].plant(rng.uniform([0, 0], TILE, (rng.integers(1, 5), 2)), water=False)
    for sim in sims:
        pts = np.random.default_rng(9).uniform([0, 0], TILE, (3000, 2)).astype(np.float32)
        rho = sim.clearance.radii(pts[:, 0], pts[:, 1], np.full(len(pts), np.float32(1e9)))
        best, _, _ = _brute_nearest(sim.crystals, pts[:, 0], pts[:, 1], hc, TILE)
        room = np.maximum(np.sqrt(best) - hc, 0.0)  # inside a disc: no jump
        assert (rho <= room + 1e-3).all(), float((rho - room).max())
    # Far from ice, a point by an edge jumps as far as one inside (no edge to stop at).
    lone = FrostSim(Params.preset("c-2", hc=hc, long_jumps=True), 160, 128, seed=1, wrap=True)
    lone.plant([(80.0, 64.0)], water=False)
    x = np.float32([0.5, 159.5, 30.0, 130.0])
    y = np.float32([64.0, 64.0, 64.0, 64.0])
    rho = lone.clearance.radii(x, y, np.full(4, np.float32(1e9)))
    assert (rho[:2] > 2 * lone.params.step).all()  # an edge that capped them would give 0.5 px
