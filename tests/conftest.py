"""The one place tests make an OpenGL context: headless (EGL), shared by the session."""

from __future__ import annotations

import atexit
import importlib.util
import os
import shutil
import sys
import tempfile

import pytest
from hypothesis import settings
from hypothesis.configuration import set_hypothesis_home_dir
from support.checkout import checkout_files

# The tuning panel's library is installed only where it has a wheel (Python 3.11 on; on a
# Mac Apple silicon with macOS 14 on); without it the window runs without the panel
# (tests/test_window_parts.py, tests/test_requirements.py check that), and its tests cannot run.
collect_ignore = [] if importlib.util.find_spec("imgui_bundle") else [
    "test_panel.py", "test_imgui_renderer.py", "test_panel_e2e.py"]

# No example database: tests never write into the checkout (.hypothesis/). No deadline:
# the machine is shared and loaded; speed is the benchmarks' business.
settings.register_profile("frost", database=None, deadline=None)
# A deeper search for the property tests, to run by hand after a change to what they
# cover: FROST_HYPOTHESIS=frost-deep .venv/bin/python -m pytest tests/test_inputs.py
settings.register_profile("frost-deep", settings.get_profile("frost"), max_examples=3000)
# `make quick`'s (a change's inner loop): a fifth of the examples; the full suite keeps 100.
settings.register_profile("frost-quick", settings.get_profile("frost"), max_examples=20)
settings.load_profile(os.environ.get("FROST_HYPOTHESIS", "frost"))
_HYPOTHESIS_HOME = tempfile.mkdtemp(prefix="frost-hypothesis-")
set_hypothesis_home_dir(_HYPOTHESIS_HOME)  # its caches too
atexit.register(shutil.rmtree, _HYPOTHESIS_HOME, True)
# `frost serve --host 0.0.0.0` keeps its token and local authority in the user's config
# folder: tests (and the servers they start, which inherit this) keep theirs in a folder of
# the run's own, never the user's.
_CONFIG_HOME = tempfile.mkdtemp(prefix="frost-config-")
os.environ["XDG_CONFIG_HOME"] = _CONFIG_HOME
atexit.register(shutil.rmtree, _CONFIG_HOME, True)


@pytest.fixture(scope="session")
def gl_ctx():
    """A standalone OpenGL context. None is a failure, not a skip: EGL is a dependency
    (Makefile's APT_PKGS), so a missing context would hide every GL test."""
    from app.tools.offscreen import make_context

    try:
        ctx = make_context()
    except RuntimeError as err:
        pytest.fail(f"{err} (apt-get install libegl1 libgles2 libgl1; `make test` does)")
    yield ctx
    ctx.release()


@pytest.fixture(scope="session")
def subprocesses():
    """Asked for by a test that starts Python in a subprocess (`frost`, `frost serve`,
    pytest, `python -c`), directly or through a fixture: it marks the test `subprocess`,
    which `make quick` leaves out (a Python's start and imports are most of such a test).
    A test that starts one without asking fails, saying so (`_starts_python` below)."""


@pytest.fixture(scope="session")
def window_tools(subprocesses):
    """Xvfb and xdotool, for the tests that run the window on a display of their own
    (support.window). They are dependencies (Makefile's APT_PKGS): missing is a failure."""
    missing = [t for t in ("Xvfb", "xdotool") if shutil.which(t) is None]
    if missing:
        pytest.fail(f"{', '.join(missing)} missing: apt-get install xvfb xauth xdotool "
                    "(`make test` does)")


@pytest.fixture(scope="session", autouse=True)
def checkout_stays_clean():
    """Tests write under tmp_path only: fail the run if the checkout gained files."""
    before = checkout_files()
    yield
    added = sorted(checkout_files() - before)
    assert not added, f"the tests wrote into the checkout: {added[:10]}"


# ---- validation runs: long statistical checks, run with --deep (make test-deep) -------------

def pytest_addoption(parser):
    parser.addoption("--deep", action="store_true",
                     help="also run the validation runs (marked `validation`: minutes)")


# What a test needs is what it uses: a test is marked from its fixtures (those it asks for
# and theirs), so that `-m "not browser"` leaves out every test that opens Chromium or
# WebKit however it came to, and no marker is forgotten by hand.
FIXTURE_MARKS = {"gl_ctx": "gl", "window_tools": "window", "pw": "browser",
                 "webkit": "browser", "subprocesses": "subprocess"}


@pytest.hookimpl(tryfirst=True)  # before `-m` selects by them
def pytest_collection_modifyitems(config, items):
    for item in items:
        for fixture in FIXTURE_MARKS.keys() & set(item.fixturenames):
            item.add_marker(FIXTURE_MARKS[fixture])
    items[:] = slowest_modules_first(items)
    if config.getoption("--deep"):
        return
    skip = pytest.mark.skip(reason="a validation run: `make test-deep` (pytest --deep) runs it")
    for item in items:
        if "validation" in item.keywords:
            item.add_marker(skip)


# The markers of the costliest tests, costliest first: a module runs as early as its
# costliest test says, so that two workers start on the long ones and end on short ones
# together, not one worker alone on a long test at the end.
COSTLIEST = ("slow", "window", "browser", "subprocess", "gl")


def slowest_modules_first(items: list) -> list:
    """`items` with the modules ordered by the costliest marker of their tests
    (COSTLIEST), each module's tests in their own order, modules of a kind in theirs."""
    def cost(item) -> int:
        return next((n for n, mark in enumerate(COSTLIEST) if item.get_closest_marker(mark)),
                    len(COSTLIEST))

    module_cost: dict = {}
    for item in items:
        module_cost[item.path] = min(module_cost.get(item.path, len(COSTLIEST)), cost(item))
    first = {module: n for n, module in enumerate(module_cost)}
    return sorted(items, key=lambda item: (module_cost[item.path], first[item.path]))


# The test running in this process, while it runs (set-up and teardown included).
_RUNNING: list = [None]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _RUNNING[0] = item
    yield
    _RUNNING[0] = None


def _runs_python(executable, argv) -> bool:
    """Whether a subprocess.Popen of `argv` (or `executable`) starts Python: this
    interpreter, any `python*`, a script (`.py`) or the `frost` command."""
    first = executable or (argv.split()[0] if isinstance(argv, (str, bytes)) else argv[0])
    first = os.fsdecode(first)
    name = os.path.basename(first)
    return (name.startswith("python") or name == "frost" or name.endswith(".py")
            or os.path.realpath(first) == os.path.realpath(sys.executable))


def _starts_python(event: str, args: tuple) -> None:
    """An audit hook: a test that starts Python in a subprocess without asking for
    `subprocesses` fails there, saying so, so that no such test is left in `make quick`."""
    item = _RUNNING[0]
    if event != "subprocess.Popen" or item is None or item.get_closest_marker("subprocess"):
        return
    if _runs_python(args[0], args[1]):
        raise RuntimeError(f"{item.nodeid} starts Python in a subprocess ({args[1]!r:.80}) "
                           "without asking for the `subprocesses` fixture (tests/conftest.py)")


sys.addaudithook(_starts_python)


@pytest.fixture(scope="session")
def deep(request) -> bool:
    """True under --deep: tests that scale their run (ticks, seeds) take the long one."""
    return bool(request.config.getoption("--deep"))


@pytest.fixture
def serve(tmp_path, subprocesses):
    """Starts `frost serve` (support.serve.phone_serve) with these arguments, in `folder`
    (default the test's tmp_path), as many as a test asks for; each stopped after the test."""
    from support.serve import phone_serve

    started: list = []

    def start(*args: str, folder=None):
        s = phone_serve(folder or tmp_path, *args)
        started.append(s)
        return s

    yield start
    for s in started:
        s.stop()


@pytest.fixture
def phones(browser, serve):
    """Opens pages on emulated phones; closes them before the server stops (`serve` is
    torn down after this)."""
    from support.phone import PHONE, open_page

    contexts = []

    def open_(url: str):
        context = browser.new_context(**PHONE)
        contexts.append(context)
        return open_page(context, url)

    yield open_
    for context in contexts:
        context.close()


@pytest.fixture(scope="module")
def pw():
    """One Playwright for each test module that asks: its browser, its persistent profiles
    (two in one thread cannot both run)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        yield p


@pytest.fixture(scope="module")
def browser(pw):
    """Headless Chromium (support.phone.launch_browser) of the module's Playwright."""
    from support.phone import launch_browser

    b = launch_browser(pw)
    yield b
    b.close()


@pytest.fixture(scope="module")
def webkit(tmp_path_factory):
    """WebKit, the iPhone's engine, for a test module (support.webkit.WebKit: WebKitWebDriver
    and WebKitGTK's MiniBrowser on an Xvfb display of their own): one session a module."""
    from support.webkit import WebKit

    w = WebKit(tmp_path_factory.mktemp("webkit"))
    yield w
    w.close()
