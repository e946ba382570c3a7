"""`python -m bench serve`: what `frost serve` sends and what pages cost it.

1. Bytes, offline (no server): a window pane grown to its frosted end and a fern scribble,
   every delta encoded as the server encodes it: per-tick message p50 / p99 / max, and the
   snapshot a late page gets (the live ice drawn anew, in parts).
2. The server on loopback, in this process, for --seconds each: first with no page (the
   same scribble played by the server itself), then with --pages pages (aiohttp clients in
   a child process, so they do not share this process's interpreter lock): one scribbling,
   one tapping clear glass to time touch-to-first-delta, the others only reading. Printed:
   the simulation thread's tick median and p99, ticks a second, bytes a tick, the pages'
   resyncs, this process's memory (RSS) over time, and the taps' latency median and p95.
3. Attacks (--attack, --grid), each on a new server for --seconds: hostile pages that keep
   within every limit a page has (bench/attacks.py): one socket tapping one spot 86
   times a second (one-spot), a finger swept over the whole pane leaving the page's most
   touches a second, every one at a fresh spot, from one page (all-over) and from 15
   (all-over-15), and a client opening sockets as fast as it can (sockets); each with a
   person's page beside it tapping clear glass (the 16th page); on the preset and on the
   finest grid its checks allow (FINEST).
   Printed: tick median and p99, ticks a second (over the phase and per tenth of it), the
   crystals in the fullest hash cell at the end and the crystals, the touches applied,
   dropped (too much input waiting), skipped (over a page's bound) and still waiting at
   the end (never applied), memory, what the attack sent, and the time from each of the
   person's taps to the first message of the tick that applied it (the session's tick for
   its touch), and how many of their taps applied at all.
Figures only; nothing is asserted.
"""

from __future__ import annotations

import asyncio
import bisect
import itertools
import math
import statistics
import sys

import numpy as np

from app.bench.memory import mb
from app.bench.options import Parser
from app.serve import MAX_PAGES
from app.serve.pages import POINT_RATE
from app.serve.protocol import Encoder
from bench.clients import Plan, scribble_point
from bench.loopback import phase
from sim import Params, all_presets
from sim.io.timeline import Timeline
from sim.look.geometry import FrostGeometry
from sim.params import MAX_HC_PER_SPACING, MAX_UPSAMPLE

# The finest grid sim/params.py lets a preset have: the largest hc (its range's top, 16 px:
# hash cells of 2 hc, so the most crystals one cell can gather), the smallest D at that hc
# (hc / MAX_UPSAMPLE: the most upsample particles a link has) and the smallest geometry
# spacing at it (hc / MAX_HC_PER_SPACING, whole px: the most grid vertices a particle
# raises at that hc). As `frost serve --hc 16 --D 1 --grid-spacing 2`.
HC_MAX = 16.0
FINEST = {"hc": HC_MAX, "D": HC_MAX / MAX_UPSAMPLE,
          "grid_spacing": math.ceil(HC_MAX / MAX_HC_PER_SPACING)}
# Each attack: (its pages' plan, the pages).
ATTACKS = {"one-spot": ("one-spot", 1), "all-over": ("all-over", 1),
           "all-over-15": ("all-over", MAX_PAGES - 1), "taps-15": ("taps", MAX_PAGES - 1),
           "sockets": ("sockets", 0)}
GRIDS = ("default", "fine")


def _figures(sizes) -> str:
    s = np.asarray(sizes, float)
    return (f"p50 {np.percentile(s, 50) / 1e3:.1f} kB, p99 {np.percentile(s, 99) / 1e3:.1f} kB, "
            f"max {s.max() / 1e3:.1f} kB")


def bytes_offline(preset: str, ticks: int, scribble: bool, seed: int = 0) -> None:
    timeline = Timeline(Params.preset(preset), seed)
    geometry = timeline.geometry
    encoder, sizes = Encoder(geometry.cols, geometry.rows), []
    for k in range(ticks):
        if scribble:
            x, y = scribble_point(k / 25.0)
            timeline.apply([{"kind": "touch", "x": x, "y": y}])
        sizes.append(sum(len(encoder.delta(d)) for d in timeline.step()))
    redraw = FrostGeometry(timeline.params).redraw(timeline.sim)
    parts = encoder.snapshot(redraw.tick, redraw.features, redraw.look, redraw.height_scale)
    what = "a touch every tick" if scribble else "no touch"
    print(f"  {preset}, seed {seed}, {ticks} ticks, {what}: per tick {_figures(sizes)}; "
          f"snapshot {sum(map(len, parts)) / 1e6:.2f} MB in {len(parts)} parts "
          f"({len(redraw.features) // 3} triangles)")


def _print_phase(name: str, f: dict) -> None:
    t = np.asarray(f["tick_ms"], float)
    print(f"  {name}: tick median {np.median(t):.2f} ms, p99 {np.percentile(t, 99):.2f} ms, "
          f"{f['rate']:.1f} ticks/s over {f['wall']:.0f} s; bytes a tick {_figures(f['sizes'])}")
    rss = f["rss"]
    print(f"    memory (RSS) {_rss(rss)}" + (f" (samples {', '.join(f'{v:.0f}' for v in rss)})"
                                          if None not in rss else ""))
    if f["bytes"]:
        print(f"    pages received {f['bytes'] / 1e6:.1f} MB; resyncs {f['resyncs']}, "
              f"snapshots drawn {f['redraws']}")
    lat = f["latency"]
    if lat:
        print(f"    touch to first delta: median {1e3 * statistics.median(lat):.0f} ms, "
              f"p95 {1e3 * float(np.percentile(lat, 95)):.0f} ms ({len(lat)} taps)")


def _rss(rss: list) -> str:
    """Resident memory over a phase: first -> last (max), or that it is unavailable."""
    if None in rss:
        return mb(None)
    return f"{rss[0]:.0f} -> {rss[-1]:.0f} MB (max {max(rss):.0f})"


def main(argv: list[str] | None = None, prog: str = "python -m bench serve") -> int:
    p = Parser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--preset", choices=list(all_presets()), default="fern",
                   help="what the server grows (default fern, as frost serve)")
    p.add_argument("--seconds", type=float, default=20.0,
                   help="length of each server phase, s (default 20; 300 for the 5-minute "
                        "memory check)")
    p.add_argument("--pages", type=int, default=16, help="pages connected in the second phase")
    p.add_argument("--skip-bytes", action="store_true", help="skip the offline byte counts")
    p.add_argument("--skip-baseline", action="store_true",
                   help="skip the server phase with no page (e.g. for a long memory run)")
    p.add_argument("--skip-pages", action="store_true",
                   help="skip the server phase with --pages pages")
    p.add_argument("--attack", choices=[*ATTACKS, "none"], action="append",
                   help="an attack to run (repeatable; default: " + ", ".join(ATTACKS)
                        + "; none: no attack)")
    p.add_argument("--grid", choices=GRIDS, action="append",
                   help="the attacks' grid: the preset's (default) or the finest legal one, "
                        "hc 16, D 1, grid spacing 2 (fine) (repeatable; default: both)")
    p.add_argument("--tick-budget", type=float, action="append", metavar="MS",
                   help="the attacks' input budget a tick, ms (repeatable: each attack runs "
                        "with each in turn, to compare them; default: frost serve's)")
    p.add_argument("--rounds", type=int, default=1,
                   help="times each attack runs (with each --tick-budget in turn; default 1)")
    args = p.parse_args(argv)
    if not args.skip_bytes:
        print("bytes (offline, the server's encoder):")
        bytes_offline("window", 2250, scribble=False)
        bytes_offline("fern", 1500, scribble=True)
    params = Params.preset(args.preset)
    if not (args.skip_baseline and args.skip_pages):
        print(f"server on loopback ({args.preset}, seed 0, a finger scribbling):")
    if not args.skip_baseline:
        _print_phase("no page (the server plays the same input)",
                     asyncio.run(phase(params, None, args.seconds)))
    if not args.skip_pages:
        _print_phase(f"{args.pages} pages",
                     asyncio.run(phase(params, Plan("house", args.pages) if args.pages else None,
                                        args.seconds)))
    run_attacks(args.preset, _chosen(args.attack, list(ATTACKS)), args.grid or list(GRIDS),
                args.seconds, [b / 1000.0 for b in args.tick_budget or []], args.rounds)
    sys.stdout.flush()
    return 0


def _chosen(asked: list[str] | None, default: list[str]) -> list[str]:
    """The attacks asked for, in their order, once each (none: the default; "none": none)."""
    if not asked:
        return default
    return [a for a in dict.fromkeys(asked) if a != "none"]


def run_attacks(preset: str, names: list[str], grids: list[str], seconds: float,
                budgets: list[float] | None = None, rounds: int = 1) -> None:
    """Each attack on each grid, `rounds` times, with each of `budgets` (s of input a tick;
    none: frost serve's) in turn: alternated, so a machine's load weighs on each alike."""
    if not names:
        return
    print(f"attacks on loopback (a new server each, seed 0; the pages in a child process, "
          f"within a page's limits; {seconds:g} s each):")
    for grid in dict.fromkeys(grids):
        params = Params.preset(preset, **FINEST) if grid == "fine" else Params.preset(preset)
        where = (f"{preset}, hc {params.hc:g}, D {params.D:g}, grid spacing "
                 f"{params.grid_spacing}" + (" (the finest legal grid)" if grid == "fine" else ""))
        tried: list[float | None] = [*budgets] if budgets else [None]
        for name, _round, budget in itertools.product(names, range(rounds), tried):
            kind, pages = ATTACKS[name]
            figures = asyncio.run(phase(params, Plan(kind, pages, params.hc), seconds, budget))
            said = "" if budget is None else f", input budget {budget * 1000:g} ms a tick"
            print_attack(f"{name} ({where}{said})", figures, pages)
            sys.stdout.flush()


def print_attack(name: str, f: dict, pages: int) -> None:
    t = np.asarray(f["tick_ms"], float)
    print(f"  {name}: tick median {np.median(t):.2f} ms, p99 {np.percentile(t, 99):.2f} ms, "
          f"{f['rate']:.1f} ticks/s over {f['wall']:.0f} s")
    rates, medians = zip(*f["samples"], strict=True) if f["samples"] else ((), ())
    print(f"    each tenth: ticks/s {' '.join(f'{r:.1f}' for r in rates)}; tick median ms "
          f"{' '.join(f'{m:.0f}' for m in medians)}")
    print(f"    fullest hash cell {f['fullest']} crystals; {f['crystals']} crystals "
          f"({f['alive']} alive); touches applied {f['planted']}; touch messages dropped "
          f"{f['dropped']} (too much input waiting), touches skipped {f['skipped']} (over a "
          f"page's {POINT_RATE:g} a second); input waiting at the end {f['waiting']} (never "
          "applied)")
    rss, sent = f["rss"], f["sent"]
    what = (f"opened {sent} sockets ({sent / f['sending_s']:.0f} a second)" if not pages else
            f"sent {sent} messages ({sent / pages / f['sending_s']:.0f} a second each)")
    print(f"    memory (RSS) {_rss(rss)}; the attack "
          f"{what}, the pages received {f['bytes'] / 1e6:.1f} MB; snapshots drawn "
          f"{f['redraws']}; closed by the server: " + (", ".join(f["closed"]) or "none"))
    shown = tap_shown(f)
    said = (f"median {1e3 * statistics.median(shown):.0f} ms, p95 "
            f"{1e3 * float(np.percentile(shown, 95)):.0f} ms, " if shown else "")
    print(f"    a person's taps beside it: tap to the tick that applied it on the page "
          f"{said}{len(shown)} of {len(f['tapped'])} applied")
    tap = f["tap_ms"]
    if tap:
        print(f"    taps (every page's) in the server: received to their tick published median "
              f"{statistics.median(tap):.0f} ms, p95 {float(np.percentile(tap, 95)):.0f} ms "
              f"({len(tap)} taps)")


def tap_shown(f: dict) -> list[float]:
    """Seconds from each of the person's taps that applied to its page's first message of
    the tick that showed it (the tick after the one its touch applied at, in the session)."""
    ticks = sorted(f["tick_at"])
    out = []
    for x, y, sent in f["tapped"]:
        tick = f["touch_ticks"].get((x, y))
        k = bisect.bisect_left(ticks, tick + 1) if tick is not None else len(ticks)
        if k < len(ticks):  # (a tick that changed nothing sends nothing: the next that did)
            out.append(f["tick_at"][ticks[k]] - sent)
    return out


if __name__ == "__main__":
    sys.exit(main())
