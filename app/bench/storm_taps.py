"""A storm of taps through the simulation alone: the 2 000 taps of
tests/data/storm-2000-taps.json (a drag across the screen, then taps all over it, each at
its tick) in the fern look, to tick 1 600, for seeds 1-10, by session version 13's rules
and the newest side by side, interleaved seed by seed so that both see the same machine.
Per run: the crystals alive at tick 1 600, the pool (walkers and owed) then, the water
dropped, and the step's median, p99 and largest time (`frost bench sim --section
storm-taps`; docs/method.md 5.2)."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from sim import FrostSim, Params
from sim.io.session import VERSION as NEWEST

# The checkout's storm (the benchmarks run from a checkout; tests/test_storms.py plays it too).
TAPS = Path(__file__).resolve().parents[2] / "tests" / "data" / "storm-2000-taps.json"
TICKS = 1600
OLD = 13


def storm_taps() -> dict[int, list[tuple[float, float]]]:
    """The storm's taps by tick; OSError naming the file where the checkout lacks it."""
    by_tick: dict[int, list[tuple[float, float]]] = {}
    for e in json.loads(TAPS.read_text(encoding="utf-8")):
        by_tick.setdefault(int(e["tick"]), []).append((float(e["x"]), float(e["y"])))
    return by_tick


def storm_run(taps: dict, seed: int, version: int, ticks: int = TICKS) -> dict:
    """One run of the storm: its figures (see the module doc)."""
    sim = FrostSim(Params.preset("fern"), seed=seed, version=version)
    times = []
    while sim.tick < ticks:
        t0 = time.perf_counter()
        for x, y in taps.get(sim.tick, ()):
            sim.touch(x, y)
        sim.step()
        times.append(time.perf_counter() - t0)
    t = np.array(times) * 1e3
    return {"seed": seed, "version": version, "crystals": int(sim.crystal_alive.sum()),
            "pool": len(sim.water) + sim.supply.waiting, "dropped": sim.water_dropped,
            "median_ms": float(np.median(t)), "p99_ms": float(np.percentile(t, 99)),
            "max_ms": float(t.max())}


def storm_taps_section(seeds: int = 10, ticks: int = TICKS) -> list[dict]:
    """Every seed 1..`seeds` by both versions' rules, printed as a table."""
    try:
        taps = storm_taps()
    except OSError as err:
        print(f"storm-taps: no storm to play ({err}): run it from a checkout")
        return []
    rows = []
    print(f"storm of {sum(len(v) for v in taps.values())} taps, fern, to tick {ticks}")
    print("seed  version  crystals   pool  dropped  median ms  p99 ms  max ms")
    for seed in range(1, seeds + 1):
        for version in (OLD, NEWEST):
            r = storm_run(taps, seed, version, ticks)
            rows.append(r)
            print(f"{seed:4} {version:8} {r['crystals']:9} {r['pool']:6} {r['dropped']:8} "
                  f"{r['median_ms']:10.2f} {r['p99_ms']:7.2f} {r['max_ms']:7.2f}")
    for version in (OLD, NEWEST):
        counts = [r["crystals"] for r in rows if r["version"] == version]
        print(f"version {version}: crystals {min(counts)}-{max(counts)} "
              f"(max / min {max(counts) / max(1, min(counts)):.2f})")
    return rows
