"""frost maps for engines: sizes, the growth-time map, the normal's Y convention, maps.json,
bad values; tiles (periodic search, seams) in tests/test_tiles.py."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from app.cli import main
from sim import Params
from sim.io.timeline import Timeline, grow, touch_events
from sim.look.geometry import GeometryDelta
from sim.look.growthmap import GROWTH_NONE, GROWTH_TOP, NEVER, GrowthClock, encode_growth
from sim.look.maps import compute_maps, live_segments, map_triangles

SIZE = (160, 128)
TICKS = 60


def _ice(timeline: Timeline) -> np.ndarray:
    sim, params = timeline.sim, timeline.params
    maps = compute_maps(timeline.geometry.heights, live_segments(sim), params, *SIZE,
                        triangles=map_triangles(sim, params))
    return maps.height > 0


@pytest.fixture(scope="module")
def run_and_oracle():
    """The clock's ticks after a TICKS run with a melt, and the oracle: the maps computed
    whole after every tick, each pixel's last step from clear to ice."""
    params = Params.preset("fern")
    timeline = Timeline(params, 3, *SIZE)
    clock = GrowthClock(params, *SIZE)
    events = touch_events([(80.0, 64.0)]) + touch_events([(20.0, 110.0)], 25) + [
        {"tick": 40, "kind": "melt", "x": 70.0, "y": 60.0, "r": 25.0}]  # it refreezes after
    first = np.full(SIZE[::-1], -1, np.int64)
    was = np.zeros(SIZE[::-1], bool)

    def tick(sim):  # after every step and every event (a melt shows before the next step)
        nonlocal was
        now = _ice(timeline)
        first[now & ~was] = sim.tick
        first[~now] = -1
        was = now

    def applied(result):
        for delta in result.deltas:
            clock.apply(delta)
        tick(timeline.sim)

    grow(timeline, TICKS, events, on_apply=applied, on_step=clock.apply, on_tick=tick)
    return clock.ticks(was), first, was


def test_growth_ticks_match_a_whole_recomputation_every_tick(run_and_oracle):
    ticks, first, ice = run_and_oracle
    assert ice.mean() > 0.2  # enough ice to say something
    assert (first[ice] > 41).mean() > 0.1  # pixels that melted and froze again
    agree = (ticks[ice] == first[ice]).mean()
    assert agree >= 0.99, agree


def _grown(ticks: int, clock: GrowthClock | None = None) -> Timeline:
    timeline = Timeline(Params.preset("fern"), 5, *SIZE)
    events = touch_events([(60.0, 50.0)]) + touch_events([(130.0, 100.0)], 20)
    grow(timeline, ticks, events, on_step=clock.apply if clock else None)
    return timeline


def test_growth_map_orders_the_growth_against_a_run_stopped_halfway():
    """Of the pixels iced at T/2 (the same seed, stopped there), >= 95 % carry growth
    <= T/2; pixels with no ice at the end carry 65535, the others less."""
    clock = GrowthClock(Params.preset("fern"), *SIZE)
    halfway, full = _ice(_grown(TICKS // 2)), _ice(_grown(TICKS, clock))
    growth = encode_growth(clock.ticks(full), TICKS)
    assert 0.1 < halfway.mean() < 0.9 * full.mean()  # growth still to come
    assert (growth[halfway] <= GROWTH_TOP // 2).mean() >= 0.95
    assert (growth[~full] == GROWTH_NONE).all() and (growth[full] < GROWTH_NONE).all()
    assert (growth[full & ~halfway] > GROWTH_TOP // 2).mean() >= 0.95  # later ice, later


def test_encode_growth_by_hand():
    t = np.array([[0, 5, 10, np.iinfo(np.int32).max]])
    assert encode_growth(t, 10).tolist() == [[0, 32767, 65534, 65535]]
    # tick 1 of 3 is 21 844.67: floored, so growth <= p x 65534 holds at p = 1/3
    assert encode_growth(np.array([1, 2, 3]), 3).tolist() == [21844, 43689, 65534]


def _square(x0: float, y0: float, side: float, z: float = 1.0) -> np.ndarray:
    """Feature vertices of two flat triangles covering a square (x, y, z, normal)."""
    corners = [(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side)]
    rows = [(*corners[i], z, 0.0, 0.0, 1.0) for i in (0, 1, 2, 0, 2, 3)]
    return np.array(rows, np.float32)


def test_a_melt_clears_its_box_and_survivors_keep_their_time():
    """By hand: two squares freeze at ticks 5 and 7; a melt at tick 9 wipes a box over
    both and re-sends only the first: it keeps 5, the second is clear until it refreezes."""
    params = Params.preset("c-2")  # paper look: bumps are ice above 0
    clock = GrowthClock(params, 64, 64)
    shape = clock.grid.shape
    flat = np.zeros((0, shape[1]), np.float32)

    def delta(tick, feats, box=None):
        return GeometryDelta(tick, slice(0, 0), flat, feats, clear_box=box)

    clock.apply(delta(5, _square(10, 10, 8)))
    clock.apply(delta(7, _square(30, 10, 8)))
    clock.apply(delta(9, _square(10, 10, 8), box=(0.0, 0.0, 50.0, 30.0)))
    t = clock.ticks(np.ones((64, 64), bool))
    assert t[14, 14] == 5 and t[14, 34] == NEVER and t[40, 40] == NEVER
    clock.apply(delta(12, _square(30, 10, 8)))
    assert clock.ticks(np.ones((64, 64), bool))[14, 34] == 12


def _maps(tmp_path, name: str, *extra: str) -> dict:
    out = tmp_path / name
    status = main(["maps", str(out), "--preset", "fern", "--touch", "50,40", "--ticks", "30",
                   "--size", "96x80", *extra])
    assert status == 0
    return {p.stem: np.asarray(Image.open(p)) for p in out.glob("*.png")} | {
        "json": json.loads((out / "maps.json").read_text(encoding="utf-8"))}


def test_normal_y_down_flips_the_green_channel(tmp_path):
    up, down = _maps(tmp_path, "up"), _maps(tmp_path, "down", "--normal-y", "down")
    g_up, g_down = up["normal"][..., 1].astype(int), down["normal"][..., 1].astype(int)
    assert (g_up != 128).mean() > 0.05  # slopes to flip
    assert np.abs(g_down - (255 - g_up)).max() <= 1
    assert np.array_equal(up["normal"][..., [0, 2]], down["normal"][..., [0, 2]])
    assert down["json"]["files"]["normal.png"]["normal_y"] == "down"
    assert "DirectX" in down["json"]["files"]["normal.png"]["convention"]
    assert "OpenGL" in up["json"]["files"]["normal.png"]["convention"]
    assert np.array_equal(up["height"], down["height"]) and np.array_equal(up["growth"], down["growth"])


def test_sizes_and_the_sidecar(tmp_path):
    maps = _maps(tmp_path, "m")
    for name in ("height", "alpha", "growth", "preview"):
        assert maps[name].shape[:2] == (80, 96), name
    assert maps["height"].dtype == np.uint16 and maps["growth"].dtype == np.uint16
    info = maps["json"]
    assert info["size"] == [96, 80] and info["ticks"] == 30 and info["seed"] == 0
    assert set(info["files"]) == {"height.png", "normal.png", "alpha.png", "growth.png", "preview.png"}
    top = info["files"]["height.png"]["height_max_px"]
    assert info["files"]["height.png"]["px_per_unit"] == pytest.approx(top / 65535)
    # The preview is the frost over a flat backdrop: ice where the growth map has ice.
    flat = (np.abs(maps["preview"].astype(int) - [70, 76, 86]).sum(axis=-1) == 0)
    assert (flat[maps["growth"] < GROWTH_NONE]).mean() < 0.5
    assert flat[maps["growth"] == GROWTH_NONE].mean() > 0.9


@pytest.mark.parametrize("argv, said", [
    (["--size", "0x5"], "each side must be 64 ... 4096"),
    (["--size", "5000x5000"], "each side must be 64 ... 4096"),
    (["--size", "64"], "must be WxH"),
    (["--size", "64x64", "--touch", "100,10"], "off the 64x64 screen"),
    (["--tile", "--preset", "nope"], "invalid choice"),
    (["--normal-y", "sideways"], "invalid choice"),
])
def test_bad_values_are_one_line_and_status_2(tmp_path, capsys, argv, said):
    with pytest.raises(SystemExit) as stop:
        main(["maps", str(tmp_path / "m"), *argv])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("frost: error: ") and err.count("\n") == 1 and said in err, err
    assert not (tmp_path / "m").exists()


def test_a_touch_in_a_large_maps_pixels_is_taken(tmp_path, capsys):
    assert main(["maps", str(tmp_path / "m"), "--preset", "fern", "--size", "1000x64",
                 "--touch", "900,30", "--ticks", "5"]) == 0
    maps = json.loads((tmp_path / "m" / "maps.json").read_text(encoding="utf-8"))
    assert maps["touches"] == [[0, 900.0, 30.0]]


@pytest.mark.parametrize("wrap", [False, True])
def test_normals_in_bands_are_the_whole_maps(wrap):
    """Over several 256-row bands, the normals equal the obvious whole-map formula:
    central differences (np.gradient, or over the wrap with np.roll), normalized."""
    from sim.look.maps import normal_map

    h = np.random.default_rng(1).random((600, 70)).astype(np.float32) * 5
    g = h.astype(np.float64)
    if wrap:
        d_row = 0.5 * (np.roll(g, -1, 0) - np.roll(g, 1, 0))
        d_col = 0.5 * (np.roll(g, -1, 1) - np.roll(g, 1, 1))
    else:
        d_row, d_col = np.gradient(g)
    n = np.stack((-d_col, d_row, np.ones_like(g)), axis=-1)
    want = (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)
    assert np.array_equal(normal_map(h, wrap=wrap), want)


def test_a_tile_off_the_height_grid_is_refused_in_one_line(tmp_path, capsys):
    """A tile's grid must close on itself: each side a multiple of grid_spacing (4 px)."""
    assert main(["maps", str(tmp_path / "m"), "--tile", "--size", "66x64", "--ticks", "3"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("frost: error: ") and err.count("\n") == 1 and "grid_spacing" in err
    assert not (tmp_path / "m").exists()


def test_the_docs_engine_shader_is_glsl_es_300(tmp_path):
    """The fragment shader docs/engine-maps.md gives engine users compiles as GLSL ES 3.00."""
    import shutil
    import subprocess
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "engine-maps.md").read_text(encoding="utf-8")
    start = page.index("```glsl\n", page.index("## Using the maps in an engine")) + 8
    source = page[start:page.index("```", start)]
    assert "u_growth" in source and "u_progress" in source
    exe = shutil.which("glslangValidator")
    assert exe, "glslangValidator is missing: apt-get install glslang-tools (`make test` does)"
    path = tmp_path / "engine.frag"
    path.write_text("#version 300 es\nprecision highp float;\n" + source, encoding="utf-8")
    run = subprocess.run([exe, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
