"""Scripted runs whose final state is hashed, to pin looks that must not change.

`python -m tests.frozen_runs` prints the hashes; tests/data/frozen_runs.json holds those
computed on the code before the frond rules (issue 20; "window-v3" on the code before the
window's tries were drawn at once), and test_fronds.py checks them. Each run asks for the
rules of the version they were computed under (4; "window-v3" 3): later versions change
how a touch's water and a seed's first hits go.
"""

from __future__ import annotations

import hashlib
import json
import sys

import numpy as np

from sim import FrostSim, Params

# (name, preset or None for Params(), overrides, ticks). Two touches, a melt across the
# first touch's ice half way, so growth, melting and refreezing all leave their mark.
RUNS = [("default", None, {}, 160)] + [
    (name, name, {}, 160) for name in ("a-1", "a-2", "a-3", "b-1", "b-2", "b-3", "c-1", "c-3")
] + [("fern", "fern", {}, 300), ("fern-nogrow", "fern", {"grow": False}, 200)]
# The window preset with every frond rule off: the window look before issue 20.
WINDOW_OLD = ("window-old", "window", None, 400)
# The window preset with its frond rules as a session file of version 3 places its water
# (TRIES rounds of one try each), before the tries were drawn at once.
WINDOW_V3 = ("window-v3", "window", {}, 400)


def state_hash(sim: FrostSim) -> str:
    h = hashlib.sha256()
    for a in (sim.crystals, sim.parents, sim.crystal_alive, sim.upsampled, sim.segments,
              sim.segments_alive, sim.water, sim.water_area):
        h.update(np.ascontiguousarray(a).tobytes())
    h.update(repr((sim.water_created, sim.water_frozen, sim.water_dropped, sim.tick)).encode())
    return h.hexdigest()


def run(preset: str | None, overrides: dict, ticks: int, seed: int = 3, **how) -> FrostSim:
    params = Params(**overrides) if preset is None else Params.preset(preset, **overrides)
    sim = FrostSim(params, seed=seed, **how)
    if not params.window_frost:
        sim.touch(380.0, 640.0)
        sim.touch(520.0, 400.0)
    for _ in range(ticks):
        sim.step()
        if sim.tick == ticks // 2:
            sim.melt(380.0, 640.0, 40.0 if not params.window_frost else 30.0)
            if params.window_frost:
                sim.melt(380.0, 1100.0, 30.0)
    return sim


def hashes(window_off: dict) -> dict[str, str]:
    out = {name: state_hash(run(p, o, t, version=4)) for name, p, o, t in RUNS}
    name, p, _, t = WINDOW_OLD
    out[name] = state_hash(run(p, window_off, t, version=4))
    name, p, o, t = WINDOW_V3
    out[name] = state_hash(run(p, o, t, version=3))
    return out


if __name__ == "__main__":
    json.dump(hashes({}), sys.stdout, indent=1)
    print()
