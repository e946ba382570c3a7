"""`python -m bench serve`'s server side: `frost serve`'s app on loopback in this process (a new
feed, seed 0, the guarded runner as frost serve's), its pages in a child process
(bench/clients.py), and what the server measured while they ran."""

from __future__ import annotations

import asyncio
import multiprocessing
import statistics
import time

from app.bench.memory import rss_mb
from app.serve import guard
from app.serve.feed import Feed
from app.serve.protocol import Input
from app.serve.server import make_app
from bench.clients import SCRIBBLE_HZ, TAP_PERIOD, Plan, pages_main, plan_pages, scribble_point, tap_point
from sim import Params

SAMPLES = 10  # memory and rate samples a phase


async def phase(params: Params, plan: Plan | None, seconds: float,
                budget_s: float | None = None) -> dict:
    """A server of `params` on loopback for `seconds` from the moment every page of `plan`
    connected (None: no page; the server plays the house's input itself); its figures,
    with those of its simulation after it stopped. `budget_s`: the simulation thread's
    input budget a tick (None: frost serve's)."""
    from aiohttp import web
    feed = Feed(params, seed=0)
    if budget_s is not None:
        feed.thread.backlog.budget_s = budget_s
    runner = guard.GuardedRunner(make_app(feed), access_log=None)  # as frost serve's
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    child, out = None, None
    if plan is not None:
        ctx = multiprocessing.get_context("spawn")
        out = ctx.Queue()
        child = ctx.Process(target=pages_main, args=(
            f"http://127.0.0.1:{runner.addresses[0][1]}/ws", plan, seconds, out))
        child.start()
        while len(feed.pages) < plan_pages(plan) and child.is_alive():
            await asyncio.sleep(0.05)
    else:
        asyncio.get_running_loop().create_task(_self_scribble(feed, seconds))
    figures = await _watch(feed, seconds)
    got = out.get(timeout=60) if out is not None else {"bytes": 0, "latency": [], "taps": 0}
    if child is not None:
        child.join(30)
    figures["redraws"] = feed.redraws
    await runner.cleanup()  # the simulation thread stopped
    feed.thread.join(30)  # (stop waits a second at most; a tick may take longer)
    return {**figures, **got, **_frost(feed)}


async def _watch(feed: Feed, seconds: float) -> dict:
    """The server's figures over the next `seconds`: tick times, bytes a tick, ticks a
    second, memory (sampled SAMPLES times) and, per sample, ticks a second and the tick
    median since the one before; the input dropped and waiting at the end."""
    feed.tick_ms.clear()  # timed from here: every page connected
    feed.sizes.clear()
    feed.tap_ms.clear()
    ticks0, t0 = feed.tick(), time.monotonic()
    rss, samples, at = [], [], (t0, ticks0)
    while time.monotonic() - t0 < seconds:
        rss.append(rss_mb())
        await asyncio.sleep(min(seconds / SAMPLES, 30.0))
        samples.append(_since(feed, *at))
        at = (time.monotonic(), feed.tick())
    wall, ticks = time.monotonic() - t0, feed.tick() - ticks0
    controls, thread = feed.controls, feed.thread
    return {"tick_ms": list(feed.tick_ms), "sizes": list(feed.sizes), "rate": ticks / wall,
            "tap_ms": list(feed.tap_ms),
            "rss": rss + [rss_mb()], "wall": wall, "samples": samples,
            "resyncs": sum(p.resyncs for p in feed.pages), "dropped": controls.dropped,
            "skipped": controls.skipped,
            "waiting": thread.sent - thread.handled + controls.turns.waiting()}


def _since(feed: Feed, t0: float, ticks0: int) -> tuple[float, float]:
    """Ticks a second and the median tick (ms) since time `t0` at tick `ticks0`."""
    ticks = feed.tick() - ticks0
    recent = list(feed.tick_ms)[-ticks:] if ticks > 0 else []
    return ticks / (time.monotonic() - t0), statistics.median(recent) if recent else float("nan")


def _frost(feed: Feed) -> dict:
    """What the stopped simulation holds: the crystals in its fullest hash cell (the
    candidate cells' count), its crystals (and those alive), the touches it applied."""
    timeline = feed.thread.timeline
    sim = timeline.sim
    touches = [e for e in timeline.events if e["kind"] == "touch"]
    return {"fullest": int(sim.index.candidates.count.max()), "crystals": len(sim.crystals),
            "alive": int(sim.crystal_alive.sum()), "planted": len(touches),
            "touch_ticks": {(e["x"], e["y"]): e["tick"] for e in reversed(touches)}}


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
