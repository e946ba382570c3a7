"""The package as a user gets it: a wheel built from a copy of the checkout, installed into a
fresh virtualenv, its `frost` command run from a folder that is not the checkout."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import urllib.request
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support import ROOT
from support.checkout import TOOLING
from support.shared import made_once

from bench.serve_process import ServeProcess

# Longer than the suite's timeout by nature: the first test to use `venv` waits for its
# two steps, each allowed 5 minutes (_run), and a wheel is built before.
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1200), pytest.mark.usefixtures("subprocesses")]

# The render the test asks the installed command for (arguments after `frost`).
RENDER_ARGS = ["render", "--touch", "380,640", "--ticks", "50", "--out", "x.png"]
TOUCH = (380, 640)
# What a checkout may hold that a build must not see (the demo's outputs, build leftovers).
NOT_SOURCE = [*TOOLING, "*.egg-info", "screenshots", "recordings", "frost-out", "sessions", ".gl", ".whl"]


def _run(cmd: list, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    done = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)
    assert done.returncode == 0, f"{cmd} failed:\n{done.stdout}\n{done.stderr}"
    return done


def _copy(tmp: Path) -> Path:
    """A copy of the checkout in `tmp` (as a user's clone or unpacked archive holds it), so
    that a build leaves nothing in the checkout."""
    shutil.copytree(ROOT, tmp / "frost", ignore=shutil.ignore_patterns(*NOT_SOURCE))
    return tmp / "frost"


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy, once a run (support.shared: the workers share it)."""
    def build(tmp: Path) -> None:
        _run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", tmp / "dist", _copy(tmp)],
             tmp)

    (found,) = (made_once(tmp_path_factory, "wheel", build) / "dist").glob("frost-*.whl")
    return found


# The steps docs/platforms.md (and the README) give a Mac, in its folder; Windows' are
# the same with `py` and .venv\Scripts\ (tests/test_package.py cannot run those).
MAC_STEPS = ["python3 -m venv .venv", ".venv/bin/python -m pip install ."]
WINDOWS_STEPS = ["py -m venv .venv", r".venv\Scripts\python -m pip install ."]


@pytest.fixture(scope="module")
def venv(tmp_path_factory) -> Path:
    """The package as the Mac's steps install it, run word for word by a shell in a copy of
    the checkout: a fresh virtual environment in it, the package and its dependencies (from
    the index or pip's cache) installed into it, once a run (support.shared: the workers
    share it, and use it only to run it). Its bin folder."""
    def install(tmp: Path) -> None:
        folder = _copy(tmp)
        for step in MAC_STEPS:
            _run(["sh", "-c", step], folder)

    return made_once(tmp_path_factory, "user", install) / "frost" / ".venv" / "bin"


@pytest.mark.parametrize("page", ["README.md", "docs/platforms.md"])
def test_the_install_steps_tested_here_are_the_ones_the_docs_give(page):
    text = (ROOT / page).read_text(encoding="utf-8")
    lines = {line.strip() for line in text.splitlines()}  # (a code block's, in a list item)
    for step in [*MAC_STEPS, *WINDOWS_STEPS]:
        assert f"`{step}`" in text or step in lines, step


@pytest.fixture
def elsewhere(tmp_path) -> Path:
    """A working folder outside the checkout."""
    assert ROOT not in tmp_path.parents
    return tmp_path


def test_wheel_holds_every_module_the_shaders_the_background_and_the_page(wheel):
    checkout = [p for pkg in ("app", "sim") for p in (ROOT / pkg).rglob("*.py")]
    modules = {p.relative_to(ROOT).as_posix(): p for p in checkout}
    data = {f"app/_data/shaders/{p.name}": p for p in (ROOT / "shaders").iterdir()}
    assert any(name.endswith(".frag") for name in data)
    data["app/_data/assets/background.png"] = ROOT / "assets" / "background.png"
    web = ROOT / "app" / "web"  # the page, its worker and its icons (the installed app's)
    data.update({f"app/web/{p.relative_to(web).as_posix()}": p for p in web.rglob("*") if p.is_file()})
    assert {"app/web/index.html", "app/web/sw.js", "app/web/icons/maskable-512.png"} <= set(data)
    with zipfile.ZipFile(wheel) as whl:
        names = set(whl.namelist())
        assert set(modules) - names == set()
        assert set(data) - names == set()
        for name, source in data.items():
            assert whl.read(name) == source.read_bytes(), name


def holding(whl: zipfile.ZipFile, word: bytes) -> list[str]:
    """The .py files of `whl` whose bytes hold `word` in any case (comments and strings too)."""
    return [name for name in whl.namelist()
            if name.endswith(".py") and word.lower() in whl.read(name).lower()]


def test_holding_finds_a_word_in_any_case_in_python_files_only(tmp_path):
    with zipfile.ZipFile(tmp_path / "x.whl", "w") as whl:
        whl.writestr("a/code.py", "from PlayWright.sync_api import x\n")
        whl.writestr("a/comment.py", "# needs PLAYWRIGHT\n")
        whl.writestr("a/clean.py", "import play\n# write\n")
        whl.writestr("a/notes.txt", "playwright\n")
    with zipfile.ZipFile(tmp_path / "x.whl") as whl:
        assert holding(whl, b"playwright") == ["a/code.py", "a/comment.py"]


def test_no_module_of_the_wheel_names_playwright_nor_is_of_the_checkout_s_bench(wheel):
    """The benchmarks that drive a browser stay in the checkout (bench/): nothing a user
    installs imports, or even mentions, the test stack's browser driver."""
    with zipfile.ZipFile(wheel) as whl:
        assert holding(whl, b"playwright") == []
        assert [n for n in whl.namelist() if n.split("/")[0] == "bench"] == []


def test_installed_package_is_not_the_checkout(venv, elsewhere):
    where = "import app, sim; print(app.__file__); print(sim.__file__)"
    out = _run([venv / "python", "-c", where], elsewhere)
    for line in out.stdout.splitlines():
        assert Path(line).is_relative_to(venv.parent), line


def test_frost_help(venv, elsewhere):
    out = _run([venv / "frost", "--help"], elsewhere)
    assert "usage:" in out.stdout
    assert "--touch" in out.stdout
    # `python -m app`, where the frost script is not found: the same command line
    assert _run([venv / "python", "-m", "app", "--help"], elsewhere).stdout == out.stdout


def test_the_install_brings_the_tuning_panel_where_its_library_has_a_wheel(venv, elsewhere):
    """Here (Linux, as CI and `make run`) pip installs imgui-bundle by pyproject.toml's
    marker wherever app/window/no_panel.py finds no reason it could not."""
    said = _run([venv / "python", "-c", "import json; from app.window.no_panel import "
                 "no_wheel, panel_problem; print(json.dumps([no_wheel(), panel_problem()]))"],
                elsewhere)
    reason, problem = json.loads(said.stdout)
    if reason is None:
        assert problem is None, problem
    else:  # (a Python 3.10 here)
        assert problem.startswith(f"the tuning panel needs imgui-bundle==1.93.0, and {reason};")


def _render(cmd: list, cwd: Path, ticks: str | None = None) -> np.ndarray:
    """Run `cmd` + RENDER_ARGS in `cwd` (with --ticks replaced by `ticks`); its PNG as an array."""
    args = list(RENDER_ARGS)
    if ticks is not None:
        args[args.index("--ticks") + 1] = ticks
    _run([*cmd, *args], cwd)
    png = cwd / "x.png"
    assert png.is_file()
    with Image.open(png) as im:
        assert im.size == (760, 1280)
        pixels = np.asarray(im.convert("RGB")).astype(int)
    png.unlink()
    return pixels


def test_installed_frost_renders_the_touch_from_another_folder(venv, elsewhere):
    frosted = _render([venv / "frost"], elsewhere)
    bare = _render([venv / "frost"], elsewhere, ticks="0")
    changed = np.argwhere((frosted != bare).any(axis=2))
    assert len(changed) > 1000, "the 50 ticks of frost left the picture as it was at tick 0"
    (y0, x0), (y1, x1) = changed.min(axis=0), changed.max(axis=0)
    assert x0 < TOUCH[0] < x1 and y0 < TOUCH[1] < y1, "the frost is not around the touch"
    # the checkout's own render is the oracle for the installed shaders and background
    assert np.array_equal(frosted, _render([sys.executable, "-m", "app"], elsewhere))


def test_installed_frost_serve_answers_every_file_of_the_page_s_shell(venv, elsewhere):
    """The installed app's files (the worker's list: the page, its modules, icons, shaders,
    backdrops) all come from the installed package, the page's as the checkout has them."""
    served = ServeProcess("--port", "0", "--max-seconds", "120", cwd=elsewhere,
                          frost=(str(venv / "frost"),),
                          env={"PYTHONPATH": None, "PYTHONHOME": None, "VIRTUAL_ENV": None})
    try:
        url = served.url
        with urllib.request.urlopen(url + "sw.js", timeout=30) as r:
            shell = json.loads(r.read().decode().split("\n", 1)[0][len("const SHELL = "):-1])
        web = ROOT / "app" / "web"
        assert {"web/install.js", "web/icons/icon-512.png", "shaders/ice.frag"} <= set(shell["files"])
        for file in shell["files"]:
            with urllib.request.urlopen(url + file, timeout=30) as r:
                assert r.status == 200, file
                body = r.read()
            if file.startswith("web/"):
                assert body == (web / file[len("web/"):]).read_bytes(), file
        with urllib.request.urlopen(url + "manifest.webmanifest", timeout=30) as r:
            for icon in json.loads(r.read())["icons"]:
                with urllib.request.urlopen(url + icon["src"], timeout=30) as got:
                    assert got.status == 200, icon
    finally:
        served.stop()
