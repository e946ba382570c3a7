"""Windows' reserved names as an output path (docs/command-line.md, Bad input): a name that
works here must work on Windows, where `CON.png` writes to the console and `NUL` to
nowhere. Every output path of every command, with any of those names (any case, any
extension, the trailing dots and spaces Windows strips) in any part of it, is refused in
one line, exit status 2, before any work, on every system. The oracle: the names written
out by hand from Microsoft's list ("Naming Files, Paths, and Namespaces"), not the code's."""

from __future__ import annotations

import argparse

import pytest
from support.cli import assert_refused_in_one_line, run_main

from app.cli import commands
from app.cli.parser import build_parser
from app.serve import command as serve_command
from app.tools import figure8, figure_fern, maps, web_site
from app.tools import render_png as render
from app.tools import replay as replay_tool
from app.window import frost_window as window
from sim import Params
from sim.io.session import SessionLog

RESERVED = ["CON", "PRN", "AUX", "NUL",
            "COM0", "COM1", "COM2", "COM3", "COM4", "COM5", "COM6", "COM7", "COM8", "COM9",
            "LPT0", "LPT1", "LPT2", "LPT3", "LPT4", "LPT5", "LPT6", "LPT7", "LPT8", "LPT9",
            "COM\u00b9", "COM\u00b2", "COM\u00b3", "LPT\u00b9", "LPT\u00b2", "LPT\u00b3"]
# Each as it may be typed: cases, extensions (one, two, none), trailing dots and spaces.
SPELLINGS = ["{}.png", "{l}.png", "{t}.jpg", "{}.tar.gz", "{l}", "{}.", "{} ", "{}.png.",
             "{} .png", "{l}.PNG  "]
# Names that only look like one: accepted.
FINE = ["console.png", "icon.png", "xcon.png", "con_.png", "com10.png", "lpt.png", "com.png",
        "nul-1.png", "auxiliary.png", "c o n.png", "prn2.png"]

# Every option of the command line that names something frost writes, by hand:
# (the command line with PATH as that option's value, the option as the error names it).
OUTPUTS = [(["render", "--out", "PATH"], "--out"),
           (["replay", "s.json", "--out", "PATH"], "--out"),
           (["figure8", "PATH"], ""), (["figure", "fern", "PATH"], ""), (["maps", "PATH"], ""),
           (["--session-dir", "PATH"], "--session-dir"),
           (["--screenshot-dir", "PATH"], "--screenshot-dir"),
           (["replay", "s.json", "--session-dir", "PATH"], "--session-dir"),
           (["replay", "s.json", "--screenshot-dir", "PATH"], "--screenshot-dir"),
           (["serve", "--session-dir", "PATH"], "--session-dir"),
           (["serve", "--screenshot-dir", "PATH"], "--screenshot-dir"),
           (["web", "PATH"], "")]
# The options that take a path frost reads (never writes): the rest are outputs above.
INPUTS = {"--params", "--background", "--cert", "--key", "replay"}


@pytest.fixture
def stubbed(monkeypatch, tmp_path):
    """main() with every command's work replaced by a recorder, run in tmp_path (where
    s.json is a session file to replay)."""
    calls = []
    for module in (figure8, figure_fern, maps, render, replay_tool, window, web_site):
        monkeypatch.setattr(module, "run", lambda args, params=None: calls.append(args) or 0)
    monkeypatch.setattr(serve_command, "serve", lambda args, params=None: calls.append(args) or 0)
    monkeypatch.setattr(commands, "display_problem", lambda: None)
    monkeypatch.chdir(tmp_path)
    SessionLog(0, Params().as_dict()).save(tmp_path / "s.json")
    return calls


def spelled(name: str, spelling: str) -> str:
    return spelling.format(name, l=name.lower(), t=name.title())


def line_with(argv: list[str], path: str) -> list[str]:
    return [path if a == "PATH" else a for a in argv]


def refused(argv: list[str], option: str, name: str, path: str, stubbed: list) -> None:
    status, err = run_main(line_with(argv, path))
    assert_refused_in_one_line(status, err, "Windows", name.upper())
    assert f"{option} {path}".strip() in err, (path, err)
    assert not stubbed, (path, err)  # (refused before any work)


@pytest.mark.parametrize("k", range(len(OUTPUTS)), ids=[" ".join(a) for a, _ in OUTPUTS])
def test_every_reserved_name_as_any_output_is_refused_in_one_line(stubbed, k):
    """Each name as each output, in one of the spellings (each output gets them all)."""
    argv, option = OUTPUTS[k]
    for i, name in enumerate(RESERVED):
        refused(argv, option, name, spelled(name, SPELLINGS[(i + k) % len(SPELLINGS)]), stubbed)


def test_every_reserved_name_in_every_spelling_is_refused(stubbed):
    for name in RESERVED:
        for spelling in SPELLINGS:
            refused(["render", "--out", "PATH"], "--out", name, spelled(name, spelling), stubbed)


@pytest.mark.parametrize("argv, option", OUTPUTS[:2] + OUTPUTS[5:6], ids=["render", "replay", "dir"])
def test_a_reserved_name_as_a_folder_in_the_path_is_refused(stubbed, argv, option):
    for path in ("aux/x.png", "out/Com1.d/x.png", "out/nul .png/x.png", "LPT3\\x.png"):
        status, err = run_main(line_with(argv, path))
        assert_refused_in_one_line(status, err, "Windows")
        assert not stubbed


@pytest.mark.parametrize("argv, option", OUTPUTS, ids=[" ".join(a) for a, _ in OUTPUTS])
def test_names_that_only_look_reserved_are_accepted(stubbed, argv, option):
    for path in FINE:
        if argv[0] in ("maps", "--session-dir", "--screenshot-dir", "serve", "web") or \
                "--session-dir" in argv or "--screenshot-dir" in argv:
            path = path.removesuffix(".png")  # (a folder)
        status, err = run_main(line_with(argv, path))
        assert status == 0 and stubbed and "Windows" not in err, (path, err)
        stubbed.clear()


def test_every_path_option_is_an_output_tested_here_or_an_input():
    """A new option that writes a file must join OUTPUTS (and the check)."""
    tested = {(a[0] if a[0] in build_parser().commands else None, o or a[-1]) for a, o in OUTPUTS}
    found = set()

    def walk(parser: argparse.ArgumentParser, command: str | None) -> None:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    walk(sub, name if command is None else command)
                continue
            flag = action.option_strings[0] if action.option_strings else action.dest
            metavar = str(action.metavar or "")
            if ("FILE" in metavar or "DIR" in metavar) and flag not in INPUTS:
                found.add((command, flag if action.option_strings else "PATH"))
    walk(build_parser(), None)
    assert found <= tested | {(c, "PATH") for c, _ in tested}, found - tested
