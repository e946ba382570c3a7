"""Simulation benchmark: `python -m app.bench.simulation` (or `make bench-sim`). Prints figures;
asserts nothing.

1. Fig. 9: time per tick of the paper's candidate areas vs the general 9-cell hash grid over
   a full growth (one touch until 90 % of the water is frozen, or 5 000 ticks), at c-1..c-3.
2. Tick time at humidity 500 ... 30 000 (c-2 otherwise), timed only on ticks that move at
   least 90 % of the humidity's walkers, and walker steps per second.
3. Growth mode: tick time from one touch until the screen is covered.
4. The simulation's memory after a full c-2 growth.
5. Scribble, storm and spread, in the fern and window looks and at c-2 and c-3 (`--look`
   picks others): tick times (events applied + step + geometry, as the app's simulation
   thread counts them) while a scripted user scribbles for 60 s, while 2 000 touches and
   melts arrive in 10 s, and while a touch a tick lands all over the screen for 1 200
   ticks; walkers, backlog, peak memory, and how many ticks a touch waits for its
   seed's first child.
6. Fern growth (docs/method.md, section 6): shape measures and tick costs of paper c-2 vs fern
   (`--section fern` runs only this).
7. Window mode (sim/rules/window_mode.py, the frond rules): the pane's measures
   (app/bench/measures.py) per seed at ticks 500 / 1000 / 1500 / 2250 with the median and
   p99 tick times, the frosted end, the one-touch fern tick and the memory (`--section
   window` runs only this).
8. Taps (app/bench/taps.py): ticks from a tap to its seed's first child, the page bench's
   taps through the simulation alone, by version 7's and version 8's rules side by side
   (`--section taps`).
9. A storm of taps (app/bench/storm_taps.py): the 2 000 taps of tests/data/storm-2000-taps.json
   in the fern look, crystals and tick times at tick 1 600 for seeds 1-10 by session version
   13's rules and the newest side by side (`--section storm-taps`).

`--record` also keeps the figures as a dated entry of docs/results/bench-sim.md
(app/bench/results.py).
"""

from __future__ import annotations

import json
import platform
import sys

import numpy as np

from app.bench.abuse import ABUSE_LOOKS, section_abuse
from app.bench.fern import fern_section
from app.bench.growth import section_busy, section_fig9, section_growth, section_memory
from app.bench.options import Parser, count
from app.bench.pane import WINDOW_TICKS, window_section
from app.bench.results import commit, keep, record_problem, results_file, shown
from app.bench.storm_taps import storm_taps_section
from app.bench.taps import taps_section
from sim import all_presets

SECTIONS = {"fig9": section_fig9, "busy": section_busy, "growth": section_growth,
            "memory": section_memory, "abuse": section_abuse,
            "fern": lambda args: {"fern": fern_section(*_fern_sizes(args))},
            "window": lambda args: {"window": window_section(*_window_sizes(args))},
            "taps": lambda args: {"taps": taps_section(seeds=1 if args.quick else 4)},
            "storm-taps": lambda args: {"storm_taps": storm_taps_section(seeds=2 if args.quick else 10)}}


def main(argv: list[str] | None = None, prog: str = "python -m app.bench.simulation") -> int:
    ap = Parser(prog=prog, description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=count, default=3, metavar="N",
                    help="full growths per search and preset, runs (default 3)")
    ap.add_argument("--samples", type=count, default=200, metavar="N",
                    help="busy ticks timed per humidity, ticks (default 200)")
    ap.add_argument("--quick", action="store_true",
                    help="a fast smoke run: 1 repeat, 20 samples, shorter scribble, fern and "
                         "window runs")
    ap.add_argument("--section", choices=list(SECTIONS), action="append", metavar="NAME",
                    help="run only this section, one of " + ", ".join(SECTIONS)
                         + " (repeatable; default: all, in that order)")
    ap.add_argument("--look", choices=list(all_presets()), action="append", metavar="NAME",
                    help="the abuse section's looks (repeatable; default: "
                         + ", ".join(ABUSE_LOOKS) + ")")
    ap.add_argument("--record", action="store_true",
                    help=f"also keep the figures, dated, at the top of {shown('sim')} (default off)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = ap.parse_args(argv)
    problem = args.record and record_problem(results_file("sim"))
    if problem:  # said before the sections run, which may take many minutes
        ap.error(f"--record: {problem}")
    head = commit() if args.record else ""  # the code that runs, whatever is committed meanwhile
    if args.quick:
        args.repeats, args.samples = 1, 20
    print(f"# frost sim benchmark: {platform.processor() or platform.machine()}, "
          f"numpy {np.__version__}, python {platform.python_version()}, one thread")
    figures: dict = {}
    for name, section in SECTIONS.items():
        if not args.section or name in args.section:
            figures.update(section(args))
    print(json.dumps(figures))
    # The entry is headed by the command that gives its figures again, without --record.
    command = " ".join([prog, *(a for a in argv if a != "--record")])
    return keep("sim", command, figures, prog, head) if args.record else 0


def _fern_sizes(args) -> tuple[int, int]:
    """Seeds and timed ticks of the fern section (fewer with --quick)."""
    return (2, 50) if args.quick else (5, 250)


def _window_sizes(args) -> tuple[int, tuple[int, ...]]:
    """Seeds and measuring ticks of the window section (fewer with --quick)."""
    return (1, (50, 100)) if args.quick else (3, WINDOW_TICKS)


if __name__ == "__main__":
    raise SystemExit(main())
