"""The abuse section of `frost bench sim`: a scripted scribble, a storm of touches and melts
and a spread of touches, played as the window's simulation thread plays them
(app/bench/scribble.py); tick-time distributions, backlog, memory and waits."""

from __future__ import annotations

import tracemalloc

import numpy as np

from app.bench.memory import mb, peak_rss_mb
from app.bench.scribble import play, scribble, spread, storm
from sim import Params
from sim.screen import TICKS_PER_SECOND

ABUSE_LOOKS = ("fern", "window", "c-2", "c-3")


def abuse(presets, seconds: float, spread_ticks: int = 1200) -> list[dict]:
    """Tick-time distributions of a scripted scribble, a storm of touches and melts and a
    spread of touches (one a tick, all over the screen) per look; for the paper's presets
    (growth mode off) the storm again with growth mode on. How long touches wait for
    their seed's first child, in ticks."""
    rows = []
    for name in presets:
        params = Params.preset(name)
        kinds = [("scribble", scribble(params, 0, seconds)), ("storm", storm(0)),
                 ("spread", spread(0, spread_ticks))]
        if not params.grow:
            kinds.append(("storm+grow", storm(0)))
        for kind, schedule in kinds:
            p = params.replace(grow=True) if kind == "storm+grow" else params
            played = play(p, schedule, tail=50, drain=True)
            tracemalloc.start()  # a second run for memory: tracing slows every tick
            play(p, schedule, tail=50, drain=True)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            t = 1e3 * played.tick_s
            rows.append({"preset": name, "kind": kind, "ticks": len(t),
                         "median_ms": float(np.median(t)), "p99_ms": float(np.percentile(t, 99)),
                         "max_ms": float(t.max()), "over_40ms": int((t > 40).sum()),
                         "touches": played.touches, "walkers_max": played.walkers_max,
                         "crystals": played.crystals, "backlog_max": played.backlog_max,
                         "drained_s": played.drained / TICKS_PER_SECOND,
                         "traced_peak_mb": peak / 1e6, **_waits(played.first_growth),
                         "on_ice": len(played.first_growth_on_ice),
                         "on_ice_grown": int((played.first_growth_on_ice < 50).sum())})
    return rows


def _waits(ticks: np.ndarray) -> dict:
    """Median and p95 ticks touches waited for their first child (NaN with no touch)."""
    if len(ticks) == 0:
        return {"wait_median": float("nan"), "wait_p95": float("nan")}
    return {"wait_median": float(np.median(ticks)), "wait_p95": float(np.percentile(ticks, 95))}


def print_abuse(rows: list[dict]) -> None:
    print("\n## Scribble (60 s: drags, warm finger, every tuning change), storm (2 000 "
          "touches and melts in 10 s), spread (a touch a tick all over the screen)")
    print("look   kind        ticks  median ms  p99 ms  max ms  >40ms  touches  walkers  "
          "crystals  backlog  drained s  traced MB  wait median  wait p95 "
          "(ticks, touches on glass)  on ice (grew in 2 s)")
    for r in rows:
        print(f"{r['preset']:6} {r['kind']:10} {r['ticks']:6} {r['median_ms']:10.2f} {r['p99_ms']:7.2f} "
              f"{r['max_ms']:7.2f} {r['over_40ms']:6} {r['touches']:8} {r['walkers_max']:8} "
              f"{r['crystals']:9} {r['backlog_max']:8} {r['drained_s']:9.1f} "
              f"{r['traced_peak_mb']:10.1f} "
              f"{r['wait_median']:12.0f} {r['wait_p95']:9.0f} {r['on_ice']:8} ({r['on_ice_grown']})")
    print(f"process peak RSS {mb(peak_rss_mb())}")


def section_abuse(args) -> dict:
    """The scripted scribble and the storm (tick distributions, memory)."""
    rows = abuse(args.look or ABUSE_LOOKS, *((10.0, 200) if args.quick else (60.0, 1200)))
    print_abuse(rows)
    return {"abuse": rows}

