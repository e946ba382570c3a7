"""`frost --export-maps`: grow a frost headless and write its height, normal and alpha
maps for game engines (computed in sim.maps, written by app.images.export_maps)."""

from __future__ import annotations

import sys

from app.images import export_maps
from sim import FrostSim, Params
from sim.files import why
from sim.geometry import FrostGeometry
from sim.maps import live_segments
from sim.screen import HEIGHT, WIDTH


def grow(params: Params, seed: int, touches, ticks: int,
         on_tick=None) -> tuple[FrostSim, FrostGeometry]:
    """Run the simulation and its geometry (no GL): touches are (tick, x, y);
    `on_tick(sim)` after every tick (progress)."""
    sim = FrostSim(params, WIDTH, HEIGHT, seed)
    geometry = FrostGeometry(params, WIDTH, HEIGHT)
    plan = sorted(touches)
    for tick in range(ticks):
        for x, y in (p[1:] for p in plan if p[0] == tick):
            sim.touch(x, y)
        sim.step()
        geometry.update(sim)
        if on_tick:
            on_tick(sim)
    return sim, geometry


def run(args, params: Params) -> int:
    """`frost maps DIR [--touch X,Y] [--ticks N]`."""
    from app.tools.headless import Progress, scripted_session

    if args.ticks < 0:
        print(f"frost: error: --ticks {args.ticks} must be 0 or more", file=sys.stderr)
        return 2
    touches = [(0, x, y) for x, y in args.touch] or scripted_session(args.ticks)
    try:
        sim, geometry = grow(params, args.seed, touches, args.ticks, Progress(args.ticks).step)
    except ValueError as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 2
    meta = {"seed": args.seed, "touches": [list(t) for t in touches], "tick": sim.tick}
    try:
        paths = export_maps(args.out_dir, geometry.heights, live_segments(sim), params, meta)
    except OSError as err:  # nothing was written: the set appears whole or not at all
        print(f"frost: error: cannot write the maps: {why(err, args.out_dir)}",
              file=sys.stderr)
        return 2
    print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0
