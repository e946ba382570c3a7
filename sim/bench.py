"""Simulation benchmark: `python -m sim.bench` (or `make bench-sim`). Prints figures; asserts nothing.

1. Fig. 9: time per tick of the paper's candidate areas vs the general 9-cell hash grid over
   a full growth (one touch until 90 % of the water is frozen, or 5 000 ticks), at c-1..c-3.
2. Tick time at humidity 500 ... 100 000 (c-2 otherwise), timed only on ticks that move at
   least 90 % of the humidity's walkers, and walker steps per second.
3. Growth mode: tick time from one touch until the screen is covered.
4. The simulation's memory after a full c-2 growth.
5. Scribble and storm: tick times (events applied + step + geometry, as the app's
   simulation thread counts them) while a scripted user scribbles for 60 s and while
   2 000 touches and melts arrive in 10 s; walkers, backlog and peak memory.
"""

from __future__ import annotations

import argparse
import json
import platform
import resource
import time
import tracemalloc

import numpy as np

from . import FrostSim, Params
from .scribble import play, scribble, storm

CENTRE = (380.0, 640.0)


def full_growth(params: Params, seed: int, max_ticks: int = 5000) -> tuple[FrostSim, list[float]]:
    """Grow one touch until 90 % of its water froze; returns the sim and each tick's seconds."""
    sim = FrostSim(params, seed=seed)
    sim.touch(*CENTRE)
    times = []
    clock = time.perf_counter
    while len(times) < max_ticks and sim.water_frozen < 0.9 * sim.water_created and len(sim.water_area):
        t0 = clock()
        sim.step()
        times.append(clock() - t0)
    return sim, times


def fig9(presets: list[str], repeats: int) -> list[dict]:
    rows = []
    for name in presets:
        totals: dict[str, list[float]] = {"candidate": [], "grid9": []}
        ticks = {}
        for r in range(repeats):  # alternate the two so drift hits both alike
            for mode in totals:
                sim, times = full_growth(Params.preset(name, neighbor_search=mode), seed=r)
                totals[mode].append(sum(times))
                ticks[mode] = len(times)
        cand, grid = (float(np.median(totals[m])) for m in ("candidate", "grid9"))
        rows.append({"preset": name, "ticks": ticks["candidate"], "candidate_s": cand, "grid9_s": grid,
                     "candidate_ms_per_tick": 1e3 * cand / ticks["candidate"],
                     "grid9_ms_per_tick": 1e3 * grid / ticks["grid9"], "ratio": grid / cand})
    return rows


PHASES = ("_walk", "_crystallize", "_link", "_register", "_forget_water")


def phase_profile(preset: str, mode: str, repeats: int) -> dict[str, float]:
    """Seconds per full growth spent in each phase of a tick (median over `repeats`)."""
    runs: dict[str, list[float]] = {p.strip("_"): [] for p in PHASES}
    for r in range(repeats):
        sim = FrostSim(Params.preset(preset, neighbor_search=mode), seed=r)
        spent = dict.fromkeys(runs, 0.0)
        for phase in PHASES:
            setattr(sim, phase, _timed(getattr(sim, phase), spent, phase.strip("_")))
        sim.touch(*CENTRE)
        while sim.tick < 5000 and sim.water_frozen < 0.9 * sim.water_created and len(sim.water_area):
            sim.step()
        for k, v in spent.items():
            runs[k].append(v)
    return {k: float(np.median(v)) for k, v in runs.items()}


def _timed(fn, spent: dict[str, float], name: str):
    def wrapper(*a):
        t0 = time.perf_counter()
        out = fn(*a)
        spent[name] += time.perf_counter() - t0
        return out
    return wrapper


def busy_ticks(humidity: int, samples: int) -> list[float]:
    """Seconds of ticks that start with at least 90 % of `humidity` walkers."""
    params = Params.preset("c-2", humidity=humidity)
    times: list[float] = []
    seed = 0
    while len(times) < samples:
        sim = FrostSim(params, seed=seed)
        sim.touch(*CENTRE)
        seed += 1
        while len(times) < samples and len(sim.water_area) >= 0.9 * humidity:
            t0 = time.perf_counter()
            sim.step()
            times.append(time.perf_counter() - t0)
    return times


def growth_curve(window: int = 100, max_ticks: int = 3000) -> list[dict]:
    """Growth mode at humidity 3 000: tick times per window of ticks, from the first crystal
    until the screen is covered (99 % of hash cells are candidate cells), its water
    has nowhere left to go, or `max_ticks`."""
    sim = FrostSim(Params.preset("c-2", grow=True), seed=0)
    sim.touch(*CENTRE)
    rows, times = [], []
    while sim.tick < max_ticks:
        t0 = time.perf_counter()
        sim.step()
        times.append(time.perf_counter() - t0)
        if len(times) == window:
            t = np.array(times)
            rows.append({"tick": sim.tick, "crystals": len(sim.crystals),
                         "covered": float((sim.candidates.count > 0).mean()),
                         "median_ms": 1e3 * float(np.median(t)), "max_ms": 1e3 * float(t.max())})
            times = []
            if rows[-1]["covered"] >= 0.99 or len(sim.water_area) == 0:
                break
    return rows


def memory() -> dict:
    sim, _ = full_growth(Params.preset("c-2"), seed=0)
    tracemalloc.start()
    traced, _ = full_growth(Params.preset("c-2"), seed=0)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return {"array_bytes": sim.nbytes(), "tracemalloc_peak_bytes": peak,
            "crystals": len(sim.crystals)}


def abuse(presets: list[str], seconds: float) -> list[dict]:
    """Tick-time distributions of a scripted scribble and a storm of input per preset."""
    rows = []
    for name in presets:
        params = Params.preset(name)
        for kind, schedule in (("scribble", scribble(params, 0, seconds)), ("storm", storm(0)),
                               ("storm+grow", storm(0))):
            p = params.replace(grow=True) if kind == "storm+grow" else params
            played = play(p, schedule, tail=50)
            tracemalloc.start()  # a second run for memory: tracing slows every tick
            play(p, schedule, tail=50)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            t = 1e3 * played.tick_s
            rows.append({"preset": name, "kind": kind, "ticks": len(t),
                         "median_ms": float(np.median(t)), "p99_ms": float(np.percentile(t, 99)),
                         "max_ms": float(t.max()), "over_40ms": int((t > 40).sum()),
                         "touches": played.touches, "walkers_max": played.walkers_max,
                         "crystals": played.crystals, "backlog_max": played.backlog_max,
                         "traced_peak_mb": peak / 1e6})
    return rows


def print_abuse(rows: list[dict]) -> None:
    print("\n## Scribble (60 s: drags, warm finger, every tuning change) and storm (2 000 "
          "touches and melts in 10 s)")
    print("preset kind        ticks  median ms  p99 ms  max ms  >40ms  touches  walkers  crystals  "
          "backlog  traced MB")
    for r in rows:
        print(f"{r['preset']:6} {r['kind']:10} {r['ticks']:6} {r['median_ms']:10.2f} {r['p99_ms']:7.2f} "
              f"{r['max_ms']:7.2f} {r['over_40ms']:6} {r['touches']:8} {r['walkers_max']:8} "
              f"{r['crystals']:9} {r['backlog_max']:8} {r['traced_peak_mb']:10.1f}")
    print(f"process peak RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


SECTIONS = ("fig9", "busy", "growth", "memory", "abuse")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m sim.bench", description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="full growths per mode and preset")
    ap.add_argument("--samples", type=int, default=200, help="busy ticks timed per humidity")
    ap.add_argument("--quick", action="store_true", help="a fast smoke run")
    ap.add_argument("--section", choices=SECTIONS, action="append",
                    help="run only this section (repeatable; default: all)")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeats, args.samples = 1, 20
    print(f"# frost sim benchmark: {platform.processor() or platform.machine()}, "
          f"numpy {np.__version__}, python {platform.python_version()}, one thread")
    if args.section:
        run_sections(args)
        return
    rows = fig9(["c-1", "c-2", "c-3"], args.repeats)
    print("\n## Fig. 9: full growth from one touch (median of", args.repeats, "runs)")
    print("preset  ticks  candidate ms/tick  grid9 ms/tick  total cand s  total grid9 s  grid9/cand")
    for r in rows:
        print(f"{r['preset']:6} {r['ticks']:6} {r['candidate_ms_per_tick']:18.3f} "
              f"{r['grid9_ms_per_tick']:14.3f} {r['candidate_s']:13.3f} {r['grid9_s']:14.3f} "
              f"{r['ratio']:11.1f}x")
    print("\n## Where a full c-2 growth spends its time, per phase (ms, median of", args.repeats, "runs)")
    prof = {m: phase_profile("c-2", m, args.repeats) for m in ("candidate", "grid9")}
    print("phase         candidate    grid9")
    for phase in prof["candidate"]:
        print(f"{phase:12} {1e3 * prof['candidate'][phase]:10.2f} {1e3 * prof['grid9'][phase]:8.2f}")
    print(f"\n## Busy ticks (>= 90 % of walkers moving), c-2, {args.samples} ticks each")
    print("humidity  median ms  p95 ms  walker steps/s")
    busy = []
    for hum in (500, 3000, 5000, 30000, 100000):
        t = np.array(busy_ticks(hum, args.samples))
        med, p95 = float(np.median(t)), float(np.percentile(t, 95))
        busy.append({"humidity": hum, "median_ms": 1e3 * med, "p95_ms": 1e3 * p95,
                     "walker_steps_per_s": hum / med})
        print(f"{hum:8} {1e3 * med:10.3f} {1e3 * p95:7.3f} {hum / med / 1e6:11.1f} M")
    curve = growth_curve()
    print("\n## Growth mode (grow=on), humidity 3000: one touch until the screen is covered")
    print(" tick  crystals  covered  median ms  max ms")
    for r in curve:
        print(f"{r['tick']:5} {r['crystals']:9} {100 * r['covered']:7.1f}% {r['median_ms']:10.3f} "
              f"{r['max_ms']:7.2f}")
    mem = memory()
    print(f"\n## Memory after a full c-2 growth ({mem['crystals']} crystals)")
    print(f"array bytes {mem['array_bytes'] / 1e6:.2f} MB, "
          f"tracemalloc peak {mem['tracemalloc_peak_bytes'] / 1e6:.2f} MB")
    abused = abuse(["c-2", "c-3"], 10.0 if args.quick else 60.0)
    print_abuse(abused)
    print(json.dumps({"fig9": rows, "phases": prof, "busy": busy, "growth": curve, "memory": mem,
                      "abuse": abused}))


def run_sections(args) -> None:
    """Only the sections asked for (those with a printer of their own)."""
    if "abuse" in args.section:
        rows = abuse(["c-2", "c-3"], 10.0 if args.quick else 60.0)
        print_abuse(rows)
        print(json.dumps({"abuse": rows}))
    others = set(args.section) - {"abuse"}
    if others:
        print(f"(sections {', '.join(sorted(others))} run only as part of the full benchmark)")


if __name__ == "__main__":
    main()
