"""Rendering benchmark: `frost bench render` (headless, 760x1280, about half the screen frosted).

Prints the median frame time (ctx.finish() inside the timing), the median geometry
update per tick, the median upload per tick, and one JSON line at the end.
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time

import numpy as np

from app.cli.options import view_from
from app.gl.renderer import Renderer
from app.tools.offscreen import make_context
from sim import FrostSim, Params
from sim.geometry import FrostGeometry
from sim.screen import HEIGHT, WIDTH

# Seven seeds spread over the screen; at c-2 each frosts a disc of about active_radius.
TOUCHES = [(190, 200), (570, 330), (380, 640), (160, 760), (600, 930), (250, 1120), (560, 150)]


def ms(seconds: list[float]) -> float:
    return 1000.0 * statistics.median(seconds) if seconds else 0.0


def grow(ctx, params: Params, seed: int, target: float, max_ticks: int,
         view: dict | None = None):
    """Grow until `target` of the screen is frosted; time geometry and uploads per tick."""
    sim = FrostSim(params, WIDTH, HEIGHT, seed)
    geometry = FrostGeometry(params, WIDTH, HEIGHT)
    renderer = Renderer(ctx, params, WIDTH, HEIGHT)
    renderer.set_view(view)
    fbo = ctx.simple_framebuffer((WIDTH, HEIGHT), components=4)
    for x, y in TOUCHES:
        sim.touch(x, y)
    geo_t, up_t = [], []
    while sim.tick < max_ticks and covered(geometry) < target:
        sim.step()
        t0 = time.perf_counter()
        delta = geometry.update(sim)
        t1 = time.perf_counter()
        renderer.apply(delta)
        ctx.finish()
        geo_t.append(t1 - t0)
        up_t.append(time.perf_counter() - t1)
        renderer.render(fbo)  # rasterizes the new features once, as the app does
        ctx.finish()
        if sim.tick % 50 == 0:
            print(f"tick {sim.tick}: {covered(geometry):.0%} frosted, "
                  f"{len(sim.crystals)} crystals", flush=True)
    return sim, geometry, renderer, fbo, geo_t, up_t


def covered(geometry: FrostGeometry) -> float:
    """Fraction of the screen's grid vertices that carry ice."""
    return float(np.count_nonzero(geometry.heights)) / geometry.heights.size


def time_frames(ctx, renderer: Renderer, fbo, frames: int) -> list[float]:
    renderer.render(fbo)
    ctx.finish()
    times = []
    for _ in range(frames):
        t0 = time.perf_counter()
        renderer.render(fbo)
        ctx.finish()
        times.append(time.perf_counter() - t0)
    return times


def run(args) -> int:
    """`frost bench render [--preset NAME] [--seed N] [--frames N] [--cover F] [--max-ticks N]`."""
    try:
        ctx = make_context()
    except RuntimeError as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 1
    params = Params.preset(args.preset)
    sim, geometry, renderer, fbo, geo_t, up_t = grow(ctx, params, args.seed, args.cover,
                                                     args.max_ticks, view_from(args))
    frames = time_frames(ctx, renderer, fbo, args.frames)
    result = {"preset": args.preset, "ticks": sim.tick, "frosted": round(covered(geometry), 3),
              "crystals": len(sim.crystals), "segments": len(sim.segments),
              "frame_ms": round(ms(frames), 2), "frame_ms_min": round(1000 * min(frames), 2),
              "geometry_ms_per_tick": round(ms(geo_t), 3),
              "geometry_ms_max": round(1000 * max(geo_t, default=0), 3),
              "upload_ms_per_tick": round(ms(up_t), 3), "renderer": ctx.info["GL_RENDERER"],
              "load_average": round(os.getloadavg()[0], 2)}
    print(f"{sim.tick} ticks, {result['frosted']:.0%} of the screen frosted, "
          f"{result['crystals']} crystals")
    print(f"frame: median {result['frame_ms']} ms, best {result['frame_ms_min']} ms over "
          f"{args.frames} frames ({WIDTH}x{HEIGHT}, ctx.finish() inside)")
    print(f"geometry update: median {result['geometry_ms_per_tick']} ms/tick "
          f"(max {result['geometry_ms_max']})")
    print(f"upload (dirty height rows + new feature vertices): median "
          f"{result['upload_ms_per_tick']} ms/tick")
    if result["load_average"] > 0.5 * (os.cpu_count() or 1):
        print(f"note: load average {result['load_average']}: other work shares the CPU "
              "that llvmpipe renders on, so timings may be inflated")
    print(json.dumps(result))
    return 0


if __name__ == "__main__":  # the command's old name
    from app.cli import main

    raise SystemExit(main(["bench", "render", *sys.argv[1:]]))
