"""Shaders (GLSL ES 3.00), the renderer's pixels against Python arithmetic, and headless PNGs."""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support.looks import paper_frame
from support.window import MAC_LIMITS

from app.gl.renderer import Renderer
from app.gl.shaders import HEADERS, SHADER_DIR, load_program, shader_source
from app.images import read_image, save_png, timestamped_path
from app.window import no_panel
from sim import Params
from sim.look.geometry import GeometryDelta, feature_triangles

ROOT = Path(__file__).resolve().parent.parent
W, H = 160, 128
PROGRAMS = [("fullscreen.vert", "background.frag"), ("tile.vert", "ice.frag"),
            ("feature.vert", "feature.frag"), ("imgui.vert", "imgui.frag")]
SHADERS = sorted(p.name for p in SHADER_DIR.iterdir() if p.suffix in (".vert", ".frag"))
NO_FEATURES = np.empty((0, 6), np.float32)


@pytest.mark.parametrize("dialect", ["es", "core"])
@pytest.mark.parametrize("name", SHADERS)
def test_shader_is_glsl_es_300_and_glsl_330(name, dialect, tmp_path):
    # ES for the page (and it rejects what 3.30 lets pass), 3.30 core for every desktop.
    exe = shutil.which("glslangValidator")
    assert exe, "glslangValidator is missing: apt-get install glslang-tools (`make test` does)"
    path = tmp_path / f"shader{Path(name).suffix}"
    path.write_text(shader_source(name, dialect=dialect), encoding="utf-8")
    run = subprocess.run([exe, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


@pytest.mark.parametrize("vert, frag", PROGRAMS)
def test_programs_compile_in_context(gl_ctx, vert, frag):
    load_program(gl_ctx, vert, frag).release()


def background() -> np.ndarray:
    """A dark, top-to-bottom graded view, so flips and offsets show."""
    y = np.linspace(20, 70, H)[:, None, None]
    x = np.linspace(0, 30, W)[None, :, None]
    return np.broadcast_to(y + x + [0, 5, 10], (H, W, 3)).astype(np.uint8)


def plateau(rows: slice, cols: slice, h: float, cols_total: int) -> GeometryDelta:
    """Heights set to h over a block of grid vertices (flat inside: slope 0)."""
    heights = np.zeros((rows.stop - rows.start, cols_total), np.float32)
    heights[:, cols] = h
    return GeometryDelta(1, rows, heights, NO_FEATURES)


def frame(ctx, renderer: Renderer) -> np.ndarray:
    fbo = ctx.simple_framebuffer((W, H), components=4)
    renderer.render(fbo)
    image = read_image(fbo)
    fbo.release()
    return image.astype(np.float64)


@pytest.fixture
def renderer(gl_ctx):
    return Renderer(gl_ctx, Params(), W, H, background=background())


def test_clear_glass_is_the_background(gl_ctx, renderer):
    np.testing.assert_array_equal(frame(gl_ctx, renderer), background())


def test_ice_brightens_and_leaves_far_pixels_alone(gl_ctx, renderer):
    cols = renderer.grid_size[0]
    renderer.apply(plateau(slice(10, 20), slice(10, 20), 3.0, cols))  # px 40..76
    img, bg = frame(gl_ctx, renderer), background().astype(np.float64)
    np.testing.assert_array_equal(img[:30], bg[:30])  # rows far above the ice
    np.testing.assert_array_equal(img[:, 90:], bg[:, 90:])  # columns far right of it
    assert (img[50:66, 50:66] > bg[50:66, 50:66] + 20).all()


def test_blend_matches_python_arithmetic(gl_ctx, renderer):
    """On a flat plateau n = (0, 0, 1): Phong and premultiplied 'over' by hand."""
    h, cols = 2.0, renderer.grid_size[0]
    renderer.show_features = False
    renderer.apply(plateau(slice(8, 24), slice(8, 24), h, cols))
    m, light = renderer.material, np.array([0.3, -0.2, 0.9])
    renderer.light = light
    light = light / np.linalg.norm(light)
    alpha = m.opacity * (1 - np.exp(-m.density * h))
    specular = light[2] ** m.shininess  # reflect(-l, n).z = l.z for n = z
    lit = np.array(m.ice_color) * (m.ambient + m.diffuse * light[2])
    ice = alpha * lit + m.specular * specular * alpha / m.opacity
    x, y = 64, 64
    want = np.clip(ice + (1 - alpha) * background()[y, x] / 255.0, 0, 1) * 255
    np.testing.assert_allclose(frame(gl_ctx, renderer)[y, x], want, atol=1.5)


def brightest_x(gl_ctx, renderer, light) -> int:
    renderer.light = light
    img = frame(gl_ctx, renderer).sum(axis=2)
    return int(np.unravel_index(np.argmax(img), img.shape)[1])


def test_moving_the_light_moves_the_highlight(gl_ctx, renderer):
    # One vertical feature at x = 80: its left faces lean left, its right faces right.
    verts = feature_triangles(np.array([[80, 40, 80, 80]], np.float32), 1.5, 0.5)
    renderer.show_bumps = False
    renderer.apply(GeometryDelta(1, slice(0, 0), np.zeros((0, 41), np.float32), verts))
    left = brightest_x(gl_ctx, renderer, (-0.6, 0.0, 0.8))
    right = brightest_x(gl_ctx, renderer, (0.6, 0.0, 0.8))
    assert left < 80 < right


def test_reset_clears_the_ice(gl_ctx, renderer):
    renderer.apply(plateau(slice(5, 9), slice(5, 9), 3.0, renderer.grid_size[0]))
    renderer.reset()
    np.testing.assert_array_equal(frame(gl_ctx, renderer), background())


def test_missing_background_is_a_clear_error(tmp_path):
    from app.gl.renderer import load_background

    with pytest.raises(FileNotFoundError, match="make_background"):
        load_background(tmp_path / "none.png")


def test_png_metadata_and_fresh_names(tmp_path):
    image = np.zeros((4, 5, 3), np.uint8)
    path = save_png(image, timestamped_path(tmp_path), {"seed": 7, "touches": [[1, 2]]})
    assert path.exists() and timestamped_path(tmp_path) != path
    text = Image.open(path).text
    assert json.loads(text["seed"]) == 7 and json.loads(text["touches"]) == [[1, 2]]


@pytest.mark.parametrize("prefix, suffix", [("frost", ".png"), ("frost-demo", ""),
                                            ("session", ".json"), ("frost", ".webp")])
def test_two_runs_in_the_same_second_choose_different_names(monkeypatch, tmp_path, prefix, suffix):
    """Two runs each choose a name before either has written (a render names its PNG at
    the start, the window its session file): in the same second they must still differ."""
    monkeypatch.setattr("app.images.time.strftime", lambda fmt: "20261125-120000")
    chosen = []
    for pid in (4100, 4101):
        monkeypatch.setattr("app.images.os.getpid", lambda pid=pid: pid)
        chosen.append(timestamped_path(tmp_path, prefix, suffix))
    assert chosen[0] != chosen[1]
    for run, path in enumerate(chosen):
        path.write_text(f"run {run}", encoding="utf-8")
    # neither overwrote the other
    assert [p.read_text(encoding="utf-8") for p in chosen] == ["run 0", "run 1"]


FROZEN_CLOCK = ("import sys, time; time.strftime = lambda fmt, *t: '20261125-120000'; "
                "from app.cli import main; sys.exit(main(sys.argv[1:]))")


@pytest.mark.usefixtures("subprocesses")
def test_runs_started_together_overwrite_none_of_each_others_files(gl_ctx, tmp_path):
    """Four headless renders at once with one frozen clock (so every run starts in the same
    second), two scripted demos and two with a touch, all into frost-out/: every file a run
    says it wrote is there, holds that run's seed, and no two runs named the same file."""
    runs = {seed: ["render", "--seed", str(seed), "--ticks", "3"] + touch
            for seed, touch in [(1, []), (2, []), (3, ["--touch", "380,640"]),
                                (4, ["--touch", "380,640"])]}
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    procs = {seed: subprocess.Popen([sys.executable, "-c", FROZEN_CLOCK, *argv], cwd=tmp_path,
                                    env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    text=True) for seed, argv in runs.items()}
    said: dict[int, list[Path]] = {}
    for seed, proc in procs.items():
        out, err = proc.communicate(timeout=180)
        assert proc.returncode == 0, err
        said[seed] = said_written(out, tmp_path / "frost-out")
    names = [p.name for files in said.values() for p in files]
    assert len(names) == 3 + 3 + 1 + 1 == len(set(names))
    assert sorted(names) == sorted(p.name for p in (tmp_path / "frost-out").iterdir())
    for seed, files in said.items():
        for path in files:
            assert json.loads(Image.open(path).text["seed"]) == seed, path


def said_written(stdout: str, folder: Path) -> list[Path]:
    """The files a render's last line says it wrote: 'wrote frost-out/NAME' (relative to
    the folder it ran in) or 'wrote N PNG files to FOLDER: a, b, c'."""
    line = stdout.strip().splitlines()[-1]
    if ": " in line:
        return [folder / name for name in line.split(": ", 1)[1].split(", ")]
    return [folder.parent / line.removeprefix("wrote ")]


def run_cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "app", "render", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.usefixtures("subprocesses")
def test_headless_cli_writes_png_with_metadata(gl_ctx, tmp_path):
    out = tmp_path / "shot.png"
    run = run_cli("--preset", "c-2", "--seed", "5", "--touch", "380,640", "--touch", "100,200",
                  "--ticks", "20", "--hc", "6", "--out", str(out))
    assert run.returncode == 0, run.stderr
    image = Image.open(out)
    assert image.size == (760, 1280)
    assert json.loads(image.text["seed"]) == 5
    assert json.loads(image.text["tick"]) == 20  # the frame's own tick
    assert json.loads(image.text["parameters"])["hc"] == 6.0
    assert [t[1:] for t in json.loads(image.text["touches"])] == [[380, 640], [100, 200]]
    assert (np.asarray(image.convert("RGB")) != np.asarray(Image.open(ROOT / "assets" /
                                                                       "background.png"))).any()


@pytest.mark.parametrize("name", ["shot.jpg", "shot.JPEG"])
@pytest.mark.usefixtures("subprocesses")
def test_headless_cli_writes_a_real_jpeg_under_a_jpeg_name(gl_ctx, tmp_path, name):
    argv = ("--seed", "3", "--touch", "380,640", "--ticks", "12")
    jpeg, png = tmp_path / name, tmp_path / "same.png"
    for out in (jpeg, png):
        run = run_cli(*argv, "--out", str(out))
        assert run.returncode == 0, run.stderr
    image = Image.open(jpeg)
    assert image.format == "JPEG" and image.size == (760, 1280)
    meta = json.loads(image.info["comment"])  # a JPEG's one comment segment holds the JSON
    assert meta["seed"] == 3 and meta["tick"] == 12 and meta["Software"] == "frost (frost render)"
    assert [t[1:] for t in meta["touches"]] == [[380, 640]]
    # The same frame as the PNG of the same run, up to JPEG's loss.
    diff = np.abs(np.asarray(image, np.int16) - np.asarray(Image.open(png).convert("RGB"), np.int16))
    assert diff.mean() < 2.0, diff.mean()


def test_a_jpeg_comment_too_long_leaves_out_its_largest_entries(tmp_path):
    from app.images import JPEG_COMMENT_MAX, save_image

    touches = [[t, 380.5, 640.25] for t in range(5000)]  # some 100 KB of JSON
    meta = {"seed": 7, "touches": touches, "view": {"light": [1, 2]}}
    path = save_image(np.zeros((8, 8, 3), np.uint8), tmp_path / "x.jpg", meta)
    comment = Image.open(path).info["comment"]
    assert len(comment) <= JPEG_COMMENT_MAX
    assert json.loads(comment) == {"seed": 7, "view": {"light": [1, 2]}, "left_out": ["touches"]}
    small = save_image(np.zeros((8, 8, 3), np.uint8), tmp_path / "y.jpg", {"seed": 7})
    assert json.loads(Image.open(small).info["comment"]) == {"seed": 7}


@pytest.mark.usefixtures("subprocesses")
def test_headless_cli_bad_touch_is_a_clear_error(gl_ctx, tmp_path):
    run = run_cli("--touch", "9999,5", "--ticks", "1", "--out", str(tmp_path / "x.png"))
    assert run.returncode == 2
    assert "off the 760x1280 screen" in run.stdout + run.stderr
    assert "Traceback" not in run.stderr


def test_no_opengl_is_a_clear_message(monkeypatch, capsys):
    from app.cli.parser import build_parser
    from app.tools import render_png as render

    def broken():
        raise RuntimeError("no OpenGL available: test")

    monkeypatch.setattr(render, "make_context", broken)
    args = build_parser().parse_args(["render", "--touch", "10,10"])
    assert render.run(args, Params()) == 1
    assert "no OpenGL available" in capsys.readouterr().err


def grown_on_renderer(gl_ctx, params, seed, touch, ticks):
    """(sim, geometry, renderer) after `ticks` ticks from one touch, every delta applied."""
    from sim import FrostSim
    from sim.look.geometry import FrostGeometry

    sim, geo = FrostSim(params, W, H, seed=seed), FrostGeometry(params, W, H)
    renderer = Renderer(gl_ctx, params, W, H, background=background())
    sim.touch(*touch)
    for _ in range(ticks):
        sim.step()
        renderer.apply(geo.update(sim))
    return sim, geo, renderer


def test_tiles_cover_all_the_ice(gl_ctx):
    """Drawing the ice pass on every tile changes nothing: no ice lies outside the tiles."""
    params = Params.preset("a-2", active_radius=40.0, humidity=600)
    _, _, renderer = grown_on_renderer(gl_ctx, params, 2, (60, 50), 30)
    tiled = frame(gl_ctx, renderer)
    assert (tiled != background()).any()
    renderer.tiles.fill()
    np.testing.assert_array_equal(frame(gl_ctx, renderer), tiled)


def test_melt_renders_as_if_the_ice_never_grew_there(gl_ctx):
    params = Params.preset("a-2", active_radius=50.0, humidity=800)
    sim, geo, melted_view = grown_on_renderer(gl_ctx, params, 4, (80, 60), 40)
    frame(gl_ctx, melted_view)  # the ice is drawn before the melt
    x, y = sim.crystals[len(sim.crystals) // 2]
    melted_view.apply(geo.melt(sim, sim.melt(float(x), float(y), 10.0)))
    fresh = Renderer(gl_ctx, params, W, H, background=background())
    live = feature_triangles(sim.segments[sim.segments_alive], 1.5, 0.5)
    fresh.apply(GeometryDelta(0, slice(0, geo.rows), geo.heights.copy(), live))
    a, b = frame(gl_ctx, melted_view), frame(gl_ctx, fresh)
    # Equal up to the order in which equally high overlapping faces were drawn.
    assert (np.abs(a - b).max(axis=2) > 2).sum() < 0.002 * W * H


def test_the_pages_shader_header_is_the_es_dialects():
    # One header per dialect: the page's copy (app/web/programs.js) is the loader's "es".
    js = (Path(__file__).resolve().parent.parent / "app" / "web" / "programs.js").read_text(encoding="utf-8")
    start = js.index('export const HEADER = "') + len('export const HEADER = "')
    page = js[start:js.index('";', start)].encode().decode("unicode_escape")
    assert page == HEADERS["es"]


@pytest.mark.parametrize("dialect", ["gles", "ES", "core "])
def test_an_unknown_shader_dialect_is_a_value_error_naming_it(dialect):
    """Not a KeyError from the table: a ValueError that says the dialect asked for and the
    ones there are."""
    with pytest.raises(ValueError, match=f"GLSL dialect {dialect!r}: one of core, es"):
        shader_source("ice.frag", dialect=dialect)


MAC_RUN = """
import sys
import numpy as np
sys.path[:0] = [".", "tests"]
from app.gl.shaders import load_program
from app.tools.offscreen import make_context
from support.looks import paper_frame
ctx = make_context()
print("GL", ctx.info["GL_VERSION"])
try:
    load_program(ctx, "fullscreen.vert", "background.frag", dialect="es")
    print("ES 3.00 compiled")
except Exception:
    print("ES 3.00 refused")
for vert, frag, defines in PROGRAMS:
    load_program(ctx, vert, frag, tuple(defines)).release()
np.save(sys.argv[1], paper_frame(ctx, "c-2"))
"""


@pytest.mark.usefixtures("subprocesses")
def test_under_a_macs_opengl_every_program_compiles_and_draws_the_frost(gl_ctx, tmp_path,
                                                                        monkeypatch):
    """Under a Mac's limits every program of every look compiles (as 3.30 core: the ES 3.00
    header is refused there) and the frost drawn matches the ES 3.00 path's within 1 / 255
    on 99.9 % of the pixels (the same rasteriser)."""
    from app.gl import shaders
    from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES

    programs = [(v, f, ()) for v, f in PROGRAMS] + [
        p for look in LOOK_DEFINES for p in (("tile.vert", "ice.frag", LOOK_DEFINES[look]),
                                             ("feature.vert", "feature.frag",
                                              FEATURE_DEFINES[look]))]
    out = tmp_path / "mac.npy"
    run = subprocess.run([sys.executable, "-c", f"PROGRAMS = {programs!r}\n" + MAC_RUN, str(out)],
                         cwd=Path(__file__).resolve().parent.parent, capture_output=True,
                         text=True, env={**os.environ, **MAC_LIMITS}, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "GL 4.1" in run.stdout and "ES 3.00 refused" in run.stdout, run.stdout
    monkeypatch.setattr(shaders, "DESKTOP", "es")
    es = paper_frame(gl_ctx, "c-2").astype(np.int16)
    off = np.abs(np.load(out).astype(np.int16) - es).max(axis=2)
    assert (off <= 1).mean() >= 0.999, ((off > 1).mean(), off.max())


@pytest.mark.parametrize("platform, tried", [("linux", ["egl", None]), ("darwin", [None]),
                                             ("win32", [None])])
def test_the_headless_context_comes_from_the_platforms_backends_in_turn(monkeypatch, platform,
                                                                        tried):
    """EGL on Linux, then GLX; a Mac's and Windows' own default (they have no EGL); each
    failure named in one line when none gives a context."""
    import moderngl

    from app.tools import offscreen

    asked = []

    def refuse(require=None, backend=None):
        asked.append(backend)
        assert require == 330
        raise Exception(f"no {backend or 'default'}\nsecond line")

    monkeypatch.setattr(offscreen.sys, "platform", platform)
    monkeypatch.setattr(moderngl, "create_standalone_context", refuse)
    with pytest.raises(RuntimeError) as err:
        offscreen.make_context()
    assert asked == tried and "\n" not in str(err.value)
    assert all(f"no {b or 'default'}" in str(err.value) for b in tried)
    asked.clear()

    def no_egl(require=None, backend=None):
        return refuse(require, backend) if backend == "egl" else asked.append(backend) or "ctx"

    monkeypatch.setattr(moderngl, "create_standalone_context", no_egl)
    assert offscreen.make_context() == "ctx" and asked == tried  # (EGL gone: the next one)


@pytest.mark.parametrize("limits", [False, True], ids=["here", "macs-limits"])
@pytest.mark.usefixtures("subprocesses")
def test_frost_info_says_what_a_bug_report_needs(limits):
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    run = subprocess.run([sys.executable, "-m", "app", "info"], capture_output=True, text=True,
                         env={**env, **(MAC_LIMITS if limits else {})}, timeout=120,
                         cwd=Path(__file__).resolve().parent.parent)
    assert run.returncode == 0, run.stdout + run.stderr
    said = dict(line.split(": ", 1) for line in run.stdout.splitlines())
    assert set(said) >= {"frost", "platform", "python", "packages", "tuning panel", "shader dialect",
                         "headless OpenGL", "its shaders", "GLFW"}
    # the panel's library as installed here, or why the window has none (tests/test_requirements.py)
    has_imgui = importlib.util.find_spec("imgui_bundle") is not None
    assert said["tuning panel"] == ("imgui-bundle 1.93.0 (key M)" if has_imgui else
                                    "none: " + no_panel.panel_problem())
    assert said["shader dialect"].startswith("GLSL core")
    assert "no display" in said["GLFW"]
    if limits:  # the Mac's: 4.1, and the page's ES 3.00 refused on the desktop
        assert said["headless OpenGL"].startswith("4.1") and "es: refused" in said["its shaders"]
        assert "\\n" not in said["its shaders"] and "main" in said["its shaders"]  # the error
    else:
        assert "core: compiles" in said["its shaders"]
