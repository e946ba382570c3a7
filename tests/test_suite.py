"""The suite's own rules: a test is marked from the fixtures it uses, an unknown marker is
refused, a test that hangs fails by name at the per-test timeout, a test that starts Python
in a subprocess says so, `make quick` leaves out the browser, the window and the
subprocesses, and no test module imports another (their shared helpers are
tests/support's). The oracles: the tests' own signatures, read by hand below, and pytest
run on files written for the purpose."""

from __future__ import annotations

import ast
import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import settings
from support import ROOT
from support.make import planned

# A plugin that prints each collected test's markers, one JSON line a test.
MARKERS_PLUGIN = """
import json

def pytest_collection_finish(session):
    for item in session.items:
        print("MARKS", json.dumps([item.nodeid, sorted(m.name for m in item.iter_markers())]))
"""


def pytest_run(*args: str, cwd: Path = ROOT, plugins: str | Path | None = None,
               timeout: float = 300) -> subprocess.CompletedProcess:
    """pytest run in a subprocess (no cache written; `plugins`: the folders of importable
    plugins, named with -p in `args`, as a path list)."""
    env = {**os.environ, **({"PYTHONPATH": str(plugins)} if plugins else {})}
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *args],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def collected_marks(tmp_path: Path, *args: str) -> dict[str, set[str]]:
    """Each test that `pytest --collect-only *args` collects: its markers' names."""
    (tmp_path / "markprint.py").write_text(MARKERS_PLUGIN, encoding="utf-8")
    run = pytest_run("--collect-only", "-q", "-p", "markprint", *args, plugins=tmp_path)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    found = [json.loads(line[len("MARKS "):]) for line in run.stdout.splitlines()
             if line.startswith("MARKS ")]
    return {nodeid: set(marks) for nodeid, marks in found}


@pytest.mark.usefixtures("subprocesses")
def test_a_test_is_marked_from_the_fixtures_it_uses(tmp_path):
    """gl_ctx asked for directly or through a fixture of the test's module makes a test
    `gl`; window_tools (asked for by a module's usefixtures) `window`; pw, through the
    browser fixture, `browser`. A test that uses none of them gets none of the three."""
    marks = collected_marks(tmp_path, "tests/test_look.py", "tests/test_render.py",
                            "tests/test_window_e2e.py", "tests/test_sim.py")
    look, render = "tests/test_look.py::", "tests/test_render.py::"
    assert "gl" in marks[look + "test_paper_presets_unchanged[c-2]"]  # gl_ctx
    assert "gl" in marks[look + "test_glass_colour_is_even_along_a_link"]  # fern_glass(gl_ctx)
    assert "gl" in marks[render + "test_clear_glass_is_the_background"]
    assert "window" in marks["tests/test_window_e2e.py::test_esc_exits_with_status_zero"]
    needs = {"gl", "window", "browser"}
    assert not needs & marks[render + "test_missing_background_is_a_clear_error"]
    sim = [m for nodeid, m in marks.items() if nodeid.startswith("tests/test_sim.py::")]
    assert sim and not any(needs & m for m in sim)


@pytest.mark.usefixtures("subprocesses")
def test_each_fixture_marks_the_tests_that_use_it_and_only_those(tmp_path):
    """Tests written for the purpose, under tests/conftest.py (loaded as a plugin): each
    marker comes from its fixture, asked for directly, through another fixture or by
    usefixtures."""
    (tmp_path / "test_uses.py").write_text(
        "import pytest\n\n"
        "def test_plain(tmp_path):\n    pass\n\n"
        "def test_gl(gl_ctx):\n    pass\n\n"
        "@pytest.mark.usefixtures('window_tools')\ndef test_window():\n    pass\n\n"
        "def test_browser(browser):\n    pass\n\n"
        "def test_phones(phones):\n    pass\n\n"
        "def test_webkit(webkit):\n    pass\n\n"
        "def test_subprocess(subprocesses):\n    pass\n\n"
        "def test_serve(serve):\n    pass\n", encoding="utf-8")
    (tmp_path / "markprint.py").write_text(MARKERS_PLUGIN, encoding="utf-8")
    run = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                     "-p", "conftest", "-p", "markprint", "--collect-only", "-q",
                     str(tmp_path / "test_uses.py"), cwd=tmp_path,
                     plugins=f"{tmp_path}{os.pathsep}{ROOT / 'tests'}")
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    marks = dict(json.loads(line[len("MARKS "):]) for line in run.stdout.splitlines()
                 if line.startswith("MARKS "))
    # the window runs the app in a subprocess, and the phones' page is `frost serve`'s
    assert marks == {"test_uses.py::test_plain": [], "test_uses.py::test_gl": ["gl"],
                     "test_uses.py::test_window": ["subprocess", "usefixtures", "window"],
                     "test_uses.py::test_browser": ["browser"],
                     "test_uses.py::test_phones": ["browser", "subprocess"],
                     "test_uses.py::test_webkit": ["browser"],
                     "test_uses.py::test_subprocess": ["subprocess"],
                     "test_uses.py::test_serve": ["subprocess"]}


@pytest.mark.usefixtures("subprocesses")
def test_a_test_that_starts_python_without_asking_fails_saying_so(tmp_path):
    """Starting Python (this interpreter, a script) in a subprocess takes the `subprocesses`
    fixture, so that `make quick` leaves the test out: without it the test fails, named, and
    the fixture named; with it, or for a program that is not Python, the test runs."""
    (tmp_path / "test_starts.py").write_text(
        "import subprocess, sys\n\n"
        "def test_unasked():\n    subprocess.run([sys.executable, '-c', 'pass'], check=True)\n\n"
        "def test_a_script(tmp_path):\n"
        "    (tmp_path / 'x.py').write_text('', encoding='utf-8')\n"
        "    subprocess.run([sys.executable, str(tmp_path / 'x.py')], check=True)\n\n"
        "def test_asked(subprocesses):\n"
        "    subprocess.run([sys.executable, '-c', 'pass'], check=True)\n\n"
        "def test_not_python():\n    subprocess.run(['true'], check=True)\n", encoding="utf-8")
    run = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                     "-p", "conftest", str(tmp_path / "test_starts.py"), cwd=tmp_path,
                     plugins=str(ROOT / "tests"))
    assert "2 failed, 2 passed" in run.stdout, run.stdout[-3000:]
    for name in ("test_unasked", "test_a_script"):
        assert f"FAILED test_starts.py::{name} - RuntimeError" in run.stdout, run.stdout[-3000:]
        assert re.search(rf"RuntimeError: test_starts.py::{name} starts Python in a subprocess "
                         r".* without asking for the `subprocesses` fixture", run.stdout)


@pytest.mark.usefixtures("subprocesses")
def test_make_quick_sets_up_the_test_stage_and_leaves_out_the_browser_and_the_window(tmp_path):
    """`make quick` installs what `make test` does, and its selection collects the plain
    tests of a module and none of the browser's, the window's, the wheel's or those that
    start `frost` in a subprocess; its property tests draw fewer examples than the suite's."""
    plan = planned("quick", tmp_path / "venv")
    assert 0 <= plan.index("pip install -q -e .;") < plan.index("pip install -q -e '.[dev]'")
    env, command = quick_command(plan)
    assert command[1:3] == ["-m", "pytest"]
    quick = settings.get_profile(env["FROST_HYPOTHESIS"])
    assert quick.database is None and quick.deadline is None
    assert 0 < quick.max_examples < settings.get_profile("frost").max_examples
    selection = command[command.index("-m", 3) + 1]
    marks = collected_marks(tmp_path, "-m", selection, "tests/test_page.py",
                            "tests/test_window_e2e.py", "tests/test_webkit_e2e.py",
                            "tests/test_package.py", "tests/test_sim.py", "tests/test_serve.py")
    assert {nodeid.split("::")[0] for nodeid in marks} == {"tests/test_sim.py", "tests/test_serve.py"}
    serve = {nodeid.split("::")[1].split("[")[0] for nodeid in marks
             if nodeid.startswith("tests/test_serve.py")}
    assert "test_a_touch_grows_frost_on_the_page" in serve  # aiohttp's client, in process
    assert "test_frost_serve_from_the_command_line" not in serve  # the command, a subprocess


def quick_command(plan: str) -> tuple[dict[str, str], list[str]]:
    """The environment `make quick` sets (its leading NAME=VALUE words) and its command."""
    words = shlex.split(plan.splitlines()[-1])
    n = 0
    while re.fullmatch(r"[A-Z_]+=\S*", words[n]):
        n += 1
    return dict(w.split("=", 1) for w in words[:n]), words[n:]


@pytest.mark.usefixtures("subprocesses")
def test_an_unknown_marker_is_refused_by_name(tmp_path):
    (tmp_path / "test_typo.py").write_text(
        "import pytest\n\n@pytest.mark.brower\ndef test_x():\n    pass\n", encoding="utf-8")
    run = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                     str(tmp_path / "test_typo.py"), cwd=tmp_path)
    assert run.returncode != 0
    assert "'brower' not found in `markers` configuration option" in run.stdout, run.stdout


@pytest.mark.usefixtures("subprocesses")
def test_a_test_that_hangs_fails_at_the_timeout_saying_which(tmp_path):
    """A test waiting on what never comes (an event nobody sets) fails at the timeout,
    named, and the run goes on to the next test."""
    (tmp_path / "test_hangs.py").write_text(
        "import threading\n\n"
        "def test_waits_for_ever():\n    threading.Event().wait()\n\n"
        "def test_after_it():\n    pass\n", encoding="utf-8")
    run = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                     "-o", "timeout=2", str(tmp_path / "test_hangs.py"), cwd=tmp_path)
    assert run.returncode == 1, run.stdout
    assert "FAILED test_hangs.py::test_waits_for_ever - Failed: Timeout" in run.stdout, run.stdout
    assert "1 failed, 1 passed" in run.stdout, run.stdout
    # and without -o, the project's own timeout is in force: a generous one
    said = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                      "--collect-only", str(tmp_path / "test_hangs.py"), cwd=tmp_path).stdout
    timeout = re.search(r"^timeout: ([\d.]+)s$", said, re.M)
    assert timeout and float(timeout.group(1)) >= 60, said


def test_no_test_module_imports_another():
    """Test modules share helpers through tests/support, never by importing each other
    (which runs the other's module-level set-up, and ties the two)."""
    tests = ROOT / "tests"
    modules = {p.stem for p in tests.glob("test_*.py")} | {"conftest"}
    found = []
    for path in sorted([*tests.glob("*.py"), *tests.glob("support/*.py")]):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or "", *(f"{node.module}.{a.name}" for a in node.names)]
                     if isinstance(node, ast.ImportFrom) else [])
            found += [f"{path.name}: {name}" for name in names
                      if name.removeprefix("tests.") in modules]
    assert found == []


@pytest.mark.usefixtures("subprocesses")
def test_the_costliest_modules_run_first_each_in_its_own_order(tmp_path):
    """Modules ordered by their costliest test's marker (slow, window, browser, subprocess,
    gl, then the rest), so that the workers start on the long tests; a module's own tests
    in the file's order (the oracle: the order of its test functions in its source)."""
    files = ["tests/test_sim.py", "tests/test_render.py", "tests/test_package.py",
             "tests/test_window_e2e.py", "tests/test_suite.py"]
    together = list(collected_marks(tmp_path, *files))
    modules = [nodeid.split("::")[0] for nodeid in together]
    runs = [m for n, m in enumerate(modules) if n == 0 or modules[n - 1] != m]
    # slow; window; subprocess (frost render's runs, then this module's pytest runs, in the
    # order given); plain
    assert runs == ["tests/test_package.py", "tests/test_window_e2e.py", "tests/test_render.py",
                    "tests/test_suite.py", "tests/test_sim.py"]
    # a module whose tests differ in cost (gl, subprocess, plain) keeps the file's order
    names = [n.split("::")[1].split("[")[0] for n in together if n.startswith("tests/test_render.py::")]
    source = ast.parse((ROOT / "tests" / "test_render.py").read_text(encoding="utf-8"))
    assert [k for n, k in enumerate(names) if n == 0 or names[n - 1] != k] == [
        node.name for node in source.body
        if isinstance(node, ast.FunctionDef) and node.name.startswith("test_")]


@pytest.mark.usefixtures("subprocesses")
def test_what_is_made_once_a_run_is_made_by_one_worker_and_shared(tmp_path):
    """support.shared.made_once under two workers (the wheel's and the virtualenv's way):
    a module-scoped fixture on each worker asks, one makes, both use what it made."""
    log = tmp_path / "made.log"
    (tmp_path / "test_shares.py").write_text(
        "import os\n\nimport pytest\nfrom support.shared import made_once\n\n\n"
        "@pytest.fixture(scope='module')\ndef thing(tmp_path_factory):\n"
        "    def make(folder):\n"
        f"        with open({str(log)!r}, 'a', encoding='utf-8') as f:\n"
        "            f.write(os.environ['PYTEST_XDIST_WORKER'] + '\\n')\n"
        "        (folder / 'x').write_text('made', encoding='utf-8')\n\n"
        "    return made_once(tmp_path_factory, 'thing', make)\n\n\n"
        "@pytest.mark.parametrize('i', range(8))\ndef test_uses(thing, i):\n"
        "    assert (thing / 'x').read_text(encoding='utf-8') == 'made'\n", encoding="utf-8")
    run = pytest_run("-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path), "-n", "2",
                     "-v", str(tmp_path / "test_shares.py"), cwd=tmp_path, plugins=str(ROOT / "tests"))
    assert "8 passed" in run.stdout, run.stdout[-3000:]
    assert "[gw0]" in run.stdout and "[gw1]" in run.stdout  # both workers used it
    assert len(log.read_text(encoding="utf-8").splitlines()) == 1
