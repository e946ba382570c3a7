"""Simulation benchmark: `python -m app.tools.bench_sim` (or `make bench-sim`). Prints figures;
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
7. Window mode (sim/rules/pane.py, the frond rules): the pane's measures (app/tools/measures.py) per seed at
   ticks 500 / 1000 / 1500 / 2250 with the median and p99 tick times, the frosted end, the
   one-touch fern tick and the memory (`--section window` runs only this).
8. Taps (app/tools/taps.py): ticks from a tap to its seed's first child, the page bench's
   taps through the simulation alone, by version 7's and version 8's rules side by side
   (`--section taps`).
"""

from __future__ import annotations

import argparse
import json
import platform
import resource
import time
import tracemalloc

import numpy as np

from app.tools.measures import END_GAIN, END_TICKS, frosted_end, pane_measures
from app.tools.morphology import extent, mass_radius_dimension, six_fold_order, turn_shares
from app.tools.scribble import play, scribble, spread, storm
from app.tools.taps import taps_section
from sim import FrostSim, Params, all_presets
from sim.look.geometry import FrostGeometry
from sim.screen import TICKS_PER_SECOND

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
    print(f"process peak RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


FERN_TICKS = (25, 50, 125, 250, 500, 750)
FERN_LOOKS = {"c-2": {}, "fern": {}, "fern-nogrow": {"grow": False}}
# Touch spots for the cost runs: the centre, then spread over the screen.
TOUCHES = [CENTRE, (190.0, 320.0), (570.0, 960.0), (570.0, 320.0), (190.0, 960.0),
           (380.0, 200.0), (380.0, 1080.0), (120.0, 640.0), (640.0, 640.0), (380.0, 420.0)]


def fern_shape(name: str, seed: int) -> dict:
    """One touch of look `name` grown for 750 ticks: the fern section's measures."""
    base, extra = ("c-2", {}) if name == "c-2" else ("fern", FERN_LOOKS[name])
    sim = FrostSim(Params.preset(base, **extra), seed=seed)
    sim.touch(*CENTRE)
    row: dict = {"crystals": {}, "reach150": None}
    while sim.tick < FERN_TICKS[-1]:
        sim.step()
        if row["reach150"] is None and extent(sim.crystals, CENTRE) >= 150:
            row["reach150"] = sim.tick
        if sim.tick in FERN_TICKS:
            row["crystals"][sim.tick] = len(sim.crystals)
        if sim.tick == 25:
            row["extent25"] = extent(sim.crystals, CENTRE)
        if sim.tick == 500:
            c, p = sim.crystals, sim.parents
            row.update(dim=mass_radius_dimension(c, CENTRE, sim.params.hc), s6=six_fold_order(c, p),
                       **turn_shares(c, p))
    return row


def fern_costs(name: str, touches: int, ticks: int) -> tuple[float, float]:
    """Median sim and geometry ms per tick over `ticks` ticks from `touches` touches."""
    base, extra = ("c-2", {}) if name == "c-2" else ("fern", FERN_LOOKS[name])
    params = Params.preset(base, **extra)
    sim, geometry = FrostSim(params, seed=0), FrostGeometry(params)
    for x, y in TOUCHES[:touches]:
        sim.touch(x, y)
    t_sim, t_geo = [], []
    for _ in range(ticks):
        t0 = time.perf_counter()
        sim.step()
        t1 = time.perf_counter()
        geometry.update(sim)
        t_sim.append(t1 - t0)
        t_geo.append(time.perf_counter() - t1)
    return 1e3 * float(np.median(t_sim)), 1e3 * float(np.median(t_geo))


def fern_profile(ticks: int) -> dict[str, float]:
    """Mean ms per tick spent in each phase of one fern touch's first `ticks` ticks."""
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(*CENTRE)
    spent = time_phases(sim, more=True)
    for _ in range(ticks):
        sim.step()
    return {k: 1e3 * v / ticks for k, v in spent.items()}


def fern_section(seeds: int, ticks: int) -> dict:
    print(f"\n## Fern growth vs the paper: one touch, seeds 0..{seeds - 1} (median; dimension "
          "and turns at tick 500)")
    print("look        dim   S6  straight  +-60  +-120  150px@tick  extent@25  crystals at "
          + "/".join(map(str, FERN_TICKS)))
    out: dict = {}
    for name in FERN_LOOKS:
        rows = [fern_shape(name, s) for s in range(seeds)]
        med = {k: float(np.median([r[k] for r in rows])) for k in ("dim", "s6", "straight", "60", "120",
                                                                     "extent25")}
        reach = [r["reach150"] or -1 for r in rows]
        counts = [int(np.median([r["crystals"][t] for r in rows])) for t in FERN_TICKS]
        out[name] = {**med, "reach150": reach, "crystals": counts}
        print(f"{name:10} {med['dim']:5.2f} {med['s6']:4.2f} {100 * med['straight']:8.0f}% "
              f"{100 * med['60']:4.0f}% {100 * med['120']:5.0f}% {str(reach):>11}  "
              f"{med['extent25']:6.0f} px  " + "/".join(map(str, counts)))
    print(f"\nms per tick (median of {ticks} ticks from the touches; humidity 3000 each): sim + geometry")
    print("look        1 touch        3 touches      10 touches")
    for name in FERN_LOOKS:  # side by side, so machine load hits every look alike
        cells = [fern_costs(name, n, ticks) for n in (1, 3, 10)]
        out[name]["ms"] = cells
        print(f"{name:10} " + "  ".join(f"{a:5.2f} + {b:5.2f}" for a, b in cells))
    prof = fern_profile(ticks)
    print("\nwhere a fern tick goes (one touch, mean ms; walk includes the relocation of its "
          "leavers, which relocate counts again; counted_and_new: the hits that only counted "
          "placed again and the frozen water's replacement, in one pass): "
          + ", ".join(f"{k} {v:.3f}" for k, v in prof.items()))
    out["fern_profile"] = prof
    return out


WINDOW_TICKS = (500, 1000, 1500, 2250)
MEASURES = ("stem_lw", "main_frac", "pinnate", "order", "clear21", "frame_mid", "cells")
FERN_SEEDS = (0, 3, 11)


def window_run(seed: int, ticks: tuple[int, ...], trace: bool = False) -> dict:
    """The window preset from its start to tick ticks[-1]: the pane's measures at each of
    `ticks` with the median and p99 of the tick times since the previous one, the frosted
    end (app.tools.measures.frosted_end) and the memory."""
    if trace:
        tracemalloc.start()
    sim = FrostSim(Params.preset("window"), seed=seed)
    held = np.zeros(sim.grid.size, bool)
    times: list[float] = []
    cover: list[float] = []
    rows: list[dict] = []
    while sim.tick < ticks[-1]:
        t0 = time.perf_counter()
        new = sim.step().crystals
        times.append(time.perf_counter() - t0)
        c = sim.crystals[new]
        held[sim.grid.keys(c[:, 0], c[:, 1])] = True
        cover.append(float(held.mean()))
        if sim.tick in ticks:
            since = int(rows[-1]["tick"]) if rows else 0
            t = 1e3 * np.array(times[since:])
            rows.append({"tick": sim.tick, **pane_measures(sim), "median_ms": float(np.median(t)),
                         "p99_ms": float(np.percentile(t, 99))})
    peak = tracemalloc.get_traced_memory()[1] if trace else 0
    if trace:
        tracemalloc.stop()
    out = {"end": frosted_end(cover), "crystals": int(sim.crystal_alive.sum()),
           "nbytes": sim.nbytes(), "peak": peak, "times": np.array(times)}
    return {"rows": rows, **out, "wipe": [] if trace else wipe_regrowth(sim)}


WIPE_Y, WIPE_HALF = 640.0, 20.0  # a 40 px wipe across the middle of the pane
WIPE_TICKS = (150, 300, 750)


def band_crystals(sim) -> int:
    """Live crystals in the wiped band."""
    c = sim.crystals[sim.crystal_alive]
    return int((np.abs(c[:, 1] - WIPE_Y) < WIPE_HALF).sum())


def wipe_regrowth(sim) -> list[float]:
    """Wipe the band (a melt every 5 px across the pane), then the band's crystals after
    each of WIPE_TICKS ticks as a share of those before the wipe."""
    before = band_crystals(sim)
    for x in np.arange(0.0, sim.width + 1.0, 5.0):
        sim.melt(float(x), WIPE_Y, WIPE_HALF)
    back = []
    for t in range(1, WIPE_TICKS[-1] + 1):
        sim.step()
        if t in WIPE_TICKS:
            back.append(band_crystals(sim) / max(before, 1))
    return back


def window_section(seeds: int, ticks: tuple[int, ...]) -> dict:
    print(f"\n## Window mode (preset window, default temperature): the pane's measures "
          f"(app/tools/measures.py) and tick ms since the row before; seeds 0..{seeds - 1}")
    print("seed  tick  stem_lw  main_frac  pinnate  order  clear21  frame/mid  cells  "
          "median ms  p99 ms")
    runs = [window_run(s, ticks) for s in range(seeds)]
    for s, r in enumerate(runs):
        for row in r["rows"]:
            print(f"{s:4} {row['tick']:5} " + _measure_cells(row)
                  + f" {row['median_ms']:10.2f} {row['p99_ms']:7.2f}")
    last = {k: float(np.median([r["rows"][-1][k] for r in runs])) for k in (*MEASURES, "median_ms",
                                                                            "p99_ms")}
    whole = 1e3 * np.concatenate([r["times"] for r in runs])
    print(f"median  {ticks[-1]:5} " + _measure_cells(last)
          + f" {last['median_ms']:10.2f} {last['p99_ms']:7.2f}")
    print(f"all ticks 1..{ticks[-1]}: median {np.median(whole):.2f} ms, p99 "
          f"{np.percentile(whole, 99):.2f} ms; frosted end (cells growing under "
          f"{100 * END_GAIN:g} % per {END_TICKS} ticks) at ticks {[r['end'] for r in runs]}")
    print(f"a {2 * WIPE_HALF:g} px wipe across y = {WIPE_Y:g} at tick {ticks[-1]}: the band's "
          "crystals back after " + "/".join(map(str, WIPE_TICKS)) + " ticks, seeds "
          + "; ".join(f"{s}: " + "/".join(f"{100 * v:.0f} %" for v in r["wipe"])
                      for s, r in enumerate(runs)))
    fern = [fern_one_touch(s, 250 if seeds > 1 else 50) for s in FERN_SEEDS]
    print("fern, one touch: median tick ms over its first ticks, seeds "
          + ", ".join(f"{s}: {t:.2f}" for s, t in zip(FERN_SEEDS, fern, strict=True)))
    mem = window_run(0, ticks[-1:], trace=True)
    print(f"memory at tick {ticks[-1]} (seed 0, {mem['crystals']} crystals): array bytes "
          f"{mem['nbytes'] / 1e6:.2f} MB, tracemalloc peak {mem['peak'] / 1e6:.2f} MB")
    return {"runs": [r["rows"] for r in runs], "median": last, "end": [r["end"] for r in runs],
            "wipe": [r["wipe"] for r in runs],
            "fern_ms": fern, "array_bytes": mem["nbytes"], "tracemalloc_peak_bytes": mem["peak"]}


def _measure_cells(row: dict) -> str:
    return (f"{row['stem_lw']:7.1f} {row['main_frac']:10.3f} {row['pinnate']:8.2f} "
            f"{row['order']:6.2f} {row['clear21']:8.3f} {row['frame_mid']:10.2f} "
            f"{row['cells']:6.3f}")


def fern_one_touch(seed: int, ticks: int) -> float:
    """Median ms of the first `ticks` ticks of one fern touch at the centre."""
    sim = FrostSim(Params.preset("fern"), seed=seed)
    sim.touch(*CENTRE)
    times = []
    for _ in range(ticks):
        t0 = time.perf_counter()
        sim.step()
        times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times))


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


def section_abuse(args) -> dict:
    """The scripted scribble and the storm (tick distributions, memory)."""
    rows = abuse(args.look or ABUSE_LOOKS, *((10.0, 200) if args.quick else (60.0, 1200)))
    print_abuse(rows)
    return {"abuse": rows}


SECTIONS = {"fig9": section_fig9, "busy": section_busy, "growth": section_growth,
            "memory": section_memory, "abuse": section_abuse,
            "fern": lambda args: {"fern": fern_section(*_fern_sizes(args))},
            "window": lambda args: {"window": window_section(*_window_sizes(args))},
            "taps": lambda args: {"taps": taps_section(seeds=1 if args.quick else 4)}}


def main(argv: list[str] | None = None, prog: str = "python -m app.tools.bench_sim") -> int:
    ap = _Parser(prog=prog, description=__doc__.splitlines()[0])
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
    args = ap.parse_args(argv)
    if args.quick:
        args.repeats, args.samples = 1, 20
    print(f"# frost sim benchmark: {platform.processor() or platform.machine()}, "
          f"numpy {np.__version__}, python {platform.python_version()}, one thread")
    figures: dict = {}
    for name, section in SECTIONS.items():
        if not args.section or name in args.section:
            figures.update(section(args))
    print(json.dumps(figures))
    return 0


class _Parser(argparse.ArgumentParser):
    """Refuses a bad command line in one line, naming the option, as `frost` does."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def count(text: str) -> int:
    """How many of something a benchmark does (--repeats, --samples, ...): a whole number
    from 1 to 100 000."""
    try:
        n = int(text)
    except ValueError:
        n = 0
    if not 1 <= n <= 100_000:
        raise argparse.ArgumentTypeError(f"{text!r} must be a whole number from 1 to 100000")
    return n


def _fern_sizes(args) -> tuple[int, int]:
    """Seeds and timed ticks of the fern section (fewer with --quick)."""
    return (2, 50) if args.quick else (5, 250)


def _window_sizes(args) -> tuple[int, tuple[int, ...]]:
    """Seeds and measuring ticks of the window section (fewer with --quick)."""
    return (1, (50, 100)) if args.quick else (3, WINDOW_TICKS)


if __name__ == "__main__":
    raise SystemExit(main())
