"""`frost maps DIR`: grow a frost headless and write its height, normal and alpha
maps for game engines (computed in sim.maps, written by app.images.export_maps)."""

from __future__ import annotations

import sys

from app.images import export_maps
from app.tools.progress import Progress
from app.tools.render import demo_touches
from sim import FrostSim, Params, session
from sim.files import why
from sim.geometry import FrostGeometry
from sim.maps import live_segments, map_triangles
from sim.session import Timeline, touch_events


def grow(params: Params, seed: int, touches, ticks: int,
         on_tick=None) -> tuple[FrostSim, FrostGeometry]:
    """The simulation and its geometry (no GL) after `ticks` ticks of touches (tick, x, y),
    through sim.session.grow; `on_tick(sim)` after every tick (progress)."""
    timeline = Timeline(params, seed)
    events = [e for t, x, y in sorted(touches) for e in touch_events([(x, y)], t)]
    session.grow(timeline, ticks, events, on_tick=on_tick)
    return timeline.sim, timeline.geometry


def run(args, params: Params) -> int:
    """`frost maps DIR [--touch X,Y] [--ticks N]` (checked by the command line)."""
    touches = [(0, x, y) for x, y in args.touch] or demo_touches(args.ticks)
    try:
        sim, geometry = grow(params, args.seed, touches, args.ticks, Progress(args.ticks).step)
    except ValueError as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 2
    meta = {"seed": args.seed, "touches": [list(t) for t in touches], "tick": sim.tick}
    try:
        paths = export_maps(args.out_dir, geometry.heights, live_segments(sim), params, meta,
                            triangles=map_triangles(sim, params))
    except OSError as err:  # nothing was written: the set appears whole or not at all
        print(f"frost: error: cannot write the maps: {why(err, args.out_dir)}",
              file=sys.stderr)
        return 2
    print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0
