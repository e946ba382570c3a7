"""Entry point: `python -m app --help`."""

from __future__ import annotations

import logging
import sys

from .cli import build_parser, has_display, params_from


def main(argv: list[str] | None = None) -> int:
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        params = params_from(args)
    except ValueError as err:
        parser.error(str(err))
    if args.figure8:
        from .figure8 import run as run_figure8
        return run_figure8(args)
    if args.export_maps:
        from .maps import run as run_maps
        return run_maps(args, params)
    if args.headless or not has_display():
        from .headless import run as run_headless
        return run_headless(args, params)
    from .window import run as run_window
    return run_window(args, params)


if __name__ == "__main__":
    sys.exit(main())
