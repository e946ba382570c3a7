"""Scripted runs whose final state is hashed, to pin looks that must not change.

`python -m tests.frozen_runs` prints the hashes; tests/data/frozen_runs.json holds them and
test_fronds.py checks them. Each set is grown by the rules of one session version
(sim/core/versions.py):
- the unprefixed set by version 4: Table 1's presets and the fern look; "window-old" the
  window preset with every frond rule off, "window-v3" with them on by version 3's rules;
- "v5/...": every preset, the paper's modes (replenish, growth, long jumps, launch
  circle), a rebuild's replant, a wrap tile and a scribble's touches into existing areas,
  by version 6's rules (whose frost is version 5's: version 6 changed only how a
  session's melts apply);
- "v7/...": the same runs by version 7's rules, each part drawing from its own stream;
- "v8/...": the same runs by version 8's rules, a touch opening an area with its ring;
- "v9/...": a page tapping one spot, by version 9's rules (a touch obeys the cells' cap);
  the v8 runs grow the same by version 9's (no cell of theirs fills up).
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
# The window preset with every frond rule off.
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


def replant(ticks: int = 120, version: int = 6) -> FrostSim:
    """A rebuild: forty touches planted at once (a spiral), then growth, a melt, regrowth."""
    sim = FrostSim(Params.preset("fern"), seed=5, version=version)
    t = np.arange(40)
    sim.plant(np.column_stack((380 + 6 * t * np.cos(t), 640 + 6 * t * np.sin(t))))
    return grown(sim, ticks, (380.0, 640.0, 60.0))


def tile(ticks: int = 200, version: int = 6) -> FrostSim:
    """A wrap tile: touches by the edges and a corner, so growth, walks and a melt cross them."""
    sim = FrostSim(Params.preset("fern", long_jumps=True), 256, 192, seed=2, wrap=True,
                   version=version)
    sim.plant([(2.0, 96.0), (250.0, 3.0), (128.0, 190.0)])
    return grown(sim, ticks, (1.0, 96.0, 20.0))


def grown(sim: FrostSim, ticks: int, melt: tuple[float, float, float]) -> FrostSim:
    """`sim` stepped `ticks` times, with `melt` (x, y, r) half way."""
    for _ in range(ticks):
        sim.step()
        if sim.tick == ticks // 2:
            sim.melt(*melt)
    return sim


def scribble(ticks: int = 150, version: int = 6) -> FrostSim:
    """A drag: a touch every 5 ticks along a stroke, each into the area the first opened
    (touch_water brings each its ring), then a wipe across half of it."""
    sim = FrostSim(Params.preset("fern", touch_water=48), seed=7, version=version)
    for k in range(ticks):
        if k < 100 and k % 5 == 0:
            sim.touch(300.0 + 4.0 * k, 600.0 + 2.0 * k)
        if k == 110:
            sim.melt(400.0, 650.0, 35.0)
        sim.step()
    return sim


# Version 5 runs: (name, preset, overrides, ticks) through `run`; then the three above.
RUNS_V5 = [(name, name, {}, 160) for name in ("a-1", "a-2", "a-3", "b-1", "b-3", "c-1", "c-2",
                                              "c-3")] + [
    ("default", None, {}, 160), ("replenish", "b-2", {"replenish": True}, 160),
    ("grow", "c-2", {"grow": True}, 160),
    ("jumps-launch", "c-2", {"long_jumps": True, "launch": 30.0, "grow": True}, 160),
    ("search-grid", "a-2", {"neighbor_search": "grid9"}, 120),
    ("fern", "fern", {}, 300), ("fern-nogrow", "fern", {"grow": False}, 200),
    ("window", "window", {}, 400)]


def hashes_of(version: int, prefix: str) -> dict[str, str]:
    """The runs of RUNS_V5 and the three above grown by the rules of `version`."""
    out = {f"{prefix}/{name}": state_hash(run(p, o, t, version=version))
           for name, p, o, t in RUNS_V5}
    for f in (replant, tile, scribble):
        out[f"{prefix}/{f.__name__}"] = state_hash(f(version=version))
    return out


def hashes_v5() -> dict[str, str]:
    """The "v5/" set: grown by version 6's rules, whose frost is version 5's (version 6
    changed only how a session's melts apply)."""
    return hashes_of(6, "v5")


def hashes_v7() -> dict[str, str]:
    """The same runs by version 7's rules: each part's own random stream."""
    return hashes_of(7, "v7")


def hashes_v8() -> dict[str, str]:
    """The same runs by version 8's rules: a touch that opens an area brings its ring."""
    return hashes_of(8, "v8")


def one_spot(ticks: int = 100, version: int = 9) -> FrostSim:
    """A page tapping one spot: 20 touches a tick there on the finest grid, its cells full
    within a few ticks; a melt half way frees them, and the touches plant again."""
    sim = FrostSim(Params.preset("fern", hc=16.0, D=1.0, grid_spacing=2), seed=11,
                   version=version)
    for _ in range(ticks):
        for _k in range(20):
            sim.touch(380.0, 640.0)
        sim.step()
        if sim.tick == ticks // 2:
            sim.melt(380.0, 640.0, 40.0)
    return sim


def hashes_v9() -> dict[str, str]:
    """Version 9's own run: one spot tapped past the cells' cap."""
    return {"v9/one-spot": state_hash(one_spot())}


def hashes(window_off: dict) -> dict[str, str]:
    out = {name: state_hash(run(p, o, t, version=4)) for name, p, o, t in RUNS}
    name, p, _, t = WINDOW_OLD
    out[name] = state_hash(run(p, window_off, t, version=4))
    name, p, o, t = WINDOW_V3
    out[name] = state_hash(run(p, o, t, version=3))
    return out


if __name__ == "__main__":
    json.dump({**hashes({}), **hashes_v5(), **hashes_v7(), **hashes_v8(), **hashes_v9()},
              sys.stdout, indent=1)
    print()
