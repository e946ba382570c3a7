"""Rendering benchmark: `frost bench render` (headless, 760x1280, about half the screen frosted).

The paper's look and the glass look on the same growing frost in one run (one simulation,
a geometry and a renderer per look, their frames interleaved): for each, the median and
99th percentile frame time (ctx.finish() inside the timing), the geometry update per tick
(median, p99, and median of the last ticks), the median upload per tick and the feature
vertices sent; then one JSON line.

The geometry is timed by two clocks: the wall clock, and the CPU time of the thread that
runs it (as the simulation thread counts its work, app/simthread/backlog.py). On a CPU renderer
(llvmpipe) the wall clock also counts the rasterizer's threads, which keep the cores busy
a while after `ctx.finish()`; the CPU time is the geometry's own cost.

`--record` also keeps the figures as a dated entry of docs/results/bench-render.md
(app/bench/results.py).
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time

import numpy as np

from app.backdrops import view_from
from app.bench.results import commit, keep, load_averages
from app.gl.renderer import Renderer
from app.tools.offscreen import make_context
from sim import FrostSim, Params
from sim.look.geometry import FrostGeometry
from sim.params import LOOKS
from sim.screen import HEIGHT, WIDTH

# Seven seeds spread over the screen; at c-2 each frosts a disc of about active_radius.
TOUCHES = [(190, 200), (570, 330), (380, 640), (160, 760), (600, 930), (250, 1120), (560, 150)]


LAST = 300  # ticks: the geometry's cost at the end of the growth, where the most ice is


def ms(seconds: list[float]) -> float:
    return 1000.0 * statistics.median(seconds) if seconds else 0.0


def p99(seconds: list[float]) -> float:
    """The 99th percentile, ms (linear between samples)."""
    return 1000.0 * float(np.percentile(seconds, 99)) if seconds else 0.0


class Look:
    """One look's geometry and renderer over the shared simulation, and its timings."""

    def __init__(self, ctx, params: Params, look: str, view: dict | None):
        self.name, self.params = look, params.replace(look=look)
        self.geometry = FrostGeometry(self.params, WIDTH, HEIGHT)
        self.renderer = Renderer(ctx, self.params, WIDTH, HEIGHT)
        self.renderer.set_view(view)
        self.geo_t: list[float] = []  # wall clock
        self.geo_cpu: list[float] = []  # this thread's CPU time
        self.up_t: list[float] = []
        self.frames: list[float] = []
        self.vertices = 0  # feature vertices sent over the run

    def tick(self, ctx, sim, fbo) -> None:
        t0, c0 = time.perf_counter(), time.thread_time()
        delta = self.geometry.update(sim)
        t1, c1 = time.perf_counter(), time.thread_time()
        self.renderer.apply(delta)
        ctx.finish()
        self.geo_t.append(t1 - t0)
        self.geo_cpu.append(c1 - c0)
        self.up_t.append(time.perf_counter() - t1)
        self.vertices += len(delta.features)
        self.renderer.render(fbo)  # rasterizes the new features once, as the app does
        ctx.finish()

    def frame(self, ctx, fbo) -> None:
        t0 = time.perf_counter()
        self.renderer.render(fbo)
        ctx.finish()
        self.frames.append(time.perf_counter() - t0)

    def result(self) -> dict:
        return {"frame_ms": round(ms(self.frames), 2),
                "frame_ms_min": round(1000 * min(self.frames, default=0), 2),
                "frame_ms_p99": round(p99(self.frames), 2),
                "geometry_ms_per_tick": round(ms(self.geo_t), 3),
                "geometry_ms_p99": round(p99(self.geo_t), 3),
                "geometry_ms_last": round(ms(self.geo_t[-LAST:]), 3),
                "geometry_ms_max": round(1000 * max(self.geo_t, default=0), 3),
                "geometry_cpu_ms_per_tick": round(ms(self.geo_cpu), 3),
                "geometry_cpu_ms_p99": round(p99(self.geo_cpu), 3),
                "geometry_cpu_ms_last": round(ms(self.geo_cpu[-LAST:]), 3),
                "upload_ms_per_tick": round(ms(self.up_t), 3), "feature_vertices": self.vertices}


def grow(ctx, params: Params, seed: int, target: float, max_ticks: int, looks: list[Look], fbo):
    """Grow until `target` of the screen is frosted, every look's geometry fed each tick."""
    sim = FrostSim(params, WIDTH, HEIGHT, seed)
    if not params.window_frost:
        for x, y in TOUCHES:
            sim.touch(x, y)
    while sim.tick < max_ticks and covered(looks[0].geometry) < target:
        sim.step()
        for look in looks:
            look.tick(ctx, sim, fbo)
        if sim.tick % 50 == 0:
            print(f"tick {sim.tick}: {covered(looks[0].geometry):.0%} frosted, "
                  f"{len(sim.crystals)} crystals", flush=True)
    return sim


def covered(geometry: FrostGeometry) -> float:
    """Fraction of the screen's grid vertices that carry ice."""
    return float(np.count_nonzero(geometry.heights)) / geometry.heights.size


def time_frames(ctx, looks: list[Look], fbo, frames: int) -> None:
    """`frames` frames of each look, interleaved so that load hits them alike."""
    for look in looks:
        look.frame(ctx, fbo)  # warm-up: shaders compiled, queued features drawn
        look.frames.clear()
    for _ in range(frames):
        for look in looks:
            look.frame(ctx, fbo)


def run(args, params: Params) -> int:
    """`frost bench render [--preset NAME | --params FILE] [--seed N] [--frames N] [--cover F]
    [--max-ticks N]`: the paper's look and the glass look on the same frost (`params`, the
    command line's), in one run."""
    head = commit() if args.record else ""  # the code that runs, whatever is committed meanwhile
    try:
        ctx = make_context()
    except RuntimeError as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 1
    fbo = ctx.simple_framebuffer((WIDTH, HEIGHT), components=4)
    looks = [Look(ctx, params, name, view_from(args)) for name in LOOKS]
    sim = grow(ctx, params, args.seed, args.cover, args.max_ticks, looks, fbo)
    time_frames(ctx, looks, fbo, args.frames)
    grown = args.params_file or args.preset or args.default_preset
    result = {"preset": grown, "ticks": sim.tick,
              "frosted": round(covered(looks[0].geometry), 3), "crystals": len(sim.crystals),
              "segments": len(sim.segments), **{look.name: look.result() for look in looks},
              "renderer": ctx.info["GL_RENDERER"], "load_average": load_average()}
    report(result, args.frames)
    return keep("render", command(args), result, "frost bench render", head) if args.record else 0


def command(args) -> str:
    """The command line that gave these figures, every value spelled out (defaults too)."""
    grown = f"--params {args.params_file}" if args.params_file else \
        f"--preset {args.preset or args.default_preset}"
    background = f" --background {args.background}" if args.background else ""
    return (f"frost bench render {grown} --seed {args.seed} --frames {args.frames} "
            f"--cover {args.cover} --max-ticks {args.max_ticks}{background}")


def load_average() -> float | None:
    """The last minute's load average, None where the system keeps none (Windows)."""
    averages = load_averages()
    return round(averages[0], 2) if averages else None


def report(result: dict, frames: int) -> None:
    print(f"{result['ticks']} ticks, {result['frosted']:.0%} of the screen frosted, "
          f"{result['crystals']} crystals")
    for name in LOOKS:
        r = result[name]
        print(f"{name}: frame median {r['frame_ms']} ms (best {r['frame_ms_min']}, p99 "
              f"{r['frame_ms_p99']}) over {frames} frames; geometry median "
              f"{r['geometry_ms_per_tick']} ms/tick (p99 {r['geometry_ms_p99']}, max "
              f"{r['geometry_ms_max']}; last {LAST} ticks {r['geometry_ms_last']}), its CPU "
              f"time median {r['geometry_cpu_ms_per_tick']} ms/tick (p99 "
              f"{r['geometry_cpu_ms_p99']}; last {LAST} ticks {r['geometry_cpu_ms_last']}); "
              f"upload median {r['upload_ms_per_tick']} ms/tick; "
              f"{r['feature_vertices']} feature vertices sent")
    paper, glass = result["paper"], result["glass"]
    print(f"glass / paper: frame {glass['frame_ms'] / max(paper['frame_ms'], 1e-9):.2f}x, "
          f"feature vertices {glass['feature_vertices'] / max(paper['feature_vertices'], 1):.2f}x "
          f"({WIDTH}x{HEIGHT}, ctx.finish() inside, frames interleaved)")
    load = result["load_average"]
    print(f"load: {'unknown' if load is None else load} (the last minute's average)")
    if load is not None and load > 0.5 * (os.cpu_count() or 1):
        print(f"note: load average {load}: other work shares the CPU "
              "that llvmpipe renders on, so timings may be inflated")
    print(json.dumps(result))

