"""The Fig. 8 sheet of Table 1's presets, and the height / normal / alpha maps."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from oracles import feature_vertices
from PIL import Image

from app.cli import main
from app.images import export_maps, frost_meta
from app.tools.figure8 import (
    CELL,
    COLS,
    LABEL_H,
    ROWS,
    cell_box,
    format_table,
    label,
    label_box,
    make_figure8,
    sheet_size,
)
from app.tools.maps import grow
from sim import PRESETS, Params
from sim.look.geometry import feature_triangles
from sim.look.maps import (
    alpha_map,
    bump_field,
    compute_maps,
    encode,
    live_segments,
    normal_map,
    triangle_field,
)

ROOT = Path(__file__).resolve().parent.parent
TOUCH = (380.0, 640.0)

# ---- normals: hand-computed ----------------------------------------------------------


def test_flat_glass_has_the_flat_normal():
    n = normal_map(np.zeros((6, 5)))
    assert np.array_equal(n, np.broadcast_to([0.0, 0.0, 1.0], (6, 5, 3)))
    images, _ = encode(compute_maps(np.zeros((3, 3), np.float32), np.empty((0, 4)), Params(), 5, 6))
    assert (images["normal"] == [128, 128, 255]).all()  # (0.5, 0.5, 1) * 255, rounded


def test_ramp_rising_right_tilts_the_normal_left():
    h = 0.5 * np.arange(7.0)[None, :].repeat(4, axis=0)  # dh/dx = 0.5
    n = normal_map(h)
    k = 1 / np.sqrt(1.25)
    assert np.allclose(n, [-0.5 * k, 0.0, k], atol=1e-6)
    rgb = np.round((n * 0.5 + 0.5) * 255)
    assert (rgb == [70, 128, 242]).all()  # (-0.447, 0, 0.894) * 0.5 + 0.5 -> 70.5, 127.5, 241.5


def test_ramp_rising_down_the_image_tilts_the_normal_up():
    h = 2.0 * np.arange(5.0)[:, None].repeat(3, axis=1)  # rows go down: dh/drow = 2
    n = normal_map(h)
    # y is up in the normal map (OpenGL convention): a slope rising downward faces up.
    assert np.allclose(n, [0.0, 2 / np.sqrt(5), 1 / np.sqrt(5)], atol=1e-6)
    assert np.allclose(normal_map(h, strength=0.5), [0.0, 1 / np.sqrt(2), 1 / np.sqrt(2)], atol=1e-6)


def test_alpha_is_zero_on_glass_and_follows_the_thickness_law():
    a = alpha_map(np.array([0.0, 1.0, 100.0]))
    assert a[0] == 0 and 0 < a[1] < a[2] <= 0.88 + 1e-6


# ---- heights ---------------------------------------------------------------------------


def test_bump_field_is_bilinear_at_pixel_centres():
    spacing = 4
    grid = np.tile(np.arange(11, dtype=np.float32) * spacing, (6, 1))  # height = x px
    z = bump_field(grid, spacing, 40, 20)
    assert np.allclose(z, np.arange(40) + 0.5, atol=1e-5)  # pixel centres are at x + 0.5


def _triangle_oracle(seg, width, height, w, h):
    """Slow, obvious: every pixel centre against the four triangles of Fig. 6, highest wins."""
    xyz, faces = feature_vertices(seg[:2], seg[2:], width, height)
    out = np.zeros((h, w))
    for y, x in itertools.product(range(h), range(w)):
        p = np.array([x + 0.5, y + 0.5])
        for f in faces:
            a, b, c = xyz[f]
            m = np.array([b[:2] - a[:2], c[:2] - a[:2]]).T
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            u, v = np.linalg.solve(m, p - a[:2])
            if u >= 0 and v >= 0 and u + v <= 1:
                out[y, x] = max(out[y, x], a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]))
    return out


@pytest.mark.parametrize("seg", [(10.2, 12.7, 18.9, 15.1), (20.0, 8.0, 13.5, 21.0), (5.0, 5.0, 5.0, 5.0)])
def test_feature_pyramids_match_the_triangles(seg):
    seg = np.array(seg)
    z = triangle_field(feature_triangles(seg[None], 1.5, 0.5), 32, 30)
    assert np.allclose(z, _triangle_oracle(seg, 1.5, 0.5, 32, 30), atol=1e-4)


# ---- exported maps -------------------------------------------------------------------


@pytest.fixture(scope="module")
def grown():
    params = Params.preset("c-2")
    sim, geometry = grow(params, 0, [(0, *TOUCH)], 40)
    return params, sim, geometry


def test_export_maps_sizes_modes_and_values(grown, tmp_path):
    params, sim, geometry = grown
    paths = export_maps(tmp_path, geometry.heights, sim.segments, params,
                        frost_meta("a test", params, 0, 40, [(0, *TOUCH)]))
    images = {name: Image.open(p) for name, p in paths.items()}
    assert {n: (im.mode, im.size) for n, im in images.items()} == {
        "height": ("I;16", (760, 1280)), "normal": ("RGB", (760, 1280)), "alpha": ("L", (760, 1280))}
    for name, im in images.items():
        assert im.text["map"] == name and json.loads(im.text["parameters"])["hc"] == params.hc
    height, normal, alpha = (np.asarray(images[n]) for n in ("height", "normal", "alpha"))
    far = (slice(0, 200), slice(0, 200))  # top-left corner, 500+ px from the touch
    assert (height[far] == 0).all() and (alpha[far] == 0).all()
    assert (normal[far] == [128, 128, 255]).all()
    near = (slice(630, 651), slice(370, 391))
    assert height[near].max() > 0 and alpha[near].max() > 0
    assert (height > 0).sum() > 500 and (normal != [128, 128, 255]).any(axis=-1).sum() > 500
    top = float(images["height"].text["height_max_px"])
    maps = compute_maps(geometry.heights, sim.segments, params)
    assert height.max() / 65535 * top == pytest.approx(maps.height.max(), abs=1e-3)


def test_melted_ice_leaves_the_maps():
    params = Params.preset("c-2")
    sim, geometry = grow(params, 0, [(0, *TOUCH)], 100)
    inside = (slice(640 - 30, 640 + 30), slice(380 - 30, 380 + 30))  # > hc + feature reach inside
    assert compute_maps(geometry.heights, live_segments(sim), params).height[inside].max() > 0
    geometry.melt(sim, sim.melt(*TOUCH, 60.0))
    maps = compute_maps(geometry.heights, live_segments(sim), params)
    assert (maps.height[inside] == 0).all() and maps.height.max() > 0


def test_cli_export_maps(tmp_path, capsys):
    status = main(["maps", str(tmp_path / "maps"), "--preset", "c-2", "--touch", "380,640",
                   "--ticks", "20"])
    assert status == 0
    out = capsys.readouterr().out
    for name in ("height", "normal", "alpha"):
        assert str(tmp_path / "maps" / f"{name}.png") in out
        assert json.loads(Image.open(tmp_path / "maps" / f"{name}.png").text["touches"]) == [[0, 380, 640]]


# ---- the Fig. 8 sheet ----------------------------------------------------------------


@pytest.fixture(scope="module")
def figure(gl_ctx):
    return make_figure8(gl_ctx, seed=0, ticks=60, touch=TOUCH)


def _cells(sheet):
    out = {}
    for (r, row), (c, col) in itertools.product(enumerate(ROWS), enumerate(COLS)):
        x0, y0, x1, y1 = cell_box(r, c)
        out[f"{row}-{col}"] = sheet[y0:y1, x0:x1].astype(int)
    return out


@pytest.mark.gl
def test_sheet_is_three_by_three_cells(figure):
    sheet, stats = figure
    assert sheet.shape == (sheet_size()[1], sheet_size()[0], 3) and sheet.dtype == np.uint8
    assert [s.name for s in stats] == list(PRESETS)
    assert cell_box(2, 2)[2] <= sheet.shape[1] and cell_box(2, 2)[3] <= sheet.shape[0]
    cells = _cells(sheet)
    assert all(c.shape == (CELL[1], CELL[0], 3) for c in cells.values())
    # Each cell holds a frame (the background's sky), not the sheet's dark fill.
    assert all(c.std() > 10 for c in cells.values())


@pytest.mark.gl
def test_cells_differ_where_the_presets_do(figure):
    cells = _cells(figure[0])
    for a, b in [("b-1", "b-2"), ("b-2", "b-3"), ("b-1", "b-3"), ("c-1", "c-2"), ("c-2", "c-3"),
                 ("c-1", "c-3"), ("a-1", "a-3")]:  # a-1 has upsample particles, a-3 none
        assert np.abs(cells[a] - cells[b]).mean() > 0.05, (a, b)


@pytest.mark.gl
def test_every_cell_has_its_own_label(figure):
    sheet = figure[0]
    bands = {}
    for (r, row), (c, col) in itertools.product(enumerate(ROWS), enumerate(COLS)):
        x0, y0, x1, y1 = label_box(r, c)
        assert y1 - y0 == LABEL_H
        bands[f"{row}-{col}"] = sheet[y0:y1, x0:x1].astype(int)
    assert all((b.max(axis=-1) > 150).sum() > 30 for b in bands.values())  # text is drawn
    for a, b in itertools.combinations(bands, 2):
        assert not np.array_equal(bands[a], bands[b]), (a, b)
    assert label("a-1") == "a-1  D=1 hc=10 H=3000"


@pytest.mark.gl
def test_stats_table_lists_every_preset(figure):
    stats = figure[1]
    table = format_table(stats)
    assert all(label(n) in table for n in PRESETS)
    by = {s.name: s for s in stats}
    # D only upsamples: it never changes where the crystals are.
    assert by["a-1"].crystals == by["a-3"].crystals and by["a-1"].upsampled > by["a-3"].upsampled
    assert all(s.extent >= 0 and s.density >= 0 for s in stats)


@pytest.mark.usefixtures("subprocesses")
def test_cli_figure8_writes_a_sheet_with_metadata(tmp_path):
    """In a subprocess: the app makes its own GL context there."""
    out = tmp_path / "fig8.png"
    run = subprocess.run([sys.executable, "-m", "app", "figure8", str(out), "--ticks", "20"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr  # no OpenGL fails here: EGL is a dependency
    assert f"wrote {out}" in run.stdout and "c-3  D=7 hc=7 H=5000" in run.stdout
    im = Image.open(out)
    assert im.size == sheet_size() and json.loads(im.text["tick"]) == 20
    assert json.loads(im.text["touches"]) == [[0, 380.0, 640.0]]
    assert im.text["Software"] == "frost (frost figure8)" and "parameters" not in im.text


def test_every_png_states_itself_in_one_schema():
    """app.images.frost_meta: the keys every screenshot, render, map and sheet carries."""
    meta = frost_meta("frost render", Params.preset("c-2"), 3, 40, [(0, 380, 640), (7, 1.5, 2)],
                      view={"light": [0, 0, 1]})
    assert set(meta) == {"parameters", "seed", "tick", "touches", "Software", "Creation Time",
                         "view"}
    assert meta["parameters"] == Params.preset("c-2").as_dict() and meta["seed"] == 3
    assert meta["tick"] == 40 and meta["touches"] == [[0, 380.0, 640.0], [7, 1.5, 2.0]]
    assert meta["Software"] == "frost (frost render)"
    assert "parameters" not in frost_meta("frost figure8", None, 0, 20, [])
