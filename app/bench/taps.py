"""Taps on the phone, through the simulation alone: how many ticks each tap's seed waits
for its first child (the desktop log's and the page's "growth"). `frost bench sim --section
taps` prints it for every session version's rules side by side; `python -m bench page --taps`
taps the same spots through `frost serve`."""

from __future__ import annotations

import numpy as np

from sim import FrostSim, Params
from sim.screen import HEIGHT, TICKS_PER_SECOND, WIDTH

# A tap every 0.7 s, 40 px or more from the screen's edges (the page bench's taps).
GAP_S = 0.7
MARGIN = 40.0
# A seed with no child this many ticks after its tap never grows: it lies in ice whose
# slots around it are taken (docs/method.md, 5.3).
NEVER = 120


def tap_spots(n: int, seed: int = 7) -> np.ndarray:
    """`n` (x, y) spots, uniform on the screen less MARGIN, drawn x then y per tap."""
    rng = np.random.default_rng(seed)
    return np.array([(rng.uniform(MARGIN, WIDTH - MARGIN), rng.uniform(MARGIN, HEIGHT - MARGIN))
                     for _ in range(n)])


def waits(preset: str, version: int, taps: int, seed: int, spots_seed: int = 7) -> np.ndarray:
    """Ticks from each of `taps` taps (GAP_S apart, at `tap_spots`) to its seed's first
    child, by the rules of session `version`; NEVER for a seed with none by then. A tap
    is applied before a tick, as the simulation thread applies one; its seed's wait keeps
    counting through the next taps."""
    sim = FrostSim(Params.preset(preset), seed=seed, version=version)
    tick_of_tap = np.floor(np.arange(taps) * GAP_S * TICKS_PER_SECOND).astype(int)
    seeds, out = [], np.full(taps, NEVER)
    spots = tap_spots(taps, spots_seed)
    for tick in range(int(tick_of_tap[-1]) + NEVER):
        for k in np.flatnonzero(tick_of_tap == tick):
            sim.touch(*spots[k])
            seeds.append((k, len(sim.crystals) - 1, tick))
        sim.step()
        if not seeds:
            continue
        waiting = [(k, s, t) for k, s, t in seeds if out[k] == NEVER]
        if not waiting:
            if len(seeds) == taps:
                break
            continue
        grown = np.isin([s for _, s, _ in waiting], sim.parents[sim.crystal_alive])
        for (k, _, t), g in zip(waiting, grown, strict=True):
            if g and sim.tick - t <= NEVER:
                out[k] = sim.tick - t
    return out


def taps_section(presets=("fern", "c-2", "window"), versions=(7, 8), taps: int = 32,
                 seeds: int = 4) -> dict:
    print(f"\n## Taps: ticks from a tap to its seed's first child ({taps} taps {GAP_S} s apart "
          f"at the page bench's spots, sim seeds 0..{seeds - 1}, the simulation alone; "
          f"'never': none in {NEVER} ticks, a seed in finished ice)")
    print("preset   version  median  p90  p95  max   never")
    out: dict = {}
    for preset in presets:
        for version in versions:
            w = np.concatenate([waits(preset, version, taps, s) for s in range(seeds)])
            grew = w[w < NEVER]
            row = {"median": float(np.median(grew)), "p90": float(np.percentile(grew, 90)),
                   "p95": float(np.percentile(grew, 95)), "max": int(grew.max()),
                   "never": int((w >= NEVER).sum()), "taps": int(len(w))}
            out[f"{preset}/v{version}"] = row
            print(f"{preset:8} {version:7} {row['median']:7.0f} {row['p90']:4.0f} "
                  f"{row['p95']:4.0f} {row['max']:4}   {row['never']}/{row['taps']}")
    return out
