"""`python -m bench WHAT [ARGS ...] [--record]` from a checkout: runs the benchmark WHAT,
which parses every argument after its name itself (--help too); `--record` keeps what it
printed, dated, at the top of docs/results/bench-WHAT.md (app/bench/results.py)."""

from __future__ import annotations

import importlib
import sys

from app.bench.options import Parser
from app.bench.results import keep_printed

PROG = "python -m bench"
# Each benchmark, the module whose main(argv, prog) runs it, and what it measures.
BENCHES = {
    "page": ("bench.page", "the phone page against the desktop renderer (parity) and its frame "
             "time; through frost serve: touch latency, joins, scribbles, photos, a phone-like network"),
    "serve": ("bench.serve", "frost serve: bytes a tick and of a snapshot, tick time with 0 and 16 "
              "pages, memory, touch-to-first-delta latency, hostile pages' attacks"),
    "minute": ("bench.minute", "the lock screen's new minute: the server's, the desktop's and the "
               "page's work for it"),
    "tiles": ("app.bench.tiles", "a window-preset tile grown to its frosted end and its maps "
              "written: time and peak memory"),
    "shaper": ("bench.shaper", "the shaping proxy alone: 127.0.0.1:PORT forwarded to a server "
               "through a phone-like link"),
}
# The shaper forwards until Ctrl-C: it measures nothing to keep.
MEASURES_NOTHING = ("shaper",)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    record = "--record" in argv
    argv = [a for a in argv if a != "--record"]
    p = Parser(prog=PROG, usage=f"{PROG} WHAT [ARGS ...] [--record]",
               description="The checkout's benchmarks: " + "; ".join(
                   f"{name}: {what}" for name, (_, what) in BENCHES.items()) + ".")
    p.add_argument("what", choices=list(BENCHES), metavar="WHAT",
                   help="the benchmark: " + ", ".join(BENCHES))
    p.add_argument("--record", action="store_true", help="also keep what the benchmark printed, "
                   "dated, at the top of docs/results/bench-WHAT.md (any benchmark but the shaper)")
    # Only the name is ours (and --record): what follows it (--help included) is the benchmark's.
    what = p.parse_args(argv[:1]).what
    if record and what in MEASURES_NOTHING:
        p.error(f"--record: {what} measures nothing to keep")
    module = importlib.import_module(BENCHES[what][0])
    prog = f"{PROG} {what}"
    if record:
        return keep_printed(what, prog, argv[1:], module.main)
    return module.main(argv[1:], prog=prog)


if __name__ == "__main__":
    raise SystemExit(main())
