"""The window section of `frost bench sim` (sim/rules/window_mode.py, the frond rules): the
pane's measures (app/bench/measures.py) per seed over time, the frosted end, a wipe's
regrowth, the one-touch fern tick and the memory."""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from app.bench.growth import CENTRE
from app.bench.measures import END_GAIN, END_TICKS, frosted_end, pane_measures
from sim import FrostSim, Params

WINDOW_TICKS = (500, 1000, 1500, 2250)
MEASURES = ("stem_lw", "main_frac", "pinnate", "order", "clear21", "frame_mid", "cells")
FERN_SEEDS = (0, 3, 11)


def window_run(seed: int, ticks: tuple[int, ...], trace: bool = False) -> dict:
    """The window preset from its start to tick ticks[-1]: the pane's measures at each of
    `ticks` with the median and p99 of the tick times since the previous one, the frosted
    end (app.bench.measures.frosted_end) and the memory."""
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
          f"(app/bench/measures.py) and tick ms since the row before; seeds 0..{seeds - 1}")
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
