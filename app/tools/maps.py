"""`frost maps DIR`: grow a frost headless and write the maps a game engine reads: height,
normal, alpha, growth (when each pixel froze), a preview and maps.json saying what each
holds (computed in sim.look.maps and sim.look.growthmap, written by app.tools.engine_maps)."""

from __future__ import annotations

import sys

from app.tools.engine_maps import EngineRun, write_engine_maps
from app.tools.progress import Progress
from app.tools.render_png import demo_touches
from sim import FrostSim, Params
from sim.io.files import why
from sim.io.timeline import Timeline, touch_events
from sim.io.timeline import grow as grow_timeline
from sim.look.geometry import FrostGeometry
from sim.look.growthmap import GrowthClock
from sim.screen import HEIGHT, SIZE, WIDTH


def grow(params: Params, seed: int, touches, ticks: int,
         on_tick=None, size: tuple[int, int] = SIZE, wrap: bool = False,
         clock: GrowthClock | None = None) -> tuple[FrostSim, FrostGeometry]:
    """The simulation and its geometry (no GL) after `ticks` ticks of touches (tick, x, y)
    on a `size` screen (`wrap`: a tile), through sim.io.timeline.grow; `on_tick(sim)` after
    every tick (progress); `clock` is fed every geometry delta."""
    timeline = Timeline(params, seed, *size, wrap=wrap)
    events = [e for t, x, y in sorted(touches) for e in touch_events([(x, y)], t)]

    def applied(result) -> None:
        for delta in result.deltas:
            clock.apply(delta)  # type: ignore[union-attr]

    grow_timeline(timeline, ticks, events, on_apply=applied if clock else None,
                  on_step=clock.apply if clock else None, on_tick=on_tick)
    return timeline.sim, timeline.geometry


def tile_window(params: Params, size: tuple[int, int], given=frozenset()) -> Params:
    """Window mode on a tile: no frame, so no frame sites and no chill by it; its nuclei
    become pane sites (as many as the frame would have had), and the pane's water scales
    with its area against the phone's (the pool and budget were sized for 760 x 1280),
    each within its range; a parameter in `given` (set on the command line) is kept."""
    area = size[0] * size[1] / (WIDTH * HEIGHT)
    scaled = {"pane_sites": params.pane_sites + round(params.frame_sites * 2 * sum(size) / 100),
              "humidity": round(params.humidity * max(area, 1.0)),
              "water_budget": round(params.water_budget * max(area, 1.0))}
    top = {"pane_sites": 1000, "humidity": 100_000, "water_budget": 30_000}
    changes = {k: min(v, top[k]) for k, v in scaled.items() if k not in given}
    return params.replace(frame_sites=0.0, frame_chill=0.0, **changes)


def run(args, params: Params) -> int:
    """`frost maps DIR [--size WxH] [--tile] [--normal-y up|down] [--touch X,Y] [--ticks N]`
    (checked by the command line)."""
    size = (int(args.size[0]), int(args.size[1]))
    if args.tile and params.window_frost:
        params = tile_window(params, size, {n for n in ("pane_sites", "humidity", "water_budget")
                                            if getattr(args, n, None) is not None})
    touches = [(0, x, y) for x, y in args.touch]
    if not touches and not params.window_frost:  # a frosted window grows untouched
        touches = demo_touches(args.ticks, size)
    clock = GrowthClock(params, *size, args.tile)
    try:
        sim, geometry = grow(params, args.seed, touches, args.ticks, Progress(args.ticks).step,
                             size, args.tile, clock)
    except ValueError as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 2
    job = EngineRun(sim, geometry, clock, params, args.seed, touches, args.tile,
                    args.normal_y, args.ticks)
    try:
        paths = write_engine_maps(args.out_dir, job)
    except OSError as err:  # nothing was written: the set appears whole or not at all
        print(f"frost: error: cannot write the maps: {why(err, args.out_dir)}",
              file=sys.stderr)
        return 2
    except RuntimeError as err:  # no EGL for the preview: said before any file is written
        print(f"frost: error: {err}", file=sys.stderr)
        return 2
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0
