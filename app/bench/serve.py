"""`frost bench serve`: what `frost serve` sends and what pages cost it.

1. Bytes, offline (no server): a window pane grown to its frosted end and a fern scribble,
   every delta encoded as the server encodes it: per-tick message p50 / p99 / max, and the
   snapshot a late page gets (the live ice drawn anew, in parts).
2. The server on loopback, in this process, for --seconds each: first with no page (the
   same scribble played by the server itself), then with --pages pages (aiohttp clients in
   a child process, so they do not share this process's interpreter lock): one scribbling,
   one tapping clear glass to time touch-to-first-delta, the others only reading. Printed:
   the simulation thread's tick median and p99, ticks a second, bytes a tick, the pages'
   resyncs, this process's memory (RSS) over time, and the taps' latency median and p95.
Figures only; nothing is asserted.
"""

from __future__ import annotations

import argparse
import asyncio
import math
import multiprocessing
import statistics
import sys
import time

import numpy as np

from app.serve import guard, protocol
from app.serve.feed import Feed
from app.serve.protocol import Encoder, Input
from app.serve.server import make_app
from sim import Params, all_presets
from sim.io.timeline import Timeline
from sim.look.geometry import FrostGeometry
from sim.screen import HEIGHT, WIDTH

SCRIBBLE_HZ = 50.0  # pointer events a second of the scribbling finger
TAP_PERIOD = 0.6  # s between the latency page's taps
NEAR = 40.0  # px: a delta's vertex this near a tap shows its growth


def scribble_point(t: float) -> tuple[float, float]:
    """Where the scribbling finger is at time t (s): a slow Lissajous over the screen."""
    return (WIDTH / 2 + 0.4 * WIDTH * math.sin(0.9 * t),
            HEIGHT / 2 + 0.4 * HEIGHT * math.sin(0.55 * t + 0.3))


def tap_point(k: int) -> tuple[float, float]:
    """The latency page's k-th tap: a grid of spots away from the scribble's path."""
    return (60.0 + (k * 97) % (WIDTH - 120), 60.0 + (k * 211) % (HEIGHT - 120))


def _figures(sizes) -> str:
    s = np.asarray(sizes, float)
    return (f"p50 {np.percentile(s, 50) / 1e3:.1f} kB, p99 {np.percentile(s, 99) / 1e3:.1f} kB, "
            f"max {s.max() / 1e3:.1f} kB")


def bytes_offline(preset: str, ticks: int, scribble: bool, seed: int = 0) -> None:
    timeline = Timeline(Params.preset(preset), seed)
    geometry = timeline.geometry
    encoder, sizes = Encoder(geometry.cols, geometry.rows), []
    for k in range(ticks):
        if scribble:
            x, y = scribble_point(k / 25.0)
            timeline.apply([{"kind": "touch", "x": x, "y": y}])
        sizes.append(sum(len(encoder.delta(d)) for d in timeline.step()))
    redraw = FrostGeometry(timeline.params).redraw(timeline.sim)
    parts = encoder.snapshot(redraw.tick, redraw.features, redraw.look, redraw.height_scale)
    what = "a touch every tick" if scribble else "no touch"
    print(f"  {preset}, seed {seed}, {ticks} ticks, {what}: per tick {_figures(sizes)}; "
          f"snapshot {sum(map(len, parts)) / 1e6:.2f} MB in {len(parts)} parts "
          f"({len(redraw.features) // 3} triangles)")


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


# ---- the pages (a child process) ------------------------------------------------------------

def pages_main(url: str, pages: int, seconds: float, out) -> None:
    out.put(asyncio.run(_pages(url, pages, seconds)))


async def _pages(url: str, pages: int, seconds: float) -> dict:
    from aiohttp import ClientSession
    got = {"bytes": 0, "latency": []}
    async with ClientSession() as http:
        sockets = [await http.ws_connect(url, max_msg_size=0) for _ in range(pages)]
        end = time.monotonic() + seconds + 0.5  # the server times `seconds` from here
        tasks = [asyncio.create_task(_read(ws, got, end, None)) for ws in sockets[2:]]
        tasks.append(asyncio.create_task(_scribble(sockets[0], got, end)))
        if pages > 1:
            tasks.append(asyncio.create_task(_taps(sockets[1], got, end)))
        await asyncio.gather(*tasks)
        for ws in sockets:
            await ws.close()
    return got


async def _read(ws, got: dict, end: float, on_binary) -> None:
    while time.monotonic() < end:
        try:
            msg = await asyncio.wait_for(ws.receive(), max(0.01, end - time.monotonic()))
        except asyncio.TimeoutError:
            return
        if msg.type.name != "BINARY" and msg.type.name != "TEXT":
            return
        got["bytes"] += len(msg.data)
        if on_binary is not None and msg.type.name == "BINARY":
            on_binary(msg.data)


async def _scribble(ws, got: dict, end: float) -> None:
    reader = asyncio.create_task(_read(ws, got, end, None))
    t0, phase = time.monotonic(), "down"
    while time.monotonic() < end:
        x, y = scribble_point(time.monotonic() - t0)
        await ws.send_json({"type": "touch", "x": x, "y": y, "phase": phase})
        phase = "move"
        await asyncio.sleep(1.0 / SCRIBBLE_HZ)
    await reader


async def _taps(ws, got: dict, end: float) -> None:
    """Tap clear glass; the time until the first message with a vertex near the tap."""
    pending: dict = {}

    def seen(data: bytes) -> None:
        if not pending:
            return
        xy = protocol.decode_geometry(data)["vertices"][:, :2]
        (x, y), t = pending["spot"], pending["t"]
        if len(xy) and (np.hypot(xy[:, 0] - x, xy[:, 1] - y) < NEAR).any():
            got["latency"].append(time.monotonic() - t)
            pending.clear()

    reader = asyncio.create_task(_read(ws, got, end, seen))
    k = 0
    while time.monotonic() < end - 1.0:
        spot = tap_point(k)
        pending.update(spot=spot, t=time.monotonic())
        await ws.send_json({"type": "touch", "x": spot[0], "y": spot[1], "id": 1})
        await ws.send_json({"type": "touch", "phase": "up", "id": 1})
        k += 1
        await asyncio.sleep(TAP_PERIOD)
    await reader


# ---- the server (this process) -------------------------------------------------------------

async def _phase(params: Params, pages: int, seconds: float) -> dict:
    from aiohttp import web
    feed = Feed(params, seed=0)
    runner = guard.GuardedRunner(make_app(feed), access_log=None)  # as frost serve's
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    port = runner.addresses[0][1]
    child, out = None, None
    if pages:
        ctx = multiprocessing.get_context("spawn")
        out = ctx.Queue()
        child = ctx.Process(target=pages_main, args=(f"http://127.0.0.1:{port}/ws", pages,
                                                      seconds, out))
        child.start()
        while len(feed.pages) < pages and child.is_alive():
            await asyncio.sleep(0.05)
    else:
        asyncio.get_running_loop().create_task(_self_scribble(feed, seconds))
    feed.tick_ms.clear()  # timed from here: every page connected
    feed.sizes.clear()
    ticks0, rss, t0 = feed.tick(), [], time.monotonic()
    while time.monotonic() - t0 < seconds:
        rss.append(rss_mb())
        await asyncio.sleep(min(seconds / 10, 30.0))
    wall, ticks = time.monotonic() - t0, feed.tick() - ticks0
    resyncs = sum(p.resyncs for p in feed.pages)
    got = out.get(timeout=60) if out is not None else {"bytes": 0, "latency": []}
    if child is not None:
        child.join(30)
    figures = {"tick_ms": list(feed.tick_ms), "sizes": list(feed.sizes), "rate": ticks / wall,
               "rss": rss + [rss_mb()], "latency": got["latency"], "received": got["bytes"],
               "resyncs": resyncs, "redraws": feed.redraws, "wall": wall}
    await runner.cleanup()
    return figures


async def _self_scribble(feed: Feed, seconds: float) -> None:
    """The pages' input played by the server itself: the scribble and the taps."""
    t0, phase, k = time.monotonic(), "down", 0
    fingers: dict = {}
    while time.monotonic() - t0 < seconds:
        now = time.monotonic() - t0
        x, y = scribble_point(now)
        feed.controls.handle(Input("touch", x, y, phase), fingers)
        phase = "move"
        if now >= k * TAP_PERIOD and now < seconds - 1.0:
            feed.controls.handle(Input("touch", *tap_point(k), "down", 1), fingers)
            feed.controls.handle(Input("touch", phase="up", finger=1), fingers)
            k += 1
        await asyncio.sleep(1.0 / SCRIBBLE_HZ)


def _print_phase(name: str, f: dict) -> None:
    t = np.asarray(f["tick_ms"], float)
    print(f"  {name}: tick median {np.median(t):.2f} ms, p99 {np.percentile(t, 99):.2f} ms, "
          f"{f['rate']:.1f} ticks/s over {f['wall']:.0f} s; bytes a tick {_figures(f['sizes'])}")
    rss = f["rss"]
    print(f"    memory (RSS) {rss[0]:.0f} -> {rss[-1]:.0f} MB (max {max(rss):.0f}; samples "
          f"{', '.join(f'{v:.0f}' for v in rss)})")
    if f["received"]:
        print(f"    pages received {f['received'] / 1e6:.1f} MB; resyncs {f['resyncs']}, "
              f"snapshots drawn {f['redraws']}")
    lat = f["latency"]
    if lat:
        print(f"    touch to first delta: median {1e3 * statistics.median(lat):.0f} ms, "
              f"p95 {1e3 * float(np.percentile(lat, 95)):.0f} ms ({len(lat)} taps)")


def main(argv: list[str] | None = None, prog: str = "frost bench serve") -> int:
    p = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--preset", choices=list(all_presets()), default="fern",
                   help="what the server grows (default fern, as frost serve)")
    p.add_argument("--seconds", type=float, default=20.0,
                   help="length of each server phase, s (default 20; 300 for the 5-minute "
                        "memory check)")
    p.add_argument("--pages", type=int, default=16, help="pages connected in the second phase")
    p.add_argument("--skip-bytes", action="store_true", help="skip the offline byte counts")
    p.add_argument("--skip-baseline", action="store_true",
                   help="skip the server phase with no page (e.g. for a long memory run)")
    args = p.parse_args(argv)
    if not args.skip_bytes:
        print("bytes (offline, the server's encoder):")
        bytes_offline("window", 2250, scribble=False)
        bytes_offline("fern", 1500, scribble=True)
    params = Params.preset(args.preset)
    print(f"server on loopback ({args.preset}, seed 0, a finger scribbling):")
    if not args.skip_baseline:
        _print_phase("no page (the server plays the same input)",
                     asyncio.run(_phase(params, 0, args.seconds)))
    _print_phase(f"{args.pages} pages", asyncio.run(_phase(params, args.pages, args.seconds)))
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
