"""The phone's own frost (`python -m bench page --local`): the page of `frost serve
--preset fern` on loopback, installed (its service worker's cache), reloaded after the
server stopped, so it grows frost in its Web Worker; its CPU slowed N times (Chromium's
`Emulation.setCPUThrottlingRate`, default 4: a phone) and three touches growing:

- the worker's own tick durations (its clock: throttling does not reach a dedicated
  worker, so the phone figure is its p99 times the slowdown), and its ticks a second;
- the page's frames under the throttle (requestAnimationFrame's intervals);
- the Python simulation's tick beside it (sim/, the same preset and touches, this machine),
  and the worker's tick in Node (where `node` is: the same code with no browser beside it).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.chromium import ANGLE, chromium_options
from bench.phoneapp import serving
from bench.threads import page_threads
from sim import FrostSim, Params

GROW_TICKS = 250  # ticks grown with the touches (the worker's p99 is of its last 250): --ticks
FRAMES = """(ms) => new Promise((done) => { const t = [];
  const frame = (now) => { t.push(now); if (now - t[0] < ms) requestAnimationFrame(frame); else done(t); };
  requestAnimationFrame(frame); })"""


def installed_alone(ctx, url: str):
    """A page of `url` whose worker cached its shell; the server then stops (the caller's
    `serving` ends) and this returns the page for the caller to reload."""
    page = ctx.new_page()
    page.goto(url)
    page.wait_for_function("window.frost && frost.synced && frost.frames > 0", timeout=60_000)
    page.wait_for_function("navigator.serviceWorker.controller !== null", timeout=30_000)
    page.wait_for_function("caches.keys().then((k) => k.some((n) => n.startsWith('frost-shell-')))",
                           timeout=30_000)
    return page


def python_ticks(preset: str, ticks: int, seed: int, touches) -> np.ndarray:
    """ms of each of `ticks` steps of sim/ grown from `touches`."""
    sim = FrostSim(Params.preset(preset), seed=seed)
    for x, y in touches:
        sim.touch(x, y)
    times = []
    for _ in range(ticks):
        start = time.perf_counter()
        sim.step()
        times.append((time.perf_counter() - start) * 1e3)
    return np.array(times)


# The worker's tick (LocalRun.tick: step, geometry, encoding) timed in Node.
NODE_TICKS = """
import { readFileSync } from "node:fs";
import { LocalRun, warmUp } from "./app/web/local/run.js";
const [preset, ticks, seed, touches] = JSON.parse(process.argv[1]);
const config = JSON.parse(readFileSync("app/web/local/params.json", "utf-8"));
warmUp(config);  // (as the worker does before its hello)
const run = new LocalRun(config, () => {}, { preset, seed });
run.hello();
for (const [x, y] of touches) run.input({ type: "touch", phase: "down", id: 0, x, y });
const times = [];
for (let i = 0; i < ticks; i++) {
  const start = performance.now();
  run.tick();
  times.push(performance.now() - start);
}
console.log(JSON.stringify(times));
"""


def node_ticks(preset: str, ticks: int, seed: int, touches) -> np.ndarray | None:
    """ms of each of `ticks` of the worker's ticks run by Node (grown from `touches`), or
    None without Node."""
    node = shutil.which("node")
    if node is None:
        return None
    root = Path(__file__).resolve().parent.parent
    out = subprocess.run([node, "--input-type=module", "-e", NODE_TICKS,
                          json.dumps([preset, ticks, seed, list(touches)])],
                         cwd=root, capture_output=True, text=True, timeout=600, check=True)
    return np.array(json.loads(out.stdout))


def run(args, rate: float, touches) -> int:
    """The bench: the page's CPU slowed `rate` times, its frost grown from `touches`."""
    from playwright.sync_api import sync_playwright

    preset = args.preset or "fern"
    ticks = args.ticks or GROW_TICKS
    with tempfile.TemporaryDirectory() as profile, sync_playwright() as pw:
        ctx = pw.chromium.launch_persistent_context(  # (a phone of 390x844 CSS px)
            profile, **chromium_options(pw, ANGLE[args.angle]), viewport={"width": 390, "height": 844},
            device_scale_factor=3, has_touch=True, is_mobile=True)
        try:
            with serving(preset) as url:
                page = installed_alone(ctx, url)
            page.reload()
            page.wait_for_function("window.frost && frost.local && frost.synced && frost.frames > 0",
                                   timeout=60_000)
            cdp = ctx.new_cdp_session(page)
            cdp.send("Emulation.setCPUThrottlingRate", {"rate": rate})
            rect = page.evaluate("frost.paneCss()")
            before, began = page_threads(profile), time.monotonic()
            for x, y in touches:
                page.touchscreen.tap(rect["x"] + x * rect["sx"], rect["y"] + y * rect["sy"])
            start = page.evaluate("frost.local.tick")
            frames = np.diff(page.evaluate(FRAMES, ticks * 40))
            page.wait_for_function(f"frost.local.tick >= {start + ticks}", timeout=600_000)
            local = page.evaluate("frost.alone.stats")
            after, seconds = page_threads(profile), time.monotonic() - began
        finally:
            ctx.close()
    py = python_ticks(preset, ticks, args.seed, touches)
    js = node_ticks(preset, ticks, args.seed, touches)
    print(f"{preset}, three touches, {ticks} ticks, the page's CPU slowed {rate:g}x "
          f"(Chromium, {args.angle}); {local['crystals']} crystals")
    print(f"worker tick (its own clock, last 250): median {local['tickMedianMs']:.2f} ms, "
          f"p99 {local['tickP99Ms']:.2f} ms; on a phone {rate:g}x slower: p99 "
          f"{local['tickP99Ms'] * rate:.1f} ms (goal 20)")
    print(f"worker ticks a second (last 5 s): {local['ticksPerSecond']:.1f} (goal 25)")
    print(f"page frames under the throttle: median {np.median(frames):.1f} ms, p99 "
          f"{np.percentile(frames, 99):.1f} ms ({len(frames)} frames, "
          f"{1000 / np.mean(frames):.1f} a second)")
    print(f"Python tick (sim/, this machine): median {np.median(py):.2f} ms, p99 "
          f"{np.percentile(py, 99):.2f} ms")
    if js is not None:
        print(f"the worker's tick in Node (no browser): median {np.median(js):.2f} ms, p99 "
              f"{np.percentile(js, 99):.2f} ms")
    if before and after:
        print(threads_line(after["worker"] - before["worker"], after["page"] - before["page"], seconds, rate))
    return 0


def threads_line(worker, page, seconds: float, rate: float) -> str:
    """Where the worker's wall-clock ticks went (ThreadTimes over the `seconds` grown, the
    page slowed `rate` times)."""
    spin = " (Chromium's throttle busy-waits there)" if rate > 1 else ""
    return (f"its threads over the {seconds:.1f} s grown (Linux schedstat): the worker "
            f"{worker.cpu_ms:.0f} ms on a CPU, {worker.wait_ms:.0f} ms waiting for one; the page's main "
            f"thread {page.cpu_ms:.0f} ms on a CPU{spin}")
