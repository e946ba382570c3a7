"""The looks: Table 1's presets keep the paper's picture pixel for pixel (stored frame
hashes), the glass look's shader variants, and its measured cues."""

from __future__ import annotations

import hashlib
import itertools
import shutil
import subprocess

import numpy as np
import pytest
from support.looks import PAPER_RUNS, paper_frame

from app.gl import shaders
from app.gl.renderer import Renderer
from app.gl.shaders import load_program, shader_source
from app.images import read_image
from app.tools.offscreen import Offscreen
from sim import Params
from sim.io.timeline import Timeline, grow, touch_events
from sim.look.geometry import FrostGeometry, feature_scale
from sim.look.maps import compute_maps, live_segments, map_triangles
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES
from sim.look.ridges import VERTS_PER_LINK, ridge_triangles, width_level
from sim.params import LOOKS
from tests import glass_checks as checks

# sha256 of the H x W x 3 frame of the paper look, llvmpipe, its shaders compiled as GLSL
# 3.30 core (as every desktop compiles them; as ES 3.00 they differ by 1-2 / 255 on under
# 1 % of the pixels: test_the_desktop_and_the_es_dialect_draw_the_same_frost); grown by
# version 6's rules (one random stream); the runs are support.looks.PAPER_RUNS.
PAPER_HASHES = {
    "a-1 melt": "028bd041d2a1999cc8338d0fe639b2c443ad20df50c8d12ece543e1c0e8e9a3b",
    "b-1": "e81f21688e7ac4fb85327d0cedd4e0a221f1edfff90c5b2633bb9690490765fc",
    "c-2": "f1bdf7353a811f46558f02fd93f78671f2c536d46a0a9d7cd257b71f19e9dfea",
}


@pytest.mark.parametrize("name", sorted(PAPER_RUNS))
def test_paper_presets_unchanged(gl_ctx, name):
    digest = hashlib.sha256(paper_frame(gl_ctx, name).tobytes()).hexdigest()
    assert digest == PAPER_HASHES[name]


@pytest.mark.parametrize("name", ["c-2", "a-1 melt"])
def test_the_desktop_and_the_es_dialect_draw_the_same_frost(gl_ctx, name, monkeypatch):
    """The same files compiled as GLSL 3.30 core (every desktop: a Mac has no ES 3.00) and
    as ES 3.00 (the page's), on one rasteriser: within 1 / 255 on 99.9 % of the pixels."""
    frames = {}
    for dialect in ("es", "core"):
        monkeypatch.setattr(shaders, "DESKTOP", dialect)
        frames[dialect] = paper_frame(gl_ctx, name).astype(np.int16)
    off = np.abs(frames["es"] - frames["core"]).max(axis=2)
    assert frames["es"].std() > 10  # (frost drawn, not an empty frame)
    assert (off <= 1).mean() >= 0.999 and off.max() <= 4, (off.max(), (off > 1).mean())


# ---- the glass look's shader variants ---------------------------------------------------

GLASS_DEFINES = LOOK_DEFINES["glass"]
VARIANTS = [c for k in range(len(GLASS_DEFINES) + 1)
            for c in itertools.combinations(GLASS_DEFINES, k)]


@pytest.mark.parametrize("defines", VARIANTS, ids=lambda d: "+".join(d) or "paper")
def test_every_ice_variant_is_glsl_es_300(defines, tmp_path):
    exe = shutil.which("glslangValidator")
    assert exe, "glslangValidator is missing: apt-get install glslang-tools (`make test` does)"
    path = tmp_path / "ice.frag"
    path.write_text(shader_source("ice.frag", defines, dialect="es"), encoding="utf-8")
    run = subprocess.run([exe, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


@pytest.mark.parametrize("look", LOOKS)
@pytest.mark.parametrize("name", ["feature.vert", "feature.frag"])
def test_every_feature_variant_is_glsl_es_300(look, name, tmp_path):
    exe = shutil.which("glslangValidator")
    assert exe, "glslangValidator is missing: apt-get install glslang-tools (`make test` does)"
    path = tmp_path / name
    path.write_text(shader_source(name, FEATURE_DEFINES[look], dialect="es"), encoding="utf-8")
    run = subprocess.run([exe, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_every_look_compiles_in_context(gl_ctx):
    for look in LOOKS:
        load_program(gl_ctx, "tile.vert", "ice.frag", LOOK_DEFINES[look]).release()
        load_program(gl_ctx, "feature.vert", "feature.frag", FEATURE_DEFINES[look]).release()


# ---- anti-aliased ridge edges -------------------------------------------------------------

def covered_oracle(p, q, w: float, size: tuple[int, int], n: int = 8) -> np.ndarray:
    """Share of each pixel that lies within w of the line through p and q, counted on an
    n x n grid of points in the pixel."""
    t = (q - p) / np.hypot(*(q - p))
    sub = (np.arange(n) + 0.5) / n
    y, x = np.mgrid[0:size[1], 0:size[0]]
    sx, sy = x[..., None, None] + sub[None, None, None, :], y[..., None, None] + sub[:, None]
    across = (sx - p[0]) * -t[1] + (sy - p[1]) * t[0]
    return (np.abs(across) < w).mean(axis=(2, 3))


@pytest.mark.parametrize("degrees", [3, 19, 45, 71])
@pytest.mark.parametrize("w", [0.9, 2.3])
def test_a_glass_ridge_covers_its_edge_pixels_in_part(gl_ctx, degrees, w):
    # A straight ridge's coverage in the feature texture, along its body, against the
    # share of each pixel its footprint covers (the 0.9 px tips alias into dots without).
    size, turn = (200, 200), np.radians(degrees)
    half = 80.0 * np.array([np.cos(turn), np.sin(turn)])
    p, q = np.array([100.3, 100.2]) - half, np.array([100.3, 100.2]) + half
    renderer = Renderer(gl_ctx, Params.preset("fern"), *size, background=checkerboard(*size))
    layer = renderer.features
    layer.look, layer.height_scale = "glass", 16.0
    layer.append(ridge_triangles(p[None], q[None], np.array([w]), 1.6, np.array([7])))
    layer.draw_queued()
    cover = np.frombuffer(layer.texture.read(), np.uint8).reshape(200, 200, 4)[::-1, :, 3] / 255
    y, x = np.mgrid[0:200, 0:200]
    along = np.abs((x + 0.5 - 100.3) * np.cos(turn) + (y + 0.5 - 100.2) * np.sin(turn))
    body = along < 70  # the caps end in points, away from here
    err = np.abs(cover - covered_oracle(p, q, w, size))[body]
    assert err.max() <= 0.2


# ---- the pipe model ---------------------------------------------------------------------

def carried_oracle(sim) -> dict[int, int]:
    """Crystals each live link carries, walking up from every live crystal one by one."""
    counts: dict[int, int] = {}
    parents, alive = sim.parents, sim.crystal_alive
    for c in range(len(parents)):
        node = c
        while alive[c] and node >= 0:
            counts[node] = counts.get(node, 0) + 1
            node = int(parents[node])
    return counts


def grown_glass(ticks: int, melts=()):
    timeline = Timeline(Params.preset("fern"), 2, 300, 260, touches=[(150.0, 130.0)])
    grow(timeline, ticks, list(melts))
    return timeline


def test_carried_counts_follow_growth_and_melts():
    melts = [{"tick": 120, "kind": "melt", "x": 150.0, "y": 150.0, "r": 12.0},
             {"tick": 160, "kind": "melt", "x": 120.0, "y": 110.0, "r": 20.0}]
    timeline = grown_glass(200, melts)
    sim, ridges = timeline.sim, timeline.geometry.ridges
    want = carried_oracle(sim)
    live = np.flatnonzero(sim.crystal_alive)
    assert len(live) > 100 and max(want.values()) > 20
    assert {int(c): int(ridges.carried[c]) for c in live} == want


def test_a_melt_before_the_geometry_saw_the_ice_counts_right():
    # A storm's melt can land in the tick a touch planted its seed, before any step: the
    # counts had no row for it yet (an IndexError in the storm benchmark).
    events = [{"tick": 0, "kind": "melt", "x": 150.0, "y": 130.0, "r": 5.0},
              {"tick": 100, "kind": "touch", "x": 60.0, "y": 60.0},
              {"tick": 100, "kind": "melt", "x": 60.0, "y": 60.0, "r": 4.0},
              {"tick": 100, "kind": "touch", "x": 240.0, "y": 200.0},
              {"tick": 140, "kind": "melt", "x": 150.0, "y": 130.0, "r": 15.0}]
    timeline = Timeline(Params.preset("fern"), 2, 300, 260, touches=[(150.0, 130.0)])
    grow(timeline, 200, events)
    sim, ridges = timeline.sim, timeline.geometry.ridges
    live = np.flatnonzero(sim.crystal_alive)
    assert len(live) > 50
    assert {int(c): int(ridges.carried[c]) for c in live} == carried_oracle(sim)


def test_a_link_is_sent_again_only_when_it_thickens():
    # Sent once per width level it reached at the end of a tick, by the oracle's counts.
    timeline = grown_glass(0)
    hc, levels, sent = timeline.params.hc, {}, 0
    for _ in range(110):
        sent += len(timeline.step()[-1].features) // VERTS_PER_LINK
        sim = timeline.sim
        for c, n in carried_oracle(sim).items():
            if sim.parents[c] >= 0:
                levels.setdefault(c, set()).add(int(width_level(np.array([n]), hc)[0]))
    assert len(levels) > 200
    assert sent == sum(len(s) for s in levels.values())


def test_after_a_melt_the_ridges_are_those_drawn_from_scratch(gl_ctx):
    melts = [{"tick": 130, "kind": "melt", "x": 150.0, "y": 100.0, "r": 12.0}]
    timeline = Timeline(Params.preset("fern"), 2, 300, 260, touches=[(150.0, 130.0)])
    live_view = Renderer(gl_ctx, timeline.params, 300, 260, background=checkerboard(300, 260))
    grow(timeline, 160, melts, lambda a: [live_view.apply(d) for d in a.deltas],
         live_view.apply, None)
    fresh = Renderer(gl_ctx, timeline.params, 300, 260, background=checkerboard(300, 260))
    fresh.apply(FrostGeometry(timeline.params, 300, 260).redraw(timeline.sim))
    a, b = draw(gl_ctx, live_view), draw(gl_ctx, fresh)
    assert (a != b).any(axis=2).sum() == 0


@pytest.mark.parametrize("first, then", [("paper", "glass"), ("glass", "paper")])
def test_a_change_of_look_redraws_the_same_frost(gl_ctx, first, then):
    def run(looks):
        o = Offscreen(gl_ctx, Params.preset("fern", look=looks[0]), 0)
        o.grow(120, touch_events([(380.0, 640.0)]))
        change = [{"tick": 120, "kind": "params", "params": Params.preset("fern", look=looks[-1])}]
        o.grow(60, change if len(looks) > 1 else [])
        try:
            return o.frame(), o.sim.crystals.copy()
        finally:
            o.release()

    (switched, c1), (straight, c2) = run((first, then)), run((then,))
    np.testing.assert_array_equal(c1, c2)  # the simulation went on, not regrown
    np.testing.assert_array_equal(switched, straight)


def test_high_features_are_not_clipped():
    # feature_height up to 10 x L: the texture's scale must cover the tallest feature.
    for look in LOOKS:
        params = Params.preset("c-2", feature_height=10.0, look=look)
        timeline = Timeline(params, 0, 200, 200, touches=[(100.0, 100.0)])
        top = 0.0
        for _ in range(60):
            top = max(top, float(timeline.step()[-1].features[:, 2].max(initial=0.0)))
        assert top > 16.0
        assert top <= feature_scale(params)


# ---- helpers ------------------------------------------------------------------------------

def checkerboard(width: int, height: int, side: int = 8) -> np.ndarray:
    y, x = np.mgrid[0:height, 0:width]
    on = ((x // side + y // side) % 2).astype(np.uint8) * 255
    return np.repeat(on[:, :, None], 3, axis=2)


def draw(ctx, renderer: Renderer) -> np.ndarray:
    fbo = ctx.simple_framebuffer(renderer.size, components=4)
    try:
        renderer.render(fbo)
        return read_image(fbo)
    finally:
        fbo.release()


# ---- the glass look's targets, measured (tests/glass_checks.py) ----------------------

def measured(ctx, look: str):
    """One touch at the centre grown to tick 750 in fern's frost with `look`: the run,
    its frames over flat backdrops and the checkerboard, and its thickness (bumps, ridges)."""
    run = checks.grown(ctx, look)
    return run, checks.frames_over(run), checks.thickness(run.renderer)


@pytest.fixture(scope="module")
def fern_glass(gl_ctx):
    """The default look (fern: glass), one touch at the centre, tick 750."""
    run, frames, thick = measured(gl_ctx, "glass")
    yield run, frames, thick
    run.release()


def test_glass_colour_is_even_along_a_link(fern_glass):
    run, frames, _ = fern_glass
    assert checks.colour_variation(frames["black"], run.sim) <= 0.11


def test_the_paper_look_varies_along_a_link_by_about_15_percent(gl_ctx):
    # The paper's per-segment pyramids dip at every node: about 15 % colour variation.
    run, frames, _ = measured(gl_ctx, "paper")
    run.release()
    assert 0.13 <= checks.colour_variation(frames["black"], run.sim) <= 0.17


def test_glass_ridges_are_thicker_by_the_seed_than_at_a_leaf(fern_glass):
    run, _, thick = fern_glass
    near, leaf = checks.ridge_mass(thick[1], run.sim, 0.75 * run.sim.params.hc)
    assert near >= 2 * leaf > 0


def test_glass_ridges_follow_the_pipe_model(fern_glass):
    # Half-width ~ n^(1/3) and a ridge's cross-section ~ width^2: mass ~ n^(2/3). Pixels
    # weigh the thinnest ridges up (a 2 px ridge's crest and edge pixels), so the measure
    # reads about 0.85 x the exponent: 2/3 reads 0.58, a square root (1) 0.84, n^(1/4) 0.42.
    run, _, thick = fern_glass
    assert 0.5 < checks.width_law(thick[1], run.sim, 0.75 * run.sim.params.hc) < 0.75


def test_glass_ice_is_tinted_when_thin_and_white_when_thick(fern_glass):
    run, frames, thick = fern_glass
    thin, deep = checks.tint(frames["black"], checks.opacity(frames), sum(thick))
    assert thin > deep + 0.08


def speck_hash(height: int, width: int) -> np.ndarray:
    """shaders/ice.frag's per-pixel speck number at each pixel (rows top down), float32 as
    the GPU computes it: interleaved gradient noise of gl_FragCoord's whole part."""
    yy, xx = np.mgrid[0:height, 0:width]
    fx, fy = xx.astype(np.float32), (height - 1 - yy).astype(np.float32)
    dot = fx * np.float32(0.06711056) + fy * np.float32(0.00583715)
    inner = np.float32(52.9829189) * (dot - np.floor(dot))
    return inner - np.floor(inner)


def test_sparkle_breaks_the_glints_into_one_pixel_specks(fern_glass, monkeypatch):
    """With the variant off the same frost shines evenly; with it each pixel's glint is
    dimmed or brightened as its speck number says (>= 0.55: brighter)."""
    import app.gl.renderer as renderer_module

    run, frames, thick = fern_glass
    monkeypatch.setattr(renderer_module, "LOOK_DEFINES", {
        **LOOK_DEFINES, "glass": tuple(d for d in LOOK_DEFINES["glass"] if d != "SPARKLE")})
    cached = run.renderer._ice_progs.pop("glass")
    try:
        run.renderer.set_background_image(np.zeros((1280, 760, 3), np.uint8), "black")
        even = run.frame().astype(np.float64).mean(axis=2)
    finally:
        run.renderer._ice_progs["glass"] = cached
    sparkled = frames["black"].mean(axis=2)
    changed = (sum(thick) > 1.0) & (np.abs(sparkled - even) > 3)
    assert changed.sum() > 500
    brighter = (sparkled > even)[changed]
    assert (brighter == (speck_hash(*even.shape) >= 0.55)[changed]).all()


def test_glass_displaces_the_view_and_leaves_clear_glass_exact(fern_glass):
    run, frames, thick = fern_glass
    seen = checks.view_through(frames, sum(thick))
    assert seen["medium_px"] > 5000 and seen["clear_px"] > 100_000
    assert seen["displaced"] > 0.2
    assert seen["clear_exact"]


def test_the_paper_look_blends_the_view_without_displacing_it(gl_ctx):
    run = checks.grown(gl_ctx, "paper", ticks=200)
    try:
        seen = checks.view_through(checks.frames_over(run), sum(checks.thickness(run.renderer)))
    finally:
        run.release()
    assert seen["medium_px"] > 1000 and seen["displaced"] < 0.01 and seen["clear_exact"]


# ---- maps share the renderer's geometry ----------------------------------------------------

@pytest.mark.parametrize("preset, look", [("fern", "glass"), ("fern", "paper"), ("c-2", "paper")])
def test_maps_height_is_what_the_renderer_holds(gl_ctx, preset, look):
    # The drawn surface read back (bumps through the film, ridges from the feature texture)
    # against the exported height map: equal to the texture's 8-bit steps but for pixels
    # on a triangle's edge, where GL's tie rule and the pixel-centre test may differ.
    timeline = Timeline(Params.preset(preset, look=look), 1, 300, 260, touches=[(150.0, 130.0)])
    renderer = Renderer(gl_ctx, timeline.params, 300, 260, background=checkerboard(300, 260))
    grow(timeline, 150, (), lambda a: [renderer.apply(d) for d in a.deltas], renderer.apply)
    bumps, ridges = checks.thickness(renderer)
    maps = compute_maps(timeline.geometry.heights, live_segments(timeline.sim), timeline.params,
                        300, 260, map_triangles(timeline.sim, timeline.params))
    step = renderer.height_scale / 255
    off = np.abs(maps.height - (bumps + ridges)) > step + 1e-3
    assert ridges.max() > 2 and off.mean() < 0.01
