"""Bad input, generated: whatever a user types on the command line or puts in a session
file either works or is refused with one line naming the problem (exit status 2 on the
command line, SessionError from the loader); nothing else escapes, and nothing loaded
fails later when it is replayed."""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st
from support.cli import assert_refused_in_one_line, run_main

from app.bench import render as bench
from app.cli import commands, main, paths, shared_options
from app.cli.parser import build_parser
from app.tools import figure8, figure_fern, maps
from app.tools import render_png as render
from app.tools import replay as replay_tool
from app.window import frost_window as window
from sim import PRESETS, FrostSim, Params, all_presets
from sim.io.files import one_line
from sim.io.session import SessionError, SessionLog, check_event
from sim.io.timeline import replay

REPLAY_RUN = replay_tool.run  # (before a test stubs it)

FIXTURE_OK = settings(suppress_health_check=[HealthCheck.function_scoped_fixture])

# ---- the command line -------------------------------------------------------------------

JUNK = ["", "nan", "-nan", "inf", "-inf", "1e999", "-1e999", "junk", "0", "-0", "-1", "1e-320",
        "on", "off", "3,4", "759.9999999999,1279.99999999", "760,0", "1,2,3", "1,2@3",
        "1,2,3@-1", "1,2,0@4", "nan,1@2", "1e308,1e308,1e308@0", "0,0:10,10@5", "0,0@5",
        "c-2", "candidate", "grid9", "9" * 30, "2.5", "4.0", "true"]
NUMBER_TEXT = st.one_of(
    st.sampled_from(JUNK),
    st.integers(-10**12, 10**12).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(0, 2000).map(lambda v: f"{v},{v * 0.6}"),
    st.text(max_size=6))
PATH_OPTIONS = {"--out", "--screenshot-dir", "--session-dir"}
# Each command (None: the window) and the positionals it needs: OUT is a fresh folder,
# SESSION a session file.
COMMANDS = {None: [], "render": [], "replay": ["SESSION"], "figure8": ["OUT/f.png"],
            "figure": ["fern", "OUT/f.png"], "maps": ["OUT/maps"], "bench render": []}


def command_parser(command: str | None):
    parser = build_parser()
    for word in (command or "").split():
        parser = parser.commands[word]
    return parser


def options_of(command: str | None) -> tuple[list[str], list[str]]:
    """The command's options that take a value (paths aside: tested on their own) and its flags."""
    actions = [a for a in command_parser(command)._actions if a.option_strings and a.dest != "help"]
    return ([a.option_strings[-1] for a in actions if a.nargs != 0 and a.option_strings[-1]
             not in PATH_OPTIONS], [a.option_strings[-1] for a in actions if a.nargs == 0])


@st.composite
def command_lines(draw) -> list[str]:
    command = draw(st.sampled_from(list(COMMANDS)))
    valued, flags = options_of(command)
    typed = st.tuples(st.sampled_from(valued), NUMBER_TEXT).map(lambda ov: f"{ov[0]}={ov[1]}")
    other = st.sampled_from([*flags, "--headless", "--bogus", "stray", "render"])
    head = command.split() if command else []
    return head + COMMANDS[command] + draw(st.lists(st.one_of(typed, other), max_size=6))


@pytest.fixture
def stubbed(monkeypatch):
    """main() with every command's work replaced by a recorder: no window, no GL, no files."""
    calls = []

    def record(args, params=None):
        calls.append((args, params))
        return 0

    for module in (figure8, figure_fern, maps, render, replay_tool, window, bench):
        monkeypatch.setattr(module, "run", record)
    monkeypatch.setattr(commands, "display_problem", lambda: None)  # as if a display works
    return calls


def assert_runnable(args, params) -> None:
    """What every command relies on once the command line is accepted."""
    assert params is None or isinstance(params, Params)
    assert isinstance(args.seed, int) and args.seed >= 0
    ticks = getattr(args, "ticks", 0)
    assert isinstance(ticks, int) and ticks >= 0 or ticks is None and args.command == "replay"
    touches = getattr(args, "touch", [])
    for x, y in touches:
        assert 0 <= x < 760 and 0 <= y < 1280
    assert len(touches) <= 1 or args.command != "figure8"
    for m in getattr(args, "melt", []):
        check_event({**m, "r": args.melt_radius if m["r"] is None else m["r"]})
    if getattr(args, "melt", None) or getattr(args, "melt_path", None):
        assert touches or args.window_mode
    for name in ("scale", "max_seconds"):
        value = getattr(args, name, None)
        assert value is None or math.isfinite(value) and value >= 0


def with_paths(argv: list[str], folder: Path) -> list[str]:
    """argv with OUT a folder under `folder` and SESSION a session file there."""
    session = folder / "s.json"
    if not session.exists():
        SessionLog(0, {}).save(session)
    return [a.replace("OUT", str(folder / "out")).replace("SESSION", str(session)) for a in argv]


@FIXTURE_OK
@given(argv=command_lines())
@example(argv=["--hc=nan"])
@example(argv=["--humidity=2.5"])
@example(argv=["--touch=759.9999999999,3"])
@example(argv=["--touch=nan,nan"])  # was silently ignored by the window
@example(argv=["--seed=-1"])  # numpy refused it with a traceback
@example(argv=["render", "--ticks=-5"])
@example(argv=["--scale=nan"])
@example(argv=["--max-seconds=-1"])
@example(argv=["render", "--melt=1e308,1e308,1e308@0", "--touch=1,1"])  # x + r overflowed in melt
@example(argv=["render", "--melt-path=nan,0:1,1@2", "--touch=1,1"])
@example(argv=["render", "--melt=1,2,0@3", "--touch=1,1"])  # a zero radius
@example(argv=["--melt-radius=0"])  # zero radius, scale: refused by name, never a crash
@example(argv=["--scale=0"])
@example(argv=["render", "--melt-radius=-0", "--touch=1,1"])
@example(argv=["figure8", "OUT/f.png", "--touch=1,1", "--touch=2,2"])
@example(argv=["bench", "render", "--frames=0"])
def test_any_command_line_runs_or_is_refused_in_one_line(stubbed, tmp_path, argv):
    stubbed.clear()
    status, err = run_main(with_paths(argv, tmp_path))
    event("ran" if stubbed else "refused")
    if stubbed:
        assert status == 0, err
        assert_runnable(*stubbed[0])
    else:
        assert_refused_in_one_line(status, err)


@pytest.mark.parametrize("argv, named", [
    (["--headless", "--touch", "1,1"], "--headless"), (["--replay", "SESSION"], "--replay"),
    (["--figure8", "OUT/f.png"], "--figure8"), (["--figure", "fern", "OUT/f.png"], "--figure"),
    (["--export-maps=OUT"], "--export-maps"), (["render", "--screenshot", "OUT/x.png"], "--screenshot"),
    (["render", "--headless"], "--headless"), (["--active_radius", "150"], "--active_radius")])
def test_the_old_mode_options_are_refused_in_one_line(stubbed, tmp_path, argv, named):
    status, err = run_main(with_paths(argv, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, named)


@pytest.mark.parametrize("argv, named", [
    (["figure8", "OUT/f.png", "--touch", "1,1", "--touch", "2,2"], "--touch"),
    (["render", "--melt", "10,10@3"], "--melt"),
    (["render", "--melt-path", "0,0:9,9@3"], "--melt-path"),
    (["--seed", "3", "render"], "render"),
    (["replay", "SESSION", "--out", "OUT/x.png", "--scale", "1"], "--scale"),
    (["replay", "SESSION", "--headless", "--session-dir", "OUT"], "--session-dir"),
    (["figure8", "OUT/f.png", "--preset", "c-2"], "--preset"),
    (["maps", "OUT", "--melt", "1,1@2"], "--melt"),
    (["replay", "SESSION", "--touch", "1,1"], "--touch")])
def test_combinations_that_make_no_sense_are_refused_in_one_line(stubbed, tmp_path, argv, named):
    status, err = run_main(with_paths(argv, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, named)


@pytest.mark.parametrize("hc", ["0.03", "0.01", "1e-300"])
@pytest.mark.parametrize("head", [[], ["render"], ["maps", "OUT"]])
def test_an_hc_below_its_floor_is_refused_in_one_line_naming_it(stubbed, tmp_path, hc, head):
    status, err = run_main(with_paths([*head, "--hc", hc], tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, f"hc={float(hc)!r}", "[1.0, 16.0]")


DEFAULT_STEP = 5.0  # px: the step every look keeps where its hc allows (sim/params.py)


@pytest.mark.parametrize("hc", ["1", "3", "4.5"])
@pytest.mark.parametrize("head", [[], ["render"], ["maps", "OUT"], ["figure", "fern", "OUT/f.png"],
                                  ["render", "--preset", "c-2"], ["render", "--window-frost"]])
def test_an_hc_below_the_default_step_takes_step_with_it(stubbed, tmp_path, head, hc):
    assert Params.preset("fern").step == Params.preset("c-2").step == DEFAULT_STEP
    status, err = run_main(with_paths([*head, "--hc", hc], tmp_path))
    assert status == 0 and err == "", err
    params = stubbed[0][1]
    assert params.hc == float(hc) and params.step == float(hc)  # walkers never step over hc


@pytest.mark.parametrize("head", [[], ["render"], ["figure8", "OUT/f.png"]])
def test_a_step_above_a_given_hc_is_refused_naming_both(stubbed, tmp_path, head):
    status, err = run_main(with_paths([*head, "--hc", "3", "--step", "4"], tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, "step=4.0 must not exceed hc=3.0")


@pytest.mark.parametrize("hc", [1.0, 3.0, 12.0])
def test_figure8_fits_each_presets_step_to_an_hc_given(hc):
    args = build_parser().parse_args(["figure8", "f.png", "--hc", str(hc)])
    overrides = figure8.preset_overrides(args)
    for name in PRESETS:
        params = Params.preset(name, **overrides)
        assert params.hc == hc and params.step == min(DEFAULT_STEP, hc)


def test_figure8_refuses_a_preset_its_options_break_before_drawing(monkeypatch, capsys):
    """D 0.5 suits the default look's hc (7) but not a-1's (10: at most 16 particles a
    link), so only figure8's own presets can tell."""
    monkeypatch.setattr(figure8, "make_context", lambda: pytest.fail("drew"))
    args = build_parser().parse_args(["figure8", "f.png", "--D", "0.5"])
    assert figure8.run(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("frost: error: preset a-1 ") and "D=0.5" in err


def test_a_window_frost_render_melts_with_no_touch(stubbed):
    status, err = run_main(["render", "--window-frost", "--melt", "10,10@3"])
    assert status == 0 and len(stubbed) == 1, err


@pytest.mark.parametrize("head", [[], ["render"], ["maps", "OUT"], ["figure", "fern", "OUT/f.png"]])
def test_a_kebab_case_override_reaches_the_parameters(stubbed, tmp_path, head):
    status, err = run_main(with_paths([*head, "--active-radius", "150", "--tip-hits=3"], tmp_path))
    assert status == 0, err
    args, params = stubbed[0]
    assert params.active_radius == 150.0 and params.tip_hits == 3 and args.active_radius == 150.0
    assert params.hc == Params.preset("fern").hc  # the rest is the default preset's


def test_figure8_passes_its_overrides_by_their_parameter_names(stubbed, tmp_path):
    status, err = run_main(with_paths(["figure8", "OUT/f.png", "--neighbor-search", "grid9"],
                                      tmp_path))
    assert status == 0, err
    assert stubbed[0][0].neighbor_search == "grid9"


@pytest.mark.parametrize("env, words", [
    ({}, "DISPLAY is unset"), ({"DISPLAY": ""}, "DISPLAY set but empty"),
    ({"DISPLAY": "", "WAYLAND_DISPLAY": ""}, "DISPLAY and WAYLAND_DISPLAY set but empty")])
def test_no_display_is_worded_as_the_environment_has_it(env, words):
    assert commands.no_display_words(env) == words


def test_a_headless_replay_leaves_the_parameters_to_the_session(stubbed, tmp_path, monkeypatch):
    monkeypatch.setattr(commands, "display_problem", lambda: "DISPLAY is unset")
    status, err = run_main(with_paths(["replay", "SESSION"], tmp_path))
    assert status == 0, err
    assert stubbed[0][0].replay.endswith("s.json") and stubbed[0][0].ticks is None


# ---- help ---------------------------------------------------------------------------------

OVERRIDES = {"--hc", "--D", "--humidity", "--water-budget", "--step", "--active-radius", "--bump",
             "--max-height", "--grid-spacing", "--feature-width", "--feature-height",
             "--neighbor-search", "--replenish", "--grow", "--grains", "--drift", "--tip-hits",
             "--side-hits", "--side-gap", "--long-jumps", "--launch", "--frame-sites",
             "--pane-sites", "--temperature", "--touch-water", "--look", "--order-hits",
             "--max-order", "--water-far", "--near-water", "--vapour-var", "--frame-chill"}
WEATHER = {"--weather", "--weather-api", "--geocoding-api", "--glazing", "--room-temperature",
           "--room-humidity"}
HELP_LISTS = {
    "replay": {"--help", "--params", "--headless", "--ticks", "--out", "--melt-radius", "--session-dir",
               "--screenshot-dir", "--scale", "--max-seconds", "--background"},
    "figure8": {"--help", "--params", "--seed", "--ticks", "--touch", "--background"} | OVERRIDES,
    "render": {"--help", "--preset", "--window-frost", "--params", "--seed", "--touch", "--ticks", "--out",
               "--melt", "--melt-path", "--melt-radius", "--background", "--clock"} | OVERRIDES | WEATHER,
    "bench render": {"--help", "--preset", "--params", "--seed", "--frames", "--cover", "--max-ticks",
                     "--background", "--record"},
    "maps": {"--help", "--preset", "--window-frost", "--params", "--seed", "--size", "--tile", "--normal-y",
             "--touch", "--ticks"} | OVERRIDES}


def help_text(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as stop:
        main([*argv, "--help"])
    assert stop.value.code == 0
    return out.getvalue()


def listed_options(text: str) -> dict[str, str]:
    """Each option the help lists (the lines that start with one) and its help text."""
    listed = {}
    for block in re.split(r"\n(?=  -)", text):
        found = re.match(r"  (?:-\w, )?(--[\w-]+)", block)
        if found:
            listed[found[1]] = " ".join(block.split())
    return listed


@pytest.mark.parametrize("command", list(HELP_LISTS))
def test_each_commands_help_lists_its_own_options(command):
    assert set(listed_options(help_text(command.split()))) == HELP_LISTS[command]


@pytest.mark.parametrize("command", [c for c in COMMANDS if c] + [""])
def test_each_option_says_its_default(command):
    text = help_text(command.split())
    for option, described in listed_options(text).items():
        assert option == "--help" or "default" in described, described
    assert ("keys in the window:" in text) == (command == ""), command  # the window's keys


def test_the_parser_builds_each_presets_parameters_once(monkeypatch):
    """Every command's help shows each preset's value of each parameter: read from one
    Params a preset, built once in a process, not one per parameter and command (two
    thousand a parser, which every `frost` start and every command line parsed builds).
    The oracle: the presets, counted by hand from all_presets()."""
    made: list[str] = []
    preset = Params.preset.__func__  # type: ignore[attr-defined]

    def counted(cls, name, **overrides):
        made.append(name)
        return preset(cls, name, **overrides)

    monkeypatch.setattr(Params, "preset", classmethod(counted))
    shared_options._preset.cache_clear()
    build_parser()
    assert sorted(made) == sorted(all_presets())
    build_parser()
    assert len(made) == len(all_presets())


def test_bench_sim_hands_its_arguments_to_the_simulations_benchmark():
    assert "--repeats" in help_text(["bench", "sim"]) and "--repeats" not in help_text(["bench"])


@pytest.mark.usefixtures("subprocesses")
def test_python_m_app_is_the_frost_command(tmp_path):
    frost = Path(sys.executable).with_name("frost")
    # A hard requirement, not a skip: the package declares the script (make test installs it).
    assert frost.exists(), f"no {frost}: install the package (pip install -e '.[dev]')"
    env = {**os.environ, "COLUMNS": "100"}
    as_script = subprocess.run([frost, "--help"], capture_output=True, text=True, env=env,
                               cwd=tmp_path, timeout=60)
    as_module = subprocess.run([sys.executable, "-m", "app", "--help"], capture_output=True,
                               text=True, env=env, cwd=tmp_path, timeout=60)
    assert as_script.returncode == as_module.returncode == 0, as_script.stderr + as_module.stderr
    assert as_script.stdout == as_module.stdout and as_script.stdout.startswith("usage: frost")


# ---- path options -----------------------------------------------------------------------


@pytest.fixture
def blocked(monkeypatch, tmp_path):
    """Paths that cannot be written: under a file, under a folder os.access calls
    read-only (root ignores permission bits), and one whose folders are only missing."""
    blocker = tmp_path / "blocker"
    blocker.write_text("a file", encoding="utf-8")
    (tmp_path / "ro").mkdir()
    real = os.access
    monkeypatch.setattr(paths.os, "access", lambda p, m: real(p, m) and "ro" not in Path(p).parts)
    return {"file as folder": (blocker / "sub" / "x.png", str(blocker)),
            "unwritable": (tmp_path / "ro" / "x.png", str(tmp_path / "ro")),
            "missing parent": (tmp_path / "new" / "deeper" / "x.png", None)}


OUTPUTS = {"render --out": lambda p: ["render", f"--out={p}"],
           "figure8": lambda p: ["figure8", str(p)], "maps": lambda p: ["maps", str(p)]}


@pytest.mark.parametrize("output", list(OUTPUTS))
@pytest.mark.parametrize("case", ["file as folder", "unwritable", "missing parent"])
def test_output_paths_are_checked_before_any_work(stubbed, blocked, output, case):
    target, named = blocked[case]
    status, err = run_main(OUTPUTS[output](target))
    if named is None:  # made when written
        assert status == 0 and stubbed and err == "", err
        return
    assert not stubbed  # refused before the run started
    assert_refused_in_one_line(status, err, output.split()[-1], named)
    if output == "maps":  # a file where the folder itself belongs
        blocker = named if case == "file as folder" else target.parent.parent / "blocker"
        status, err = run_main(OUTPUTS[output](blocker))
        assert_refused_in_one_line(status, err, str(blocker), "is a file, not a folder")


@pytest.mark.parametrize("option", ["--screenshot-dir", "--session-dir"])
@pytest.mark.parametrize("case", ["file as folder", "unwritable", "missing parent"])
def test_the_windows_folders_get_a_one_line_warning_and_it_runs(stubbed, blocked, option, case):
    target, named = blocked[case]
    status, err = run_main([f"{option}={target}"])
    assert status == 0 and stubbed  # the window reports each failed write and runs on
    if named is None:
        assert err == ""
        return
    assert err.count("\n") == 1 and err.startswith(f"frost: warning: {option} {target}: "), err
    assert named in err and "Traceback" not in err


@pytest.mark.parametrize("make, problem", [
    (lambda p: None, "no such file"), (lambda p: p.mkdir(), "is a folder")])
def test_replay_of_a_missing_file_or_a_folder_is_refused(stubbed, tmp_path, make, problem):
    path = tmp_path / "s.json"
    make(path)
    status, err = run_main(["replay", "--headless", str(path)])
    assert_refused_in_one_line(status, err, str(path), problem)


@pytest.mark.parametrize("windowed", [False, True])
def test_replay_of_a_file_that_is_no_session_points_to_the_help(stubbed, tmp_path, monkeypatch,
                                                                windowed):
    """A file that is there but no session (or a session this screen cannot replay) is the
    command line's mistake, as render's are: its line ends with where to look. Headless,
    frost replay's own code reads it; windowed, the command line does before the window."""
    if not windowed:
        monkeypatch.setattr(replay_tool, "run", REPLAY_RUN)  # the real one: it fails first
    small = SessionLog(0, Params().as_dict(), 10, 10, [], 0).save(tmp_path / "small.json")
    (tmp_path / "x.json").write_text('{"x": 1}', encoding="utf-8")
    for path in (tmp_path / "x.json", small):
        status, err = run_main(["replay", *(["--headless"] if not windowed else []), str(path)])
        assert_refused_in_one_line(status, err, str(path))
        assert err.endswith(" (see frost replay --help)\n"), err
    assert not stubbed


def test_a_fern_figure_into_a_blocked_folder_is_refused(stubbed, blocked):
    target, named = blocked["file as folder"]
    status, err = run_main(["figure", "fern", str(target)])
    assert_refused_in_one_line(status, err, str(target), named)


# Each command's output file, with {} for the path.
FILE_OUTPUTS = {"render --out": ["render", "--out={}"], "figure8": ["figure8", "{}"],
                "figure": ["figure", "fern", "{}"],
                "replay --out": ["replay", "SESSION", "--out={}"]}
FOLDER_OUTPUTS = {"maps": ["maps", "{}"]}
# The window's folders: warned of, and the window runs and reports each failed write.
WINDOW_OUTPUTS = {"--screenshot-dir": ["--screenshot-dir={}"], "--session-dir": ["--session-dir={}"],
                  "replay --session-dir": ["replay", "SESSION", "--session-dir={}"]}


def output_argv(template: list[str], path, folder: Path) -> list[str]:
    return with_paths([a.replace("{}", str(path)) for a in template], folder)


@pytest.fixture
def unsearchable(monkeypatch, tmp_path):
    """A folder "nox" whose permissions allow writing but not searching (mode 0o200: a name
    can be added, no file in it reached). Root passes every permission check, so os.access
    is made to refuse X_OK alone on it, as it does for a user; every other mode passes."""
    (tmp_path / "nox").mkdir()
    real = os.access
    monkeypatch.setattr(paths.os, "access", lambda p, m: real(p, m) and not (
        m & os.X_OK and Path(p).name == "nox"))
    return tmp_path / "nox"


UNSEARCHABLE = "is not searchable (no x permission)"


@pytest.mark.parametrize("output", [*FILE_OUTPUTS, *FOLDER_OUTPUTS])
@pytest.mark.parametrize("inside", ["x.png", "new/x.png"])
def test_an_output_in_a_folder_writable_but_not_searchable_is_refused(
        stubbed, tmp_path, unsearchable, output, inside):
    template = {**FILE_OUTPUTS, **FOLDER_OUTPUTS}[output]
    target = unsearchable / (inside if output not in FOLDER_OUTPUTS else inside.replace(".png", ""))
    status, err = run_main(output_argv(template, target, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, str(unsearchable), UNSEARCHABLE)


def test_an_existing_output_in_a_folder_not_searchable_is_refused(stubbed, tmp_path, unsearchable):
    (unsearchable / "x.png").write_bytes(b"old")  # root made it; a user could not reach it
    status, err = run_main(["render", f"--out={unsearchable / 'x.png'}"])
    assert_refused_in_one_line(status, err, f"its folder {unsearchable}", UNSEARCHABLE)
    status, err = run_main(["maps", str(unsearchable)])
    assert_refused_in_one_line(status, err, str(unsearchable), UNSEARCHABLE)


@pytest.mark.parametrize("output", [*FILE_OUTPUTS, *FOLDER_OUTPUTS])
def test_an_output_in_a_folder_searchable_but_not_writable_is_refused(stubbed, tmp_path, monkeypatch,
                                                                     output):
    """A folder of mode 0o500 (its files reached, no name added): os.access (root passes
    every bit) refuses W_OK alone on it, as it does for a user."""
    folder = tmp_path / "rx"
    folder.mkdir()
    real = os.access
    monkeypatch.setattr(paths.os, "access", lambda p, m: real(p, m) and not (
        m & os.W_OK and Path(p).name == "rx"))
    template = {**FILE_OUTPUTS, **FOLDER_OUTPUTS}[output]
    target = folder / ("x.png" if output not in FOLDER_OUTPUTS else "maps")
    status, err = run_main(output_argv(template, target, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, str(folder), "is not writable")


def test_the_default_folder_not_searchable_is_refused(stubbed, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "frost-out").mkdir()
    real = os.access
    monkeypatch.setattr(paths.os, "access", lambda p, m: real(p, m) and not (
        m & os.X_OK and Path(p).name == "frost-out"))
    status, err = run_main(["render"])
    assert not stubbed
    assert_refused_in_one_line(status, err, "frost-out", UNSEARCHABLE)


@pytest.mark.parametrize("option", ["--screenshot-dir", "--session-dir"])
def test_a_window_folder_not_searchable_is_warned_of(stubbed, unsearchable, option):
    status, err = run_main([f"{option}={unsearchable}"])
    assert status == 0 and stubbed and err.count("\n") == 1, err
    assert err.startswith(f"frost: warning: {option} {unsearchable}: ") and UNSEARCHABLE in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root passes every permission bit")
@pytest.mark.parametrize("mode", [0o200, 0o600])
def test_a_real_folder_without_x_is_refused(stubbed, tmp_path, mode):
    folder = tmp_path / "nox"
    folder.mkdir()
    folder.chmod(mode)
    try:
        status, err = run_main(["render", f"--out={folder / 'x.png'}"])
    finally:
        folder.chmod(0o700)
    assert_refused_in_one_line(status, err, str(folder), UNSEARCHABLE)


def make_node(kind: str, path: Path) -> None:
    if kind == "fifo":
        os.mkfifo(path)
    elif os.geteuid() != 0:
        pytest.skip("making a device node needs root")
    else:  # a copy of /dev/null: the real one is never touched
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))


@pytest.mark.parametrize("output", list(FILE_OUTPUTS))
@pytest.mark.parametrize("kind, said", [("fifo", "is a FIFO"),
                                        ("char device", "is a character device")])
@pytest.mark.parametrize("through_link", [False, True])
def test_an_output_that_is_not_a_regular_file_is_refused_before_any_work(
        stubbed, tmp_path, output, kind, said, through_link):
    node = tmp_path / "node"
    make_node(kind, node)
    path = node
    if through_link:
        path = tmp_path / "link.png"
        path.symlink_to(node)
    status, err = run_main(output_argv(FILE_OUTPUTS[output], path, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, str(path), said, "not a regular file")
    assert os.lstat(node).st_mode & 0o170000 == (stat.S_IFIFO if kind == "fifo" else stat.S_IFCHR)


def test_a_map_file_that_is_a_fifo_is_refused_before_any_work(stubbed, tmp_path):
    (tmp_path / "maps").mkdir()
    os.mkfifo(tmp_path / "maps" / "normal.png")
    status, err = run_main(["maps", str(tmp_path / "maps")])
    assert not stubbed
    assert_refused_in_one_line(status, err, "normal.png: is a FIFO")


def test_an_output_symlink_to_a_file_is_accepted(stubbed, tmp_path):
    (tmp_path / "real.png").write_bytes(b"old")
    (tmp_path / "link.png").symlink_to(tmp_path / "real.png")
    status, err = run_main(["render", f"--out={tmp_path / 'link.png'}"])
    assert status == 0 and stubbed and err == "", err


LONG = "n" * 300


def refused_or_warned(stubbed, output: str, status, err: str, *words: str) -> None:
    """An output is refused before any work; a window's folder warned of in one line."""
    if output in WINDOW_OUTPUTS:
        assert status == 0 and stubbed, err
        assert err.count("\n") == 1 and err.startswith("frost: warning: "), err
        assert all(word in err for word in words), err
        return
    assert not stubbed
    assert_refused_in_one_line(status, err, *words)


OUTPUT_TEMPLATES = {**FILE_OUTPUTS, **FOLDER_OUTPUTS, **WINDOW_OUTPUTS}


@pytest.mark.parametrize("output", list(OUTPUT_TEMPLATES))
@pytest.mark.parametrize("where", ["last", "folder"])
def test_a_name_too_long_is_refused_or_warned_of(stubbed, tmp_path, output, where):
    path = tmp_path / LONG if where == "last" else tmp_path / LONG / "x"
    status, err = run_main(output_argv(OUTPUT_TEMPLATES[output], path, tmp_path))
    refused_or_warned(stubbed, output, status, err, "300 bytes long", str(path))


@pytest.mark.parametrize("output", ["render --out", "maps", "--session-dir"])
@pytest.mark.parametrize("name", [LONG, "n" * 251 + ".png"], ids=["300 bytes", "255 bytes"])
def test_without_pathconf_a_name_is_held_to_255_bytes(stubbed, tmp_path, monkeypatch, output,
                                                      name):
    """Windows' Python has no os.pathconf: the check takes 255 bytes (Linux's limit; NTFS
    allows 255 characters) instead of failing."""
    monkeypatch.delattr(os, "pathconf")
    path = tmp_path / name
    status, err = run_main(output_argv(OUTPUT_TEMPLATES[output], path, tmp_path))
    if name == LONG:
        refused_or_warned(stubbed, output, status, err, "300 bytes long", "allows 255")
    else:
        assert status == 0 and stubbed and err == "", err


@pytest.mark.parametrize("output", list(FOLDER_OUTPUTS) + list(WINDOW_OUTPUTS))
def test_the_current_folder_is_a_folder_to_write_in(stubbed, tmp_path, monkeypatch, output):
    # "." has no parts to measure: it crashed the length check ("max() arg is empty")
    monkeypatch.chdir(tmp_path)
    status, err = run_main(output_argv(OUTPUT_TEMPLATES[output], ".", tmp_path))
    assert status == 0 and stubbed and err == "", err


# /proc and /sys take no new files (even from root); only a file made there tells.
PSEUDO = [p for p in ("/proc", "/sys") if os.path.isdir(p)]


@pytest.mark.parametrize("root", PSEUDO)
@pytest.mark.parametrize("output", list(OUTPUT_TEMPLATES))
def test_a_folder_that_takes_no_files_is_refused_or_warned_of(stubbed, tmp_path, root,
                                                             output):
    path = f"{root}/frost-x.png"
    status, err = run_main(output_argv(OUTPUT_TEMPLATES[output], path, tmp_path))
    refused_or_warned(stubbed, output, status, err, path, f"cannot create files in {root}")
    assert ".tmp" not in err and "frost-probe" not in err


def test_the_start_up_check_leaves_no_probe_behind(stubbed, tmp_path):
    (tmp_path / "out").mkdir()
    for argv in (["maps", str(tmp_path / "out")], ["--session-dir", str(tmp_path / "new")],
                 ["render", "--out", str(tmp_path / "out" / "x.png")]):
        status, err = run_main(argv)
        assert status == 0 and err == "", err
    assert len(stubbed) == 3 and [p.name for p in tmp_path.rglob("*")] == ["out"]


def test_a_replay_of_a_fifo_is_refused_without_blocking(stubbed, tmp_path):
    os.mkfifo(tmp_path / "s.json")
    status, err = run_main(["replay", "--headless", str(tmp_path / "s.json")])
    assert_refused_in_one_line(status, err, "s.json", "is a FIFO")


@pytest.mark.parametrize("argv", [["render"], ["replay", "SESSION", "--headless"],
                                  ["replay", "SESSION", "--ticks=3"], []])
def test_the_default_folder_is_checked_when_there_is_no_out(stubbed, tmp_path, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("DISPLAY", raising=False)  # the window renders to PNGs instead
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    argv = with_paths(argv, tmp_path)
    (tmp_path / "frost-out").write_text("a file in the way", encoding="utf-8")
    status, err = run_main(argv)
    assert not stubbed
    assert_refused_in_one_line(status, err, "frost-out", "is a file, not a folder")
    (tmp_path / "frost-out").unlink()
    status, err = run_main(argv)
    assert status == 0 and stubbed and not (tmp_path / "frost-out").exists(), err


@pytest.mark.parametrize("output", list(FILE_OUTPUTS))
@pytest.mark.parametrize("name, shown", [("x.gif", ".gif"), ("x.png.txt", ".txt"),
                                         ("x", "no suffix")])
def test_a_picture_name_frost_cannot_write_is_refused_naming_the_suffixes(
        stubbed, tmp_path, output, name, shown):
    status, err = run_main(output_argv(FILE_OUTPUTS[output], tmp_path / name, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, name, ".png, .jpg, .jpeg", shown)


@pytest.mark.parametrize("name", ["x.png", "x.jpg", "x.JPEG", "x.Png"])
def test_picture_names_frost_writes_are_accepted(stubbed, tmp_path, name):
    status, err = run_main(["render", f"--out={tmp_path / name}"])
    assert status == 0 and stubbed and err == "", err


# A bad command line of each command, the prefix its error starts with and the help it
# points to. Every command parsed by frost speaks as frost; frost bench sim's arguments
# belong to the benchmark's own parser, which speaks as frost bench sim, wherever the words
# of the command line put the mistake.
PREFIXES = [([], "frost", "frost"), (["render"], "frost", "frost render"),
            (["replay", "SESSION"], "frost", "frost replay"),
            (["figure8", "OUT/f.png"], "frost", "frost figure8"),
            (["figure", "fern", "OUT/f.png"], "frost", "frost figure"),
            (["maps", "OUT/maps"], "frost", "frost maps"),
            (["bench", "render"], "frost", "frost bench render"),
            (["bench", "sim"], "frost bench sim", "frost bench sim"),
            (["bench", "--bogus", "sim"], "frost bench sim", "frost bench sim")]


@pytest.mark.parametrize("argv, prefix, command", PREFIXES)
def test_each_commands_errors_carry_its_prefix(stubbed, tmp_path, argv, prefix, command):
    bad = argv if "--bogus" in argv else [*argv, "--bogus"]
    status, err = run_main(with_paths(bad, tmp_path))
    assert status == 2 and err.count("\n") == 1, err
    assert err.startswith(f"{prefix}: error: ") and err.endswith(f"(see {command} --help)\n"), err
    if argv and bad != argv:  # a window option before the command: it is named whole
        status, err = run_main(with_paths(["--seed=3", *argv], tmp_path))
        assert status == 2 and err.startswith(f"{prefix}: error: "), err
        assert f"write {command} [options]" in err, err


def test_a_render_over_a_folder_is_refused(stubbed, tmp_path):
    status, err = run_main(["render", "--out", str(tmp_path)])
    assert_refused_in_one_line(status, err, "--out", "is a folder, not a file")


# A path (or any text) a user typed may hold a newline, a carriage return or a terminal
# escape; the message that names it stays one line and shows them escaped.
ODD = "a\nb\rc\x1bd"
ODD_SHOWN = "a\\nb\\rc\\x1bd"


def test_a_replay_path_with_control_characters_is_refused_in_one_line(stubbed, tmp_path):
    status, err = run_main(["replay", "--headless", str(tmp_path / ODD)])
    assert_refused_in_one_line(status, err, ODD_SHOWN, "no such file")


def test_an_output_path_with_control_characters_is_refused_in_one_line(stubbed, blocked):
    target = blocked["file as folder"][0].parent / ODD / "x.png"
    status, err = run_main(["render", f"--out={target}"])
    assert_refused_in_one_line(status, err, ODD_SHOWN, "is a file, not a folder")


def test_a_stray_argument_with_control_characters_is_refused_in_one_line(stubbed):
    status, err = run_main(["render", ODD])
    assert_refused_in_one_line(status, err, "unrecognized arguments", ODD_SHOWN)


def test_a_window_folder_with_control_characters_gets_a_one_line_warning(stubbed, blocked):
    target = blocked["file as folder"][0].parent / ODD
    status, err = run_main([f"--screenshot-dir={target}"])
    assert status == 0 and err.count("\n") == 1 and ODD_SHOWN in err, err


@pytest.mark.parametrize("text, shown", [
    ("a\nb", "a\\nb"), ("x\r\x1b[2Jy", "x\\r\\x1b[2Jy"), ("\u2028", "\\u2028"),
    ("tab\there", "tab\\there"), ("é ü / ~", "é ü / ~"), ("", "")])
def test_one_line_escapes_what_would_break_or_restyle_a_line(text, shown):
    assert one_line(text) == shown


@given(st.text())
def test_one_line_is_one_printable_line_and_keeps_printable_text(text):
    shown = one_line(text)
    assert shown.isprintable() and len(shown.splitlines()) <= 1
    assert (shown == text) == text.isprintable()


# ---- session files ----------------------------------------------------------------------

JSON = st.recursive(
    st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=4),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                 max_size=3),
    max_leaves=8)
NUMBER = st.one_of(st.integers(-3, 3), st.integers(), st.floats(), st.booleans(),
                   st.floats(0, 800), st.sampled_from([0, 0.5, 4.0, 759.9999999999, 1e308, 2**70]))
TICK = st.one_of(st.integers(0, 4), NUMBER)
# Parameter values near and beyond the valid ranges, of every JSON type. (Only affordable
# values are replayed below: tiny hc or huge humidity are the bounds on work per tick (docs/method.md 5.2).)
PARAM_VALUE = st.one_of(NUMBER, st.sampled_from(["candidate", "grid9", "octree", None]))
PARAM_NAMES = st.sampled_from([n for n, _, _ in Params.describe()] + ["zap"])
PARAMS = st.dictionaries(PARAM_NAMES, PARAM_VALUE, max_size=3) | JSON
KINDS = st.sampled_from(["touch", "melt", "params", "clear", "zap"]) | JSON


VALID_PARAMS = st.fixed_dictionaries({}, optional={
    "hc": st.floats(5, 10), "humidity": st.integers(1, 3000), "grow": st.booleans(),
    "neighbor_search": st.sampled_from(["candidate", "grid9"]), "D": st.floats(1, 10)})
VALID_EVENT = st.one_of(
    st.fixed_dictionaries({"kind": st.just("touch"), "x": st.floats(0, 800), "y": st.floats(0, 1300)}),
    st.fixed_dictionaries({"kind": st.just("melt"), "x": st.floats(-50, 800),
                           "y": st.floats(-50, 1300), "r": st.floats(0.1, 300)}),
    st.fixed_dictionaries({"kind": st.just("params"), "params": VALID_PARAMS}),
    st.just({"kind": "clear"}))


@st.composite
def events(draw):
    """A well-formed event at a small tick, sometimes with one value replaced by anything."""
    event = {**draw(VALID_EVENT), "tick": draw(st.integers(0, 4))}
    if draw(st.integers(0, 2)) == 0:
        key = draw(st.sampled_from(sorted(event) + ["kind", "x", "params"]))
        event[key] = draw(NUMBER | JSON | PARAMS | KINDS)
    return event if draw(st.integers(0, 19)) else draw(JSON)


@st.composite
def sessions(draw):
    """A session file that is valid but for (sometimes) one or two entries."""
    timed = sorted(draw(st.lists(events(), max_size=6)),
                   key=lambda e: e.get("tick", 0) if isinstance(e, dict) and
                   isinstance(e.get("tick"), int) else 0)
    data = {"format": "frost-session", "version": 1, "seed": draw(st.integers(0, 9)),
            "width": 760, "height": 1280, "params": draw(VALID_PARAMS),
            "steps": draw(st.integers(0, 6)), "events": timed}
    for key in draw(st.lists(st.sampled_from(sorted(data)), max_size=2)):
        if draw(st.booleans()):
            data.pop(key, None)
        else:
            data[key] = draw(NUMBER | JSON | PARAMS | st.sampled_from([64, 48, 1280, 760]))
    return data


def affordable(p: dict) -> bool:
    """Parameters whose replay takes milliseconds, not section 1's unbounded cases."""
    q = Params(**p)
    return q.hc >= 1 and q.humidity <= 5000 and q.grid_spacing >= 2 and q.D >= 0.5


@settings(max_examples=max(300, settings.default.max_examples), deadline=None)
@given(data=sessions())
@example(data={"format": "frost-session", "seed": 0, "params": {"humidity": 3000.5}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {"grid_spacing": 4.0}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {"humidity": 10**400}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": [], "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {"zap": 1}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {"\n": 1}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "steps": 1,
               "events": [{"kind": "params", "tick": 0, "params": {"hc\r": 8}}]})
@example(data={"format": "frost-session", "seed": True, "params": {}, "events": []})
@example(data={"format": "frost-session", "seed": -1, "params": {}, "events": []})
@example(data={"format": "frost-session", "seed": 2.5, "params": {}, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "width": 0, "events": []})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "events": {}})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "events": [["kind"]]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": [], "tick": 0}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "touch", "tick": True, "x": 1, "y": 1}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "touch", "tick": 0, "x": True, "y": 1}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "touch", "tick": 0.0, "x": 1, "y": 1}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "melt", "tick": 0, "x": math.nan, "y": 1, "r": 3}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "melt", "tick": 0, "x": 1e308, "y": 1, "r": 1e308}]})
@example(data={"format": "frost-session", "seed": 0, "params": {},
               "events": [{"kind": "melt", "tick": 0, "x": 1, "y": 1, "r": -2}]})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "steps": 2,
               "events": [{"kind": "params", "tick": 0, "params": {"grid_spacing": 8}}]})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "steps": 2,
               "events": [{"kind": "params", "tick": 0, "params": 7}]})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "steps": 4,
               "events": [{"kind": "touch", "tick": 3, "x": 1, "y": 1},
                          {"kind": "touch", "tick": 1, "x": 2, "y": 2}]})
@example(data={"format": "frost-session", "seed": 0, "params": {}, "steps": 2, "width": 64,
               "height": 48, "events": [{"kind": "touch", "tick": 0, "x": 63.99999999, "y": 5}]})
def test_any_session_file_loads_and_replays_or_is_refused(data):
    try:
        log = SessionLog.from_json(data)
    except SessionError as err:
        assert str(err) and "\n" not in str(err)
        event("refused")
        return
    assert isinstance(log.seed, int) and log.seed >= 0
    run = [log.params] + [e["params"] for e in log.events if e["kind"] == "params"]
    if all(affordable(p) for p in run):
        event(f"replayed with {len(log.events)} events")
        timeline = replay(log, min(log.steps, 6))
        assert timeline.steps == min(log.steps, 6)


def test_a_session_file_on_disk_names_itself_in_the_error(tmp_path):
    path = tmp_path / "s.json"
    path.write_text('{"format": "frost-session", "seed": 0, "params": {"grid_spacing": 4.0},'
                    ' "events": []}', encoding="utf-8")
    with pytest.raises(SessionError, match=r"s\.json: .*grid_spacing=4\.0 must be a whole number"):
        SessionLog.load(path)
    path.write_text("[" * 100_000, encoding="utf-8")  # deep nesting: json's RecursionError
    with pytest.raises(SessionError, match="not JSON"):
        SessionLog.load(path)


def test_an_unknown_parameter_is_named_escaped_in_one_line():
    data = {"format": "frost-session", "seed": 0, "params": {"zap\n": 1, "hc": 7.0},
            "events": []}
    with pytest.raises(SessionError) as refused:
        SessionLog.from_json(data)
    assert str(refused.value) == "'params': unknown parameter 'zap\\n'"


def test_a_params_event_may_not_resize_the_renderers_grid():
    data = {"format": "frost-session", "seed": 0, "params": {"grid_spacing": 4}, "steps": 3,
            "events": [{"kind": "params", "tick": 1, "params": {"grid_spacing": 8}}]}
    with pytest.raises(SessionError, match="cannot change grid_spacing"):
        SessionLog.from_json(data)
    data["events"][0]["params"] = {"grid_spacing": 4, "hc": 8.0}  # other changes replay
    assert replay(SessionLog.from_json(data)).params.hc == 8.0


# ---- float32 edges ----------------------------------------------------------------------


@given(x=st.floats(0, 760, exclude_max=True), y=st.floats(0, 1280, exclude_max=True))
@example(x=759.99999999, y=1279.99999999)  # both round up to the edge in float32
@example(x=0.0, y=5e-324)
def test_a_touch_on_the_screen_stays_on_it_once_stored(x, y):
    sim = FrostSim(Params(humidity=1), 760, 1280)
    sim.touch(x, y)
    (cx, cy), area = sim.crystals[-1], sim.areas[-1]
    assert 0 <= cx < 760 and 0 <= cy < 1280
    assert (area[0], area[1]) == (cx, cy)
    assert abs(cx - x) <= np.spacing(np.float32(760)) and abs(cy - y) <= np.spacing(np.float32(1280))
    key = sim.grid.keys(np.array([cx]), np.array([cy]))[0]
    assert sim.candidates.count[key] >= 1  # listed in its own, on-screen cell


def shown_defaults(described: str) -> dict[str, str]:
    """'... (default: fern, window 2.5; Table 1 1.0-10.0)' -> {look: value} ('*': every look)."""
    said = re.search(r"\(default([^()]*)\)", described)[1]
    if not said.startswith(":"):
        return {"*": said.strip()}
    shown = {}
    for part in said[1:].split(";"):
        names, value = part.strip().rsplit(" ", 1)
        shown.update({name: value for name in names.split(", ")})
    return shown


@pytest.mark.parametrize("head", [[], ["render"], ["maps", "OUT"], ["figure", "fern", "OUT/f.png"]])
def test_each_override_shows_the_value_a_run_without_it_gets(stubbed, tmp_path, head):
    def got(extra: list[str]) -> Params:
        status, err = run_main(with_paths([*head, *extra], tmp_path))
        assert status == 0, err
        return stubbed.pop()[1]

    def text(value) -> str:
        return ("on" if value else "off") if isinstance(value, bool) else str(value)

    runs = {"fern": got([]), "window": got(["--window-frost"])}
    table = [got(["--preset", name]) for name in PRESETS]
    for option, described in listed_options(help_text(head[:1])).items():
        if option not in OVERRIDES:
            continue
        name = {"--D": "D"}.get(option, option[2:].replace("-", "_"))
        values = sorted({getattr(p, name) for p in table})
        want = {look: text(getattr(p, name)) for look, p in runs.items()}
        want["Table 1"] = "-".join(text(v) for v in (values[0], values[-1])[:len(values)])
        shown = shown_defaults(described)
        assert shown == want or set(want.values()) == {shown.get("*")}, described


# ---- one rule per quantity --------------------------------------------------------------


@pytest.mark.parametrize("scale, ok", [("0.04", False), ("0.05", True), ("1", True), ("4", True),
                                       ("4.01", False), ("5", False), ("8", False)])
def test_the_command_line_takes_the_scales_the_window_opens_at(stubbed, scale, ok):
    from app.window.glfw_setup import WindowError, open_window

    status, err = run_main(["--scale", scale])
    if ok:
        assert status == 0 and stubbed, err
        return
    assert_refused_in_one_line(status, err, "--scale", "[0.05, 4]")
    with pytest.raises(WindowError, match=r"\[0\.05, 4\]"):  # refused before GLFW starts
        open_window(float(scale))


def session_with(*events, **entries) -> dict:
    return {"format": "frost-session", "seed": 0, "params": {}, "steps": 20,
            "events": list(events), **entries}


def loads(data: dict) -> bool:
    try:
        SessionLog.from_json(data)
    except SessionError:
        return False
    return True


def on_screen(x: float, y: float) -> bool:
    return 0 <= x < 760 and 0 <= y < 1280  # the phone, by hand (NaN compares False)


EDGES = [0.0, -0.0, 759.9999999, 760.0, 760.5, 1279.999, 1280.0, -1.0, -1e-9, 5e-324]
COORD = st.one_of(st.sampled_from(EDGES), st.floats(-100, 1400), st.floats())


@FIXTURE_OK
@given(x=COORD, y=COORD)
@example(x=760.0, y=5.0)  # a session took it; the command line refused it
@example(x=-1.0, y=0.0)  # argparse said "expected one argument"
@example(x=-float("inf"), y=0.0)  # and again for -inf, which the fix first took for an option
def test_a_touch_is_taken_by_the_command_line_iff_by_a_session(stubbed, x, y):
    stubbed.clear()
    status, err = run_main(["render", "--touch", f"{x!r},{y!r}"])
    session = loads(session_with({"kind": "touch", "tick": 0, "x": x, "y": y}))
    assert (status == 0) == session == on_screen(x, y), err
    if status:
        assert_refused_in_one_line(status, err, "--touch", "is off the 760x1280 screen")


RADII = st.one_of(st.sampled_from([1e-9, 0.5, 24.0, 10_000.0, 10_000.5, 1e9, 0.0, -1.0]),
                  st.floats(-10, 20_000), st.floats())


@FIXTURE_OK
@given(x=COORD, y=COORD, r=RADII)
@example(x=100.0, y=100.0, r=1e9)  # a --melt took it; --melt-radius refused it
@example(x=900.0, y=100.0, r=10.0)  # a --melt off the screen was taken
def test_a_melt_is_taken_by_the_command_line_iff_by_a_session(stubbed, tmp_path, x, y, r):
    stubbed.clear()
    ok = on_screen(x, y) and 0 < r <= 10_000  # by hand: a finger on the screen, r in range
    status, err = run_main(["render", "--touch=1,1", f"--melt={x!r},{y!r},{r!r}@3"])
    assert (status == 0) == ok, err
    if status:
        assert_refused_in_one_line(status, err, "--melt")
    assert loads(session_with({"kind": "melt", "tick": 0, "x": x, "y": y, "r": r})) == ok
    status, err = run_main(["render", "--touch=1,1", f"--melt-radius={r!r}"])
    assert (status == 0) == (0 < r <= 10_000), err


def test_a_melt_path_point_off_the_screen_is_refused(stubbed):
    status, err = run_main(["render", "--touch=1,1", "--melt-path", "-5,3:10,10@2"])
    assert_refused_in_one_line(status, err, "--melt-path", "(-5, 3) is off the 760x1280 screen")


def test_a_melt_path_point_of_three_numbers_is_refused(stubbed):
    # A path's points are X,Y: a radius (a melt's X,Y,R) is not one of them.
    status, err = run_main(["render", "--touch=1,1", "--melt-path", "10,10,5:20,20@5"])
    assert_refused_in_one_line(status, err, "--melt-path",
                               "melt path '10,10,5:20,20@5' must be X1,Y1:X2,Y2[:...]@TICK")
    assert not stubbed


@pytest.mark.parametrize("argv, least, said", [
    # A path is two points or more; a benchmark times one frame or more.
    (["render", "--touch=1,1", "--melt-path", "{}@5"], ("10,10", "10,10:20,20"),
     ("--melt-path", "melt path '10,10@5' must be X1,Y1:X2,Y2[:...]@TICK")),
    (["bench", "render", "--frames", "{}"], ("0", "1"), ("--frames", "'0' must be a whole number >= 1"))])
def test_a_value_short_of_its_least_is_refused_in_one_line(stubbed, argv, least, said):
    short, enough = least
    status, err = run_main([a.format(short) for a in argv])
    assert_refused_in_one_line(status, err, *said)
    assert not stubbed
    status, err = run_main([a.format(enough) for a in argv])
    assert status == 0 and len(stubbed) == 1, err


@pytest.mark.parametrize("option", ["--melt=5,5@{}", "--melt-path=5,5:9,9@{}"])
def test_a_melt_after_the_last_tick_is_refused(stubbed, option):
    status, err = run_main(["render", "--touch=1,1", "--ticks=10", option.format(11)])
    assert_refused_in_one_line(status, err, "tick 11", "--ticks 10")
    status, err = run_main(["render", "--touch=1,1", "--ticks=10", option.format(10)])
    assert status == 0 and stubbed, err


def test_a_melt_at_the_last_tick_applies():
    from sim.io.timeline import Timeline, grow, touch_events

    events = touch_events([(380, 640)]) + [{"tick": 10, "kind": "melt", "x": 380.0,
                                            "y": 640.0, "r": 30.0}]
    timeline = Timeline(Params.preset("c-2"), 0)
    assert grow(timeline, 10, events) == 2 and timeline.melts[-1]["tick"] == 10


@pytest.mark.parametrize("option, top, entry", [
    ("--seed", 2**63 - 1, "seed"), ("--ticks", 2**31 - 1, "steps")])
def test_a_seed_or_tick_count_is_taken_by_the_command_line_iff_by_a_session(
        stubbed, option, top, entry):
    for value, ok in ((top, True), (top + 1, False), (-1, False)):
        stubbed.clear()
        status, err = run_main(["render", "--touch=1,1", f"{option}={value}"])
        assert (status == 0) == ok == loads(session_with(**{entry: value})), (value, err)
        if not ok:
            assert_refused_in_one_line(status, err, option, str(top))


@pytest.mark.parametrize("argv, said", [
    (["--touch", "-1,0"], "touch (-1, 0) is off the 760x1280 screen"),
    (["render", "--touch", "1,1", "--melt", "-1,0@2"], "melt (-1, 0) is off"),
    (["render", "--touch", "1,1", "--melt-path", "-1,0:5,5@2"], "melt path point (-1, 0) is off"),
    (["--hc", "-1e-5"], "hc=-1e-05 is out of range"), (["--touch", "-.5,3"], "(-0.5, 3) is off"),
    (["--seed", "-1"], "--seed: '-1' must be a whole number")])
def test_a_negative_value_is_refused_for_what_is_wrong_with_it(stubbed, argv, said):
    status, err = run_main(argv)
    assert "expected one argument" not in err
    assert_refused_in_one_line(status, err, said)


# ---- zero-valued radius, scale and fraction options ----------------------------------------

@pytest.mark.parametrize("argv, named", [
    (["--melt-radius", "0"], "--melt-radius"),
    (["render", "--touch", "1,1", "--melt-radius", "0"], "--melt-radius"),
    (["render", "--touch", "100,100", "--melt", "100,100,0@5"], "--melt"),
    (["--scale", "0"], "--scale"), (["bench", "render", "--cover", "0"], "--cover"),
    (["render", "--touch", "1,1", "--active-radius", "0"], "active_radius=0.0"),
    (["render", "--touch", "1,1", "--hc", "0"], "hc=0.0"),
    (["render", "--touch", "1,1", "--step", "0"], "step=0.0"),
    (["render", "--touch", "1,1", "--max-height", "0"], "max_height=0.0")])
def test_a_zero_radius_scale_or_fraction_is_refused_in_one_line_naming_it(stubbed, tmp_path,
                                                                          argv, named):
    status, err = run_main(with_paths(argv, tmp_path))
    assert not stubbed
    assert_refused_in_one_line(status, err, named)


@pytest.mark.parametrize("option", ["launch", "drift", "frame_chill", "bump", "feature_width",
                                    "feature_height", "vapour_var"])
def test_a_zero_that_means_off_or_flat_is_taken_and_grows(stubbed, option):
    """Each of these documents 0 as its off (or flat) value: taken as given, and a short run
    with it grows and draws."""
    from sim.look.geometry import FrostGeometry
    status, err = run_main(["render", "--touch", "380,640", f"--{option.replace('_', '-')}", "0"])
    assert status == 0 and err == "", err
    params = stubbed[0][1]
    assert getattr(params, option) == 0
    sim, geometry = FrostSim(params, seed=0), FrostGeometry(params)
    sim.touch(380.0, 640.0)
    for _ in range(30):
        sim.step()
    geometry.update(sim)
    assert len(sim.crystals) > 1


# ---- numbers too long to be frost's ----------------------------------------------------

DIGITS_5000 = "9" * 5000  # past Python's 4300-digit limit on converting text to int


@pytest.mark.parametrize("text, entry", [
    ('{"format": "frost-session", "version": 6, "seed": LONG, "params": {}, "events": []}',
     "entry seed:"),
    ('{"format": "frost-session", "seed": 0, "params": {}, "events": '
     '[{"tick": 0, "kind": "touch", "x": 3, "y": -LONG}]}', "entry events[0].y:")])
def test_a_session_holding_a_number_of_5000_digits_is_refused_naming_its_entry(
        tmp_path, text, entry):
    path = tmp_path / "long.json"
    path.write_text(text.replace("LONG", DIGITS_5000), encoding="utf-8")
    status, err = run_main(["replay", "--headless", str(path), "--out", str(tmp_path / "o.png")])
    assert_refused_in_one_line(status, err, str(path), entry, "5000 digits")
    assert "set_int_max_str_digits" not in err


@pytest.mark.parametrize("command", [["render"], ["figure8", "OUT/f.png"], []])
def test_a_parameter_set_holding_a_number_of_5000_digits_is_refused_naming_it(
        stubbed, tmp_path, command):
    path = tmp_path / "set.json"
    path.write_text('{"format": "frost-params", "version": 1, "params": {"humidity": LONG}}'
                    .replace("LONG", DIGITS_5000), encoding="utf-8")
    status, err = run_main(with_paths([*command, "--params", str(path)], tmp_path))
    assert_refused_in_one_line(status, err, str(path), "entry params.humidity:", "5000 digits")
    assert "set_int_max_str_digits" not in err and not stubbed


def test_a_number_of_64_digits_is_still_read_and_judged_by_its_range(tmp_path):
    path = tmp_path / "s.json"
    path.write_text('{"format": "frost-session", "seed": %s, "params": {}, "events": []}'
                    % ("9" * 64), encoding="utf-8")
    with pytest.raises(SessionError, match=r"'seed' is 9{64}; it must be a whole number"):
        SessionLog.load(path)
