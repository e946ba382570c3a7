"""The paper's figures for `frost bench sim`: Fig. 9 (candidate areas against the 9-cell
hash grid, with where a tick's time goes), busy ticks at five humidities, growth mode until
the screen is covered, and the memory of a full growth."""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from sim import FrostSim, Params

CENTRE = (380.0, 640.0)


def full_growth(params: Params, seed: int, max_ticks: int = 5000) -> tuple[FrostSim, list[float]]:
    """Grow one touch until 90 % of its water froze; returns the sim and each tick's seconds."""
    sim = FrostSim(params, seed=seed)
    sim.touch(*CENTRE)
    times: list[float] = []
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


def phases(sim: FrostSim, more: bool = False) -> list[tuple[object, str, str]]:
    """(owner, method, name) of a tick's phases, in the order a tick calls them (`more`:
    also the fern tick's admission, settling, relocations and growth-mode follow-up)."""
    main = [(sim, "walk", "walk"), (sim, "crystallize", "crystallize"), (sim, "_link", "link"),
            (sim.index, "register", "register"), (sim.supply, "spent", "forget_water")]
    extra = [(sim, "_admit", "admit"), (sim.growth, "settle", "settle"),
             (sim.supply, "relocate", "relocate"),
             (sim.supply, "relocate_then_spawn", "counted_and_new"),
             (sim, "_follow_ice", "follow_ice")]
    return main + extra if more else main


def time_phases(sim: FrostSim, more: bool = False) -> dict[str, float]:
    """Wrap `sim`'s phases (`phases`) to add their seconds to the returned dict."""
    spent: dict[str, float] = {}
    for owner, method, name in phases(sim, more):
        spent[name] = 0.0
        setattr(owner, method, _timed(getattr(owner, method), spent, name))
    return spent


def phase_profile(preset: str, mode: str, repeats: int) -> dict[str, float]:
    """Seconds per full growth spent in each phase of a tick (median over `repeats`)."""
    runs: dict[str, list[float]] = {}
    for r in range(repeats):
        sim = FrostSim(Params.preset(preset, neighbor_search=mode), seed=r)
        spent = time_phases(sim)
        sim.touch(*CENTRE)
        while sim.tick < 5000 and sim.water_frozen < 0.9 * sim.water_created and len(sim.water_area):
            sim.step()
        for k, v in spent.items():
            runs.setdefault(k, []).append(v)
    return {k: float(np.median(v)) for k, v in runs.items()}


def _timed(fn, spent: dict[str, float], name: str):
    def wrapper(*a):
        t0 = time.perf_counter()
        out = fn(*a)
        spent[name] += time.perf_counter() - t0
        return out
    return wrapper


def busy_ticks(humidity: int, samples: int) -> list[float]:
    """Seconds of ticks that start with at least 90 % of `humidity` walkers (the screen's
    water budget raised to `humidity` where it is below, so that one touch can hold them)."""
    budget = max(humidity, Params().water_budget)
    return busy_ticks_for(Params.preset("c-2", humidity=humidity, water_budget=budget), samples)


def busy_ticks_for(params: Params, samples: int) -> list[float]:
    """Seconds of ticks that start with at least 90 % of `params.humidity` walkers."""
    humidity = params.humidity
    times: list[float] = []
    seed = 0
    while len(times) < samples:
        sim = FrostSim(params, seed=seed)
        sim.touch(*CENTRE)
        seed += 1
        if len(sim.water_area) < 0.9 * humidity:
            raise ValueError(f"a touch brought {len(sim.water_area)} of {humidity} walkers: "
                             "no tick of it can be busy")
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


def section_fig9(args) -> dict:
    """Fig. 9's table and where a c-2 growth spends its time, for both searches."""
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
    return {"fig9": rows, "phases": prof}


# The largest is the most water the screen's budget may hold (`water_budget`'s range).
BUSY_HUMIDITIES = (500, 3000, 5000, 10000, 30000)


def section_busy(args) -> dict:
    """Tick times when nearly every walker moves, at five humidities."""
    print(f"\n## Busy ticks (>= 90 % of walkers moving), c-2, {args.samples} ticks each")
    print("humidity  median ms  p95 ms  walker steps/s")
    busy = []
    for hum in BUSY_HUMIDITIES:
        t = np.array(busy_ticks(hum, args.samples))
        med, p95 = float(np.median(t)), float(np.percentile(t, 95))
        busy.append({"humidity": hum, "median_ms": 1e3 * med, "p95_ms": 1e3 * p95,
                     "walker_steps_per_s": hum / med})
        print(f"{hum:8} {1e3 * med:10.3f} {1e3 * p95:7.3f} {hum / med / 1e6:11.1f} M")
    return {"busy": busy}


def section_growth(args) -> dict:
    """Growth mode from one touch until the screen is covered."""
    curve = growth_curve()
    print("\n## Growth mode (grow=on), humidity 3000: one touch until the screen is covered")
    print(" tick  crystals  covered  median ms  max ms")
    for r in curve:
        print(f"{r['tick']:5} {r['crystals']:9} {100 * r['covered']:7.1f}% {r['median_ms']:10.3f} "
              f"{r['max_ms']:7.2f}")
    return {"growth": curve}


def section_memory(args) -> dict:
    """What a full c-2 growth holds."""
    mem = memory()
    print(f"\n## Memory after a full c-2 growth ({mem['crystals']} crystals)")
    print(f"array bytes {mem['array_bytes'] / 1e6:.2f} MB, "
          f"tracemalloc peak {mem['tracemalloc_peak_bytes'] / 1e6:.2f} MB")
    return {"memory": mem}

