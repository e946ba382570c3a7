"""Entry point: `python -m app --help`."""

from __future__ import annotations

import logging
import sys

from app.cli.options import build_parser, check_paths, has_display, params_from
from sim import Params
from sim.session import SessionError

INTERRUPTED = 130  # the shell's status for a program ended by SIGINT (128 + 2)


def main(argv: list[str] | None = None) -> int:
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        params = params_from(args)
        warnings = check_paths(args, parser)
    except ValueError as err:
        parser.error(str(err))
    for warning in warnings:
        print(f"frost: warning: {warning}", file=sys.stderr)
    try:
        return _run(args, params)
    except KeyboardInterrupt:  # Ctrl-C: every file is written atomically, none is half there
        print("frost: interrupted (Ctrl-C)", file=sys.stderr)
        return INTERRUPTED


def _run(args, params: Params) -> int:
    if args.ticks is None and not args.replay:
        args.ticks = 250
    if args.replay:
        _warn_ignored(args)
    windowed = not (args.headless or args.figure8 or args.export_maps)
    no_display = _display_problem() if windowed else None
    if args.replay and windowed and no_display is None:
        try:
            params = _windowed_replay(args)
        except SessionError as err:
            print(f"frost: error: {err}", file=sys.stderr)
            return 2
    if args.figure8:
        from app.tools.figure8 import run as run_figure8
        return run_figure8(args)
    if args.figure:
        from app.tools.figure_fern import run as run_figure
        return run_figure(args, params)
    if args.export_maps:
        from app.tools.maps import run as run_maps
        return run_maps(args, params)
    if not windowed or no_display:
        if no_display:
            print(f"frost: no display ({no_display}): rendering headless to PNG files instead",
                  file=sys.stderr)
        from app.tools.headless import run as run_headless
        return run_headless(args, params)
    from app.window.frost_window import run as run_window
    return run_window(args, params)


def _display_problem() -> str | None:
    """Why no window can open here (None: it can), e.g. DISPLAY naming no server."""
    if not has_display():
        return "DISPLAY is unset"
    from app.window.glfw_setup import display_problem
    return display_problem()


def _warn_ignored(args) -> None:
    """A replay takes its seed, parameters, touches and melts from the session file."""
    given = [name for name, _, _ in Params.describe() if getattr(args, name) is not None]
    given += [f for f in ("preset", "touch", "melt", "melt_path") if getattr(args, f)]
    if given:
        logging.getLogger("app").warning("--replay: ignoring --%s (the session file sets them)",
                                         ", --".join(given))


def _windowed_replay(args) -> Params:
    """Load --replay's session into args (seed, events) for the window; its parameters."""
    from app.tools.headless import load_session

    log_ = load_session(args.replay)
    args.seed, args.touch, args.script, args.view = log_.seed, [], log_.events, log_.view
    return Params(**log_.params)


if __name__ == "__main__":
    sys.exit(main())
