"""Sharp features (Fig. 6) by hand, and the incremental height grid against an oracle."""

from __future__ import annotations

import numpy as np
import pytest
from oracles import bump_heights, feature_vertices

from sim import FrostSim, Params
from sim.look.geometry import FrostGeometry, falloff, feature_triangles


def test_single_segment_points_by_hand():
    # p=(0,0), q=(4,0): L=4, n=(0,1); m=(2,0) at 0.5*4=2; s1,2 = m -/+ 1.5*4*n.
    xyz, faces = feature_vertices((0.0, 0.0), (4.0, 0.0), width=1.5, height=0.5)
    want = [[0, 0, 0], [4, 0, 0], [2, 0, 2], [2, -6, 0], [2, 6, 0]]
    np.testing.assert_allclose(xyz, want, atol=1e-6)
    # (p, s1, m), (s1, q, m), (q, s2, m), (s2, p, m)
    assert faces.tolist() == [[0, 3, 2], [3, 1, 2], [1, 4, 2], [4, 0, 2]]


def test_single_segment_triangles_and_normals():
    verts = feature_triangles(np.array([[0, 0, 4, 0]], np.float32), 1.5, 0.5)
    assert verts.shape == (12, 6)
    xyz, faces = feature_vertices((0.0, 0.0), (4.0, 0.0))
    np.testing.assert_allclose(verts[:, :3], xyz[faces.ravel()], atol=1e-6)
    # (s1 - p) x (m - p) = (2,-6,0) x (2,0,2) = (-12,-4,12): each face leans away
    # from the ridge, toward its own corner, and faces the viewer (+z).
    s = np.sqrt(304.0)
    want = np.array([[-12, -4, 12], [12, -4, 12], [12, 4, 12], [-12, 4, 12]]) / s
    np.testing.assert_allclose(verts[:, 3:].reshape(4, 3, 3), np.repeat(want[:, None], 3, 1),
                               atol=1e-6)


def test_normals_face_viewer_for_any_direction():
    rng = np.random.default_rng(1)
    segs = rng.uniform(0, 100, (50, 4)).astype(np.float32)
    verts = feature_triangles(segs, 1.5, 0.5)
    assert (verts[:, 5] > 0).all()
    np.testing.assert_allclose(np.linalg.norm(verts[:, 3:], axis=1), 1.0, atol=1e-5)


def test_zero_length_segment_lies_flat():
    verts = feature_triangles(np.array([[5, 5, 5, 5]], np.float32), 1.5, 0.5)
    assert np.isfinite(verts).all()
    np.testing.assert_allclose(verts[:, 3:], [[0, 0, 1]] * 12)


def test_falloff_is_smooth_and_bounded():
    d = np.array([0.0, 3.5, 7.0, 9.0])
    np.testing.assert_allclose(falloff(d, 7.0), [1.0, 0.5625, 0.0, 0.0])


@pytest.mark.parametrize("preset", ["c-2", "a-1"])
def test_height_grid_matches_oracle_after_growth(preset):
    params = Params.preset(preset, active_radius=50.0, humidity=800, max_height=3.0)
    sim = FrostSim(params, 160, 120, seed=3)
    geo = FrostGeometry(params, 160, 120)
    sim.touch(80, 60)
    before = geo.heights.copy()
    features = [geo.update(sim).features]  # the touch alone
    for _ in range(40):
        sim.step()
        delta = geo.update(sim)
        changed = np.flatnonzero((geo.heights != before).any(axis=1))
        assert changed.size == 0 or (delta.rows.start <= changed.min()
                                     and changed.max() < delta.rows.stop)
        np.testing.assert_array_equal(delta.heights, geo.heights[delta.rows])
        before = geo.heights.copy()
        features.append(delta.features)
    pts = np.concatenate((sim.crystals, sim.upsampled))
    assert len(pts) > 20
    oracle = bump_heights(pts, geo.rows, geo.cols, params.grid_spacing, params.hc,
                          params.bump, params.max_height)
    np.testing.assert_allclose(geo.heights, oracle, atol=1e-4)
    all_feats = feature_triangles(sim.segments, params.feature_width, params.feature_height)
    np.testing.assert_allclose(np.concatenate(features), all_feats, atol=1e-5)


def test_grid_shape_and_reset():
    geo = FrostGeometry(Params(), 760, 1280)
    assert geo.heights.shape == (1280 // 4 + 1, 760 // 4 + 1)
    geo.heights[3, 3] = 1.0
    delta = geo.reset()
    assert delta.reset and not geo.heights.any()


def test_melt_takes_the_ice_back_exactly():
    params = Params.preset("a-2", active_radius=50.0, humidity=800, max_height=3.0)
    sim = FrostSim(params, 160, 120, seed=4)
    geo = FrostGeometry(params, 160, 120)
    sim.touch(80, 60)
    for _ in range(40):
        sim.step()
        geo.update(sim)
    x, y = sim.crystals[len(sim.crystals) // 2]
    melted = sim.melt(float(x), float(y), 8.0)
    assert len(melted.crystals) > 0
    delta = geo.melt(sim, melted)
    assert delta.clear_box is not None
    pts = np.concatenate((sim.crystals[sim.crystal_alive], sim.upsampled[sim.upsampled_alive]))
    oracle = bump_heights(pts, geo.rows, geo.cols, params.grid_spacing, params.hc,
                          params.bump, params.max_height)
    np.testing.assert_allclose(geo.heights, oracle, atol=1e-4)
    assert not geo.heights[oracle == 0].any()  # clear glass again, no film of round-off
    # The survivors re-sent are exactly the live segments near the melt.
    live = sim.segments[sim.segments_alive]
    assert len(delta.features) % 12 == 0 and 0 < len(delta.features) <= 12 * len(live)


def test_ice_far_apart_raises_and_melts_back_as_the_oracle_says():
    # Seeds in the top and bottom rows: the raise spans the rows between them, most of
    # the grid, so only the vertices it touches are summed (and capped: a seed's bump of 1
    # is over max_height); a melt over everything takes them all back to clear glass.
    params = Params.preset("a-2", active_radius=50.0, max_height=0.5)
    sim = FrostSim(params, 120, 600, seed=2)
    geo = FrostGeometry(params, 120, 600)
    for x, y in ((60, 40), (30, 300), (90, 560)):
        sim.touch(x, y)
    sim.step()  # (a tick's update raises the seeds planted before it)
    delta = geo.update(sim)
    pts = np.concatenate((sim.crystals, sim.upsampled))
    oracle = bump_heights(pts, geo.rows, geo.cols, params.grid_spacing, params.hc,
                          params.bump, params.max_height)
    assert oracle.max() == 0.5
    np.testing.assert_allclose(geo.heights, oracle, atol=1e-6)
    changed = np.flatnonzero(geo.heights.any(axis=1))
    assert delta.rows.start <= changed.min() and changed.max() < delta.rows.stop
    geo.melt(sim, sim.melt(60.0, 300.0, 400.0))
    assert not sim.crystal_alive.any()
    assert not geo.heights.any()


def test_a_segment_melted_before_its_update_is_never_drawn():
    """A melt between a step and the geometry's update (a replayed session's melt at its
    tick, a page's warm finger) takes out links that tick grew: the update draws the live
    ones only. Oracle: no triangle of the update is a dead segment's; each live new segment
    gives its 12; the heights are the bumps of the live particles."""
    params = Params.preset("c-2", active_radius=50.0, humidity=800, max_height=3.0)
    sim = FrostSim(params, 160, 120, seed=3)
    geo = FrostGeometry(params, 160, 120)
    sim.touch(80, 60)
    for _ in range(6):  # (growing fast: tens of links a step)
        sim.step()
        geo.update(sim)
    new = sim.step().segments
    assert new.stop - new.start >= 2
    x, y = sim.segments[new.start, 2:]  # the child end of the tick's first new link
    geo.melt(sim, sim.melt(float(x), float(y), 3.0))
    dead = ~sim.segments_alive[new]
    assert dead.any() and not dead.all()  # the melt took some of the tick's links, not all
    delta = geo.update(sim)
    assert len(delta.features) == 12 * int((~dead).sum())
    killed = feature_triangles(sim.segments[new][dead], params.feature_width, params.feature_height)
    drawn = {tuple(v) for v in delta.features.round(4).tolist()}
    assert not any(tuple(v) in drawn for v in killed.round(4).tolist())
    pts = np.concatenate((sim.crystals[sim.crystal_alive], sim.upsampled[sim.upsampled_alive]))
    oracle = bump_heights(pts, geo.rows, geo.cols, params.grid_spacing, params.hc,
                          params.bump, params.max_height)
    np.testing.assert_allclose(geo.heights, oracle, atol=1e-4)
