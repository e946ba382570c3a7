"""The Makefile's stages, read from `make -n` (what make would run, run by nothing): `make
run` sets up the demo's packages and nothing of the tests', `make test` adds the test stack
on top, `make serve` runs `frost serve`; a stage already set up is not set up again; the suite's
bytecode goes into the virtualenv."""

from __future__ import annotations

import os
import subprocess

import pytest
from support import ROOT
from support.make import planned

# What the demo needs from Debian, and what only the tests add (written out by hand).
DEMO_PACKAGES = ["libegl1", "libgles2", "libgl1"]
TEST_PACKAGES = ["xvfb", "xauth", "xdotool", "glslang-tools", "chromium", "libnss3-tools", "nodejs",
                 "webkit2gtk-driver"]
RUNTIME_INSTALL = "pip install -q -e .;"
DEV_INSTALL = "pip install -q -e '.[dev]'"


def words(text: str) -> set[str]:
    return set(text.replace(";", " ").split())


def test_make_run_sets_up_the_demo_and_nothing_of_the_tests(tmp_path):
    plan = planned("run", tmp_path / "venv")
    assert set(DEMO_PACKAGES) <= words(plan)
    assert RUNTIME_INSTALL in plan
    named = [w for w in (*TEST_PACKAGES, "playwright", "[dev]") if w in plan]
    assert named == []
    assert plan.splitlines()[-1].split() == [f"{tmp_path}/venv/bin/python", "-m", "app"]


def test_make_test_adds_the_test_stack_on_top_of_the_demos(tmp_path):
    plan = planned("test", tmp_path / "venv")
    assert set(DEMO_PACKAGES + TEST_PACKAGES) <= words(plan)
    assert 0 <= plan.index(RUNTIME_INSTALL) < plan.index(DEV_INSTALL)
    assert plan.splitlines()[-1].split()[1:3] == ["-m", "pytest"]


@pytest.mark.parametrize("target", ["test", "lint"])
def test_a_stage_set_up_is_not_set_up_again(tmp_path, target):
    """With the demo's stage done, `make test` (and `make lint`, whose ruff and mypy are the
    dev extra's) installs the dev extra alone; with both done, nothing."""
    venv = tmp_path / "venv"
    venv.mkdir()
    (venv / ".installed-run").touch()  # newer than pyproject.toml and setup.py
    plan = planned(target, venv)
    assert DEV_INSTALL in plan and RUNTIME_INSTALL not in plan
    (venv / ".installed-test").touch()
    assert "pip install" not in planned(target, venv)


def test_make_serve_runs_frost_serve_on_the_demos_stage(tmp_path):
    plan = planned("serve", tmp_path / "venv")
    assert RUNTIME_INSTALL in plan and DEV_INSTALL not in plan
    assert plan.splitlines()[-1].split() == [f"{tmp_path}/venv/bin/python", "-m", "app", "serve"]


def test_what_make_would_run_reads_the_same_when_the_tests_run_under_make(tmp_path, monkeypatch):
    """`make test` runs the suite inside make, whose level and flags its children inherit:
    the plan read then is the one a user's make prints."""
    alone = planned("test", tmp_path / "venv")
    monkeypatch.setenv("MAKELEVEL", "1")
    monkeypatch.setenv("MAKEFLAGS", " -- VENV=elsewhere")
    assert planned("test", tmp_path / "venv") == alone


@pytest.mark.parametrize("target", ["test", "quick"])
def test_the_suite_writes_its_bytecode_into_the_virtualenv(tmp_path, target):
    """The suite's Pythons write bytecode (each would compile the app's modules again, and
    pytest rewrite every test module, where PYTHONDONTWRITEBYTECODE is set), into the
    virtualenv's folder, not the checkout: the environment `make test` and `make quick` run
    the suite in, read by a stand-in for the virtualenv's Python."""
    venv = tmp_path / "venv"
    (venv / "bin").mkdir(parents=True)
    for stage in (".installed-run", ".installed-test"):  # (both stages set up)
        (venv / stage).touch()
    python = venv / "bin" / "python"
    python.write_text('#!/bin/sh\necho "[$PYTHONDONTWRITEBYTECODE] [$PYTHONPYCACHEPREFIX]"\n',
                      encoding="utf-8")
    python.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
    done = subprocess.run(["make", "-s", target, f"VENV={venv}"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60, env={**env, "PYTHONDONTWRITEBYTECODE": "1"})
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == f"[] [{venv}/pycache]"


def test_the_test_stage_compiles_the_suites_bytecode_where_the_suite_reads_it(tmp_path):
    """Setting up the test stack ends with a collection of the suite that writes its
    bytecode into the folder the suite's run then reads it from, whichever target set the
    stage up: `make lint` does on CI (.ci/run), then `make test` runs the suite. Stand-ins
    for the virtualenv's Python, ruff and mypy write down how each call was made."""
    venv = tmp_path / "venv"
    (venv / "bin").mkdir(parents=True)
    (venv / ".installed-run").touch()  # (the demo's stage set up, the tests' not)
    calls = tmp_path / "calls"
    for tool in ("python", "ruff", "mypy"):
        (venv / "bin" / tool).write_text(
            f'#!/bin/sh\necho "{tool} $* [$PYTHONDONTWRITEBYTECODE] [$PYTHONPYCACHEPREFIX]" >> {calls}\n',
            encoding="utf-8")
        (venv / "bin" / tool).chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
    for target in ("lint", "test"):
        done = subprocess.run(["make", "-s", target, f"VENV={venv}"], cwd=ROOT, capture_output=True,
                              text=True, timeout=120, env={**env, "PYTHONDONTWRITEBYTECODE": "1"})
        assert done.returncode == 0, done.stdout + done.stderr
    made = calls.read_text(encoding="utf-8").splitlines()
    warm = [c for c in made if c.startswith("python -m pytest --collect-only")]
    run = [c for c in made if c.startswith("python -m pytest -n")]
    assert len(warm) == 1 and len(run) == 1, made
    assert made.index(warm[0]) < made.index(run[0])
    assert warm[0].endswith(f"[] [{venv}/pycache]") and run[0].endswith(f"[] [{venv}/pycache]"), made
