"""`frost` (and `python -m app`): parse the command line, refuse what makes no sense in
one line, and run the command."""

from __future__ import annotations

import argparse
import logging
import os
import re
import sys
from pathlib import Path

from app.backdrops import load_backdrop, view_from
from app.bench.results import record_problem, results_file
from app.cli.parser import PROG, build_parser, parser_for
from app.cli.paths import check_paths
from app.cli.shared_options import WINDOW_DEFAULTS, has_display, params_from
from sim import Params
from sim.io.files import one_line
from sim.io.session import SessionError
from sim.screen import touch_problem

NEGATIVE = re.compile(r"-(\.?\d|inf|nan)", re.IGNORECASE)  # -1,0, -.5@3 or -inf,0: a value, not an option
INTERRUPTED = 130  # the shell's status for a program ended by SIGINT (128 + 2)
# The mode flags of the one-parser command line before subcommands, and what replaced them.
MOVED = {"--headless": "frost render", "--replay": "frost replay FILE.json",
         "--figure8": "frost figure8 FILE.png", "--figure": "frost figure fern FILE.png",
         "--export-maps": "frost maps DIR", "--screenshot": "--out FILE.png (frost render)"}
# The benchmarks that drive a browser or load the server with scripted pages: they left the
# package for the checkout's bench/ (docs/benchmarks.md): they need the test stack's browser driver.
BENCH_MOVED = ("page", "serve")


def main(argv: list[str] | None = None) -> int:
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        if argv[:2] == ["bench", "sim"]:  # its arguments are the benchmark's to parse
            from app.bench.simulation import main as bench_sim
            return bench_sim(argv[2:], prog="frost bench sim")
        if argv[:2] in (["bench", what] for what in BENCH_MOVED):  # a checkout's now
            return _bench_moved(argv[1])
        args, params = _parse(argv)
        return RUN[args.command](args, params)
    except KeyboardInterrupt:  # Ctrl-C: every file is written atomically, none is half there
        print(f"{PROG}: interrupted (Ctrl-C)", file=sys.stderr)
        return INTERRUPTED


def _bench_moved(what: str) -> int:
    """The one line that says where a benchmark of the checkout went (exit status 2)."""
    print(f"{PROG} bench {what}: error: it moved out of the package: run "
          f"`python -m bench {what}` from a checkout", file=sys.stderr)
    return 2


def _parse(argv: list[str]) -> tuple[argparse.Namespace, Params]:
    """The command line's arguments and Params, or a one-line error (exit status 2); warns
    of the window's folders that cannot be written."""
    parser = build_parser()
    moved = _moved_option(argv)
    if moved:
        parser.error(moved)
    args, unknown = parser.parse_known_args(_joined_negatives(argv, parser))
    command = parser_for(parser, args)
    if unknown:
        command.error(f"unrecognized arguments: {' '.join(unknown)}")
    try:
        params = params_from(args)
        _refuse_nonsense(args, argv, command.prog)
        warnings = check_paths(args, command)
    except ValueError as err:
        command.error(str(err))
    for warning in warnings:
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    return args, params


def _joined_negatives(argv: list[str], parser: argparse.ArgumentParser) -> list[str]:
    """argv with each value that starts like a negative number written onto its option
    (--touch=-1,0): argparse takes only plain numbers such as -1 for a value, and would say
    that --touch -1,0 lacks one instead of what is wrong with -1,0."""
    valued = _valued_options(parser)
    out: list[str] = []
    for arg in argv:
        if out and out[-1] in valued and NEGATIVE.match(arg):
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


def _valued_options(parser: argparse.ArgumentParser) -> set[str]:
    """Every option string of `parser` and its subcommands' that takes a value."""
    found: set[str] = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found |= _valued_options(sub)
        elif action.option_strings and action.nargs != 0:
            found.update(action.option_strings)
    return found


def _moved_option(argv: list[str]) -> str | None:
    """Why an option of the old command line is not one any more (None: none is used)."""
    for arg in argv:
        flag = arg.split("=", 1)[0]
        if flag in MOVED and not (flag == "--headless" and argv[:1] == ["replay"]):
            return f"{flag} is gone: use {MOVED[flag]}"
        if flag.startswith("--") and "_" in flag:
            return f"{flag}: options are spelled with dashes: {flag.replace('_', '-')}"
    return None


def _refuse_nonsense(args: argparse.Namespace, argv: list[str], prog: str) -> None:
    """ValueError naming the options of a combination the grammar lets through (`prog`:
    the command as typed, e.g. frost bench sim)."""
    if args.command and argv[:1] != [args.command]:
        raise ValueError(f"the window's options do not go before a command: write "
                         f"{prog} [options]")
    if args.command == "maps":
        _refuse_maps(args)
    if args.command == "bench" and args.record:  # before minutes of work, not after
        problem = record_problem(results_file("render"))
        if problem:
            raise ValueError(f"--record: {problem}")
    if args.command == "serve" and args.window:
        problem = display_problem()
        if problem:
            raise ValueError(f"--window: no window can open here ({problem})")
    if args.command == "figure8" and len(args.touch) > 1:
        raise ValueError(f"figure8 grows from one --touch; got {len(args.touch)} --touch options")
    if args.command == "render" and (args.melt or args.melt_path) and not args.touch \
            and not args.window_mode:  # a frosted window grows untouched; the demo takes none
        raise ValueError("--melt and --melt-path need --touch (or --window-frost): the scripted "
                         "demo takes none")
    late = [m for m in getattr(args, "melt", []) + getattr(args, "melt_path", [])
            if m["tick"] > args.ticks]
    if args.command == "render" and late:  # the last applied is at --ticks, on the final frame
        raise ValueError(f"a melt at tick {late[0]['tick']} comes after the last tick "
                         f"(--ticks {args.ticks}) and would never apply")
    if args.command == "replay" and _replay_headless(args):
        window = [f"--{n.replace('_', '-')}" for n, d in WINDOW_DEFAULTS.items()
                  if getattr(args, n) != d]
        if window:
            raise ValueError(f"{', '.join(window)}: window options, but --headless, --out or "
                             "--ticks make this replay headless")


def _refuse_maps(args: argparse.Namespace) -> None:
    """frost maps: every touch on the maps' --size."""
    for x, y in args.touch:
        problem = touch_problem(x, y, tuple(args.size))
        if problem:
            raise ValueError(problem)


def _replay_headless(args: argparse.Namespace) -> bool:
    return bool(args.headless or args.out or args.ticks is not None)


def _window(args: argparse.Namespace, params: Params) -> int:
    """The window; with no display, the headless render of the same command line."""
    problem = display_problem()
    if problem:
        print(f"{PROG}: no display ({problem}): rendering headless to PNG files instead",
              file=sys.stderr)
        from app.tools.render_png import run
        return run(args, params)
    from app.window.frost_window import run
    args.view = view_from(args)
    return run(args, params)


def _render(args: argparse.Namespace, params: Params) -> int:
    from app.tools.render_png import run
    return run(args, params)


def _replay(args: argparse.Namespace, params: Params) -> int:
    """The session's parameters, or with --params a what-if replay under `params`."""
    what_if = params if args.params_file else None
    if _replay_headless(args) or display_problem():
        from app.tools import replay
        return replay.run(args, what_if)
    try:
        params = _windowed_replay(args, what_if)
    except SessionError as err:
        from app.tools.replay import refuse
        return refuse(err)
    from app.window import frost_window
    return frost_window.run(args, params)


def _windowed_replay(args: argparse.Namespace, what_if: Params | None = None) -> Params:
    """Load the replay's session into args (seed, events) for the window; its parameters
    (those of `what_if` if given, see replay.under)."""
    from app.photos import copy_photos, store_of
    from app.tools.replay import load_session, missing_photo, start_view, under

    log_ = load_session(args.replay)
    if what_if is not None:
        log_ = under(log_, what_if, args.params_file)
    args.seed, args.touch, args.script = log_.seed, [], log_.events
    args.session_version = log_.version  # its rules, not the newest
    args.view = start_view(log_, getattr(args, "background", None))
    args.fixed_backdrop = getattr(args, "background", None) is not None
    photos = store_of(Path(args.replay).parent)
    missing = None if args.fixed_backdrop else missing_photo(log_, photos)
    if missing:
        raise SessionError(f"{one_line(str(args.replay))}: cannot replay: {missing}")
    keeps = store_of(getattr(args, "session_dir", WINDOW_DEFAULTS["session_dir"]))
    try:  # (the session the window keeps, in its own folder, shows them too)
        copy_photos([e["name"] for e in log_.events if e["kind"] == "backdrop"], photos, keeps)
    except OSError as err:
        logging.getLogger("app.replay").warning(
            "the replayed session's photos could not be copied to %s: %s", keeps, err)
    background = (args.view or {}).get("background")
    if background is not None:  # a session's own file may have gone since it was saved
        try:
            load_backdrop(background)
        except ValueError as err:
            raise SessionError(f"{one_line(str(args.replay))}: cannot replay: {err}") from None
    return Params(**log_.params)


def _figure8(args: argparse.Namespace, params: Params) -> int:
    from app.tools.figure8 import run
    return run(args, params if args.params_file else None)


def _figure(args: argparse.Namespace, params: Params) -> int:
    from app.tools.figure_fern import run
    return run(args, params)


def _maps(args: argparse.Namespace, params: Params) -> int:
    from app.tools.maps import run
    return run(args, params)


def _bench_render(args: argparse.Namespace, params: Params) -> int:
    from app.bench.render import run
    return run(args, params)


def _serve(args: argparse.Namespace, params: Params) -> int:
    from app.serve.command import serve
    return serve(args, params)


def _web(args: argparse.Namespace, params: Params) -> int:
    from app.tools.web_site import run
    return run(args, params)


def _info(args: argparse.Namespace, params: Params) -> int:
    from app.tools.info import run
    return run(args, params)


RUN = {None: _window, "render": _render, "replay": _replay, "figure8": _figure8,
       "figure": _figure, "maps": _maps, "bench": _bench_render, "serve": _serve,
       "web": _web, "info": _info}


def no_display_words(env) -> str:
    """Why `env` names no display: DISPLAY (and WAYLAND_DISPLAY) unset, or set to nothing."""
    empty = [name for name in ("DISPLAY", "WAYLAND_DISPLAY") if env.get(name) == ""]
    return f"{' and '.join(empty)} set but empty" if empty else "DISPLAY is unset"


def display_problem() -> str | None:
    """Why no window can open here (None: it can), e.g. DISPLAY naming no server."""
    if not has_display():
        return no_display_words(os.environ)
    from app.window.glfw_setup import display_problem as probe
    return probe()

