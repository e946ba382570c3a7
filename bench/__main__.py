"""`python -m bench WHAT [ARGS ...]` from a checkout: runs the benchmark WHAT, which parses
every argument after its name itself (--help too)."""

from __future__ import annotations

import importlib
import sys

from app.bench.options import Parser

PROG = "python -m bench"
# Each benchmark, the module whose main(argv, prog) runs it, and what it measures.
BENCHES = {
    "page": ("bench.page", "the phone page against the desktop renderer (parity) and its frame "
             "time; through frost serve: touch latency, joins, scribbles, photos, a phone-like network"),
    "serve": ("bench.serve", "frost serve: bytes a tick and of a snapshot, tick time with 0 and 16 "
              "pages, memory, touch-to-first-delta latency, hostile pages' attacks"),
    "clock": ("bench.clock", "the lock screen's clock: the server's, the desktop's and the page's "
              "work for a new minute"),
    "shaper": ("bench.shaper", "the shaping proxy alone: 127.0.0.1:PORT forwarded to a server "
               "through a phone-like link"),
}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    p = Parser(prog=PROG, usage=f"{PROG} WHAT [ARGS ...]",
               description="The checkout's benchmarks: " + "; ".join(
                   f"{name}: {what}" for name, (_, what) in BENCHES.items()) + ".")
    p.add_argument("what", choices=list(BENCHES), metavar="WHAT",
                   help="the benchmark: " + ", ".join(BENCHES))
    # Only the name is ours: what follows it (--help included) is the benchmark's.
    what = p.parse_args(argv[:1]).what
    module = importlib.import_module(BENCHES[what][0])
    return module.main(argv[1:], prog=f"{PROG} {what}")


if __name__ == "__main__":
    raise SystemExit(main())
