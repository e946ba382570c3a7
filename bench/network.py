"""The page through `frost serve` as a phone meets it: an emulated phone (390x844 CSS px,
3 device px each, touch) in headless Chromium, the server started here on loopback and,
with a network profile, the shaping proxy (bench/shaper.py) between them; Chromium's
CPU throttling slows the page's own work (`--cpu-slowdown`, 4: Lighthouse's mobile figure).

Three measures (`python -m bench page --taps N | --join N | --scribble S`):
- taps: touch to the first drawn growth (and frost) near it, timed by the page itself;
- join: a page opened on a frosted pane (the window preset grown for a while): from the
  navigation's start to the first frame drawn with the whole snapshot in it;
- scribble: a finger dragged all over the pane for S seconds: whether the page kept up (a
  resync, a reconnect), its frames' times and the share of the ticks it received that it
  drew, each in a frame of its own.

The page is watched from outside its own code: an init script (PROBE) wraps
requestAnimationFrame (each frame's main-thread time, the tick it showed) and WebSocket
(the tick of each binary message, the resyncs).
"""

from __future__ import annotations

import json
import os
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from app.bench.taps import GAP_S, tap_spots
from bench.serve_process import ServeProcess
from bench.shaper import Profile, ShaperThread
from sim.screen import HEIGHT, WIDTH

# The checkout this module is part of: its server is the one started, whatever is installed.
ROOT = Path(__file__).resolve().parents[1]
PHONE = {"viewport": {"width": 390, "height": 844}, "device_scale_factor": 3,
         "has_touch": True, "is_mobile": True}
JOIN_TICKS = 2250  # the window preset's frosted pane (docs/phone-design.md's snapshot: 2.12 MB)
FINGER_SPEED = 800.0  # pane px a second: a brisk drag
MOVE_EVERY = 1 / 60  # s between a finger's moves (a phone reports touches once a frame)

PROBE = """(() => {
  const probe = { frames: [], ticks: [], handled: [], pongs: {}, resyncs: 0,
    opened: null, snapshot: null, snapshotEnd: null, synced: null, picked: [], shown: [] };
  window.__probe = probe;
  // (absolute ms, comparable between pages: when a file was chosen, when a backdrop showed)
  const now = () => performance.timeOrigin + performance.now();
  document.addEventListener("change", (e) => {
    if (e.target && e.target.type === "file") probe.picked.push(now());
  }, true);
  let backdrop = null;
  const raf = window.requestAnimationFrame.bind(window);
  window.requestAnimationFrame = (callback) => raf((t) => {
    const before = window.frost ? window.frost.frames : 0, t0 = performance.now();
    try { callback(t); } finally {
      const f = window.frost;
      let t1 = performance.now();
      if (f && f.frames > before) {
        probe.frames.push([t0, t1 - t0, f.tick]);
        if (f.synced && probe.synced === null) {
          // The first frame drawn synced, waited for: WebGL only queues its work, so a
          // frame's callback ends long before a whole pane is drawn (a 1-px read waits).
          const gl = document.getElementById("frost").getContext("webgl2");
          gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
          probe.synced = t1 = performance.now();
        }
        if (f.shownBackdrop && f.shownBackdrop !== backdrop) {  // drawn in this frame
          backdrop = f.shownBackdrop;
          probe.shown.push([backdrop, now()]);
        }
      }
    }
  });
  const Socket = window.WebSocket;
  window.WebSocket = class extends Socket {
    constructor(...args) {
      super(...args);
      this.addEventListener("open", () => { if (probe.opened === null) probe.opened = performance.now(); });
      let t0 = 0;
      this.addEventListener("message", (e) => {
        t0 = performance.now();
        if (e.data instanceof ArrayBuffer) {
          const v = new DataView(e.data), flags = v.getUint8(2);
          probe.ticks.push(v.getUint32(4, true));
          if (flags & 4 && probe.snapshot === null) probe.snapshot = t0;  // its first part
          if (flags & 8 && probe.snapshotEnd === null) probe.snapshotEnd = t0;  // its last
        } else if (typeof e.data === "string") {
          const m = JSON.parse(e.data);
          if (m.type === "resync") probe.resyncs += 1;
          if (m.type === "pong") probe.pongs[m.t] = t0;
        }
      });
      // After the page's own handler (set right after the socket is made): its time.
      queueMicrotask(() => this.addEventListener("message", (e) => {
        if (e.data instanceof ArrayBuffer) probe.handled.push(performance.now() - t0);
      }));
    }
  };
})();"""


@dataclass
class Served:
    url: str  # what the page opens (the shaper's address with a profile)
    server: str  # the server's own address (for the bench's own questions: /meta)
    shaper: ShaperThread | None


@contextmanager
def served(preset: str, network: Profile | None = None) -> Iterator[Served]:
    """`frost serve --preset P` on a free loopback port (in a child process), with the
    shaper in front of it when `network` is given; stopped (SIGINT) at the end."""
    with tempfile.TemporaryDirectory() as tmp, ExitStack() as stack:
        env = {"PYTHONPATH": os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
        server = ServeProcess("--port", "0", "--preset", preset, "--session-dir", tmp, cwd=tmp,
                              env=env).drain()
        try:
            url, port = server.url, server.port
            if network is not None:
                shaper = stack.enter_context(ShaperThread(("127.0.0.1", port), network))
                # The page sees the proxy's address: Host and Origin name 127.0.0.1 and its
                # port, which a loopback server accepts (any port).
                yield Served(url.replace(f":{port}/", f":{shaper.port}/"), url, shaper)
            else:
                yield Served(url, url, None)
        finally:
            stack.close()
            server.stop()


def server_tick(s: Served) -> int:
    """The tick of the frame the server published last (its /meta, asked directly)."""
    with urllib.request.urlopen(s.server.split("?")[0] + "meta", timeout=30) as r:
        return int(json.load(r)["tick"])


class Phone:
    """A new phone (a browser context) with the probe and its page, its CPU slowed
    `cpu_slowdown` times (Chromium's Emulation.setCPUThrottlingRate) from before the page
    loads; a context manager."""

    def __init__(self, browser, cpu_slowdown: float = 1.0):
        self.context = browser.new_context(**PHONE)
        self.page = self.context.new_page()
        self.page.add_init_script(PROBE)
        self.cdp = self.context.new_cdp_session(self.page)
        self.rate = cpu_slowdown
        self._slow()

    def _slow(self) -> None:
        if self.rate != 1:
            self.cdp.send("Emulation.setCPUThrottlingRate", {"rate": self.rate})

    def open(self, url: str, until: str = "window.__probe && __probe.synced !== null") -> None:
        """Open `url` and wait for `until` (default: the first frame drawn synced). The rate
        is set again once the page is there: a navigation may move it to a new renderer."""
        self.page.goto(url)
        self._slow()
        self.page.wait_for_function(until, timeout=120_000)

    def __enter__(self) -> Phone:
        return self

    def __exit__(self, *exc) -> None:
        self.context.close()


def css_point(page, x: float, y: float) -> tuple[float, float]:
    """CSS px of the pane's px (x, y)."""
    r = page.evaluate("frost.paneCss()")
    return r["x"] + x * r["sx"], r["y"] + y * r["sy"]


PINGS = """async (n) => {
  const out = [];
  for (let i = 0; i < n; i++) {
    const t = performance.now();
    frost.socket.send(JSON.stringify({ type: "ping", t }));
    while (!(t in __probe.pongs)) await new Promise((resolve) => setTimeout(resolve, 1));
    out.push(__probe.pongs[t] - t);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  return out;
}"""


def taps(browser, s: Served, n: int, cpu_slowdown: float = 1.0,
         gap_s: float = GAP_S) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ms from each of `n` taps (`gap_s` apart at `tap_spots`) to the frame that first drew
    growth near it, and to the one that first drew frost near it (the page's own timing:
    frost.latencies, frost.frostLatencies); before them, the round trip of 20 pings on the
    page's socket (the server answers a ping on its loop, at once)."""
    with Phone(browser, cpu_slowdown) as phone:
        page = phone.page
        phone.open(s.url)
        pings = page.evaluate(PINGS, 20)
        for x, y in tap_spots(n):
            page.touchscreen.tap(*css_point(page, x, y))
            page.wait_for_timeout(gap_s * 1000)
        got = page.evaluate("[frost.latencies, frost.frostLatencies || []]")
    return np.asarray(got[0]), np.asarray(got[1]), np.asarray(pings)


def join(browser, url: str, cpu_slowdown: float = 1.0) -> dict:
    """One page opened on the server's pane at `url`: ms from the navigation's start to
    its socket open and to the first frame drawn with the whole snapshot; the bytes it
    received by then."""
    with Phone(browser, cpu_slowdown) as phone:
        phone.open(url)
        return phone.page.evaluate("({opened: __probe.opened, snapshot: __probe.snapshot,"
                                   " snapshotEnd: __probe.snapshotEnd, synced: __probe.synced,"
                                   " bytes: frost.bytes, tick: frost.tick})")


def strokes(seconds: float, seed: int = 0) -> list[tuple[float, float, float]]:
    """A finger's path for `seconds`: (s from the start, x, y) each MOVE_EVERY s, strokes
    between random points of the pane at FINGER_SPEED, the finger lifted 0.2 s between
    them (a None x then)."""
    rng = np.random.default_rng(seed)
    out: list = []
    t = 0.0
    while t < seconds:
        a, b = rng.uniform((20, 20), (WIDTH - 20, HEIGHT - 20), (2, 2))
        steps = max(1, int(np.hypot(*(b - a)) / FINGER_SPEED / MOVE_EVERY))
        for k in range(steps + 1):
            p = a + (b - a) * k / steps
            out.append((t, float(p[0]), float(p[1])))
            t += MOVE_EVERY
        out.append((t, None, None))
        t += 0.2
    return out


def scribble(browser, s: Served, seconds: float, cpu_slowdown: float = 1.0) -> dict:
    """A finger dragged over the pane for `seconds` (touch events through CDP, as the
    page's own tests send them, each sent at its time or skipped when the page is behind),
    and what the page did meanwhile."""
    with Phone(browser, cpu_slowdown) as phone:
        page, cdp = phone.page, phone.cdp
        phone.open(s.url)
        hellos = page.evaluate("frost.hellos")
        page.evaluate("__probe.frames = []; __probe.ticks = []; __probe.handled = []; __probe.resyncs = 0")
        start_tick = server_tick(s)
        r = page.evaluate("frost.paneCss()")
        css = lambda x, y: {"x": r["x"] + x * r["sx"], "y": r["y"] + y * r["sy"], "id": 1}  # noqa: E731
        t0, down, sent, skipped = time.monotonic(), False, 0, 0
        for when, x, y in strokes(seconds):
            late = time.monotonic() - t0 - when
            if late < 0:
                time.sleep(-late)
            elif late > MOVE_EVERY and x is not None and down:
                skipped += 1  # the page (or this machine) is behind: the next move catches up
                continue
            if x is None:
                if down:
                    cdp.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
                down = False
                continue
            cdp.send("Input.dispatchTouchEvent", {"type": "touchMove" if down else "touchStart",
                                                  "touchPoints": [css(x, y)]})
            down, sent = True, sent + 1
        if down:
            cdp.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
        elapsed = time.monotonic() - t0
        end_tick = server_tick(s)
        got = page.evaluate("({frames: __probe.frames, ticks: __probe.ticks, handled: __probe.handled,"
                            " resyncs: __probe.resyncs,"
                            " hellos: frost.hellos, synced: frost.synced, tick: frost.tick})")
    frames = np.asarray(got["frames"]) if got["frames"] else np.zeros((0, 3))
    received = set(got["ticks"])
    drawn = set(frames[:, 2].astype(int).tolist()) & received
    return {"seconds": elapsed, "moves": sent, "skipped": skipped, "resyncs": got["resyncs"],
            "reconnects": got["hellos"] - hellos, "synced": got["synced"],
            "work_ms": frames[:, 1], "interval_ms": np.diff(frames[:, 0]),
            "message_ms": np.asarray(got["handled"]),
            "received": len(received), "drawn": len(drawn), "server_ticks": end_tick - start_tick,
            "behind": end_tick - got["tick"]}


def phone_photo(path: Path, tint: int, size=(4000, 3000), target=4_000_000) -> int:
    """A phone camera's JPEG at `path`: `size` px of soft gradients, a few shapes and the
    sensor's grain (which is what makes a phone photo weigh 4 MB), its colours tinted by
    `tint` (each photo another); the quality is picked to land near `target` bytes. Its
    size in bytes."""
    from PIL import Image, ImageDraw, ImageFilter

    w, h = size
    rng = np.random.default_rng(tint)
    y = np.linspace(0, 1, h)[:, None, None]
    x = np.linspace(0, 1, w)[None, :, None]
    base = np.array([40 + tint * 37 % 120, 90, 180], float)
    sky = base * (1 - 0.6 * y) + np.array([250, 170, 90]) * 0.5 * y * (1 - x * 0.3)
    image = Image.fromarray(np.clip(sky, 0, 255).astype(np.uint8))
    draw = ImageDraw.Draw(image)
    for _ in range(12):
        cx, cy, r = rng.integers(0, w), rng.integers(h // 3, h), rng.integers(80, 600)
        draw.ellipse([cx - r, cy - r, cx + r, cy + r], fill=tuple(int(v) for v in rng.integers(20, 250, 3)))
    image = image.filter(ImageFilter.GaussianBlur(6))
    grain = rng.normal(0, 9, (h, w, 1))
    image = Image.fromarray(np.clip(np.asarray(image, float) + grain, 0, 255).astype(np.uint8))
    for quality in (95, 92, 89, 86, 83, 80, 75, 70):
        image.save(path, "JPEG", quality=quality)
        if path.stat().st_size <= target * 1.1:
            break
    return path.stat().st_size


def photos(browser, s: Served, n: int, cpu_slowdown: float = 1.0) -> dict:
    """`n` phone photos chosen one after another on one page's "Use a photo…" (6 s apart:
    the server takes one every 5 s from an address), a second page open beside it: for
    each, ms from the choice to the sender's POST answered and to each page's first frame
    drawn with it."""
    from app.photos import MAX_BYTES

    out: dict[str, list[float]] = {"answered": [], "sender": [], "other": [], "all": []}
    with tempfile.TemporaryDirectory() as tmp, Phone(browser, cpu_slowdown) as a, \
            Phone(browser, cpu_slowdown) as b:
        a.open(s.url)
        b.open(s.url)
        files = [Path(tmp) / f"IMG_{k:04d}.jpg" for k in range(n)]
        sizes = [phone_photo(f, k) for k, f in enumerate(files)]
        assert max(sizes) <= MAX_BYTES
        for file in files:
            a.page.set_input_files("#photo-file", str(file))
            a.page.wait_for_function("frost.photo && frost.photo.last && frost.photo.last.status",
                                     timeout=120_000)
            last = a.page.evaluate("frost.photo.last")
            if last.get("error"):
                raise RuntimeError(f"the photo was refused: {last['error']}")
            name = last["backdrop"]
            shown = f"__probe.shown.some(([n]) => n === {json.dumps(name)})"
            for phone in (a, b):
                phone.page.wait_for_function(shown, timeout=120_000)
            picked = a.page.evaluate("__probe.picked[__probe.picked.length - 1]")
            when = [phone.page.evaluate(f"__probe.shown.find(([n]) => n === {json.dumps(name)})[1]")
                    for phone in (a, b)]
            out["answered"].append(a.page.evaluate("frost.photo.last.answered") - picked)
            out["sender"].append(when[0] - picked)
            out["other"].append(when[1] - picked)
            out["all"].append(max(when) - picked)
            a.page.evaluate("frost.photo.last = null")
            a.page.wait_for_timeout(6000)
    return {**{k: np.asarray(v) for k, v in out.items()}, "sizes": sizes}


def stats(ms: np.ndarray) -> str:
    if not len(ms):
        return "none"
    def f(v: float) -> str:
        return f"{v:.1f}" if v < 10 else f"{v:.0f}"
    return (f"median {f(np.median(ms))} ms, p95 {f(np.percentile(ms, 95))} ms, "
            f"p99 {f(np.percentile(ms, 99))} ms, max {f(ms.max())} ms")


def load() -> str:
    """The machine's load averages (1, 5, 15 min), as `uptime` says them."""
    try:
        with open("/proc/loadavg", encoding="utf-8") as f:
            return "load average " + ", ".join(f.read().split()[:3])
    except OSError:
        return "load average unknown"


def run(args, network: Profile | None, launch) -> int:
    """`python -m bench page --taps/--join/--scribble`: the measure asked, printed."""
    from playwright.sync_api import sync_playwright

    where = network.describe() if network else "loopback"
    slow = f", CPU slowed {args.cpu_slowdown:g}x" if args.cpu_slowdown != 1 else ""
    preset = args.preset or ("window" if args.join else "fern")
    print(f"before: {load()}")
    with sync_playwright() as pw, served(preset, network) as s:
        browser = launch(pw)
        try:
            if args.taps:
                growth, frost, pings = taps(browser, s, args.taps, args.cpu_slowdown)
                print(f"the page's socket, ping to pong ({where}{slow}, {len(pings)} pings): "
                      f"{stats(pings)}")
                for what, ms in (("growth", growth), ("frost (the seed's own ice)", frost)):
                    print(f"touch to first drawn {what} ({preset}, {where}{slow}, {len(ms)} of "
                          f"{args.taps} taps seen): {stats(ms)}")
                if len(growth) < args.taps:
                    print(f"{args.taps - len(growth)} of the taps drew no growth before the next "
                          f"tap ({GAP_S} s later): a seed in finished ice has no open slot ('never' "
                          "in `frost bench sim --section taps`, the same taps through the "
                          "simulation alone)")
            if args.join:
                ticks = args.ticks or JOIN_TICKS
                print(f"growing {preset} to tick {ticks} ({ticks / 25:.0f} s at 25 ticks a second) ...",
                      flush=True)
                while server_tick(s) < ticks:
                    time.sleep(1)
                # With a network, joins on loopback too (to the server directly), taken in
                # turn with the shaped ones: the same pane, the same machine's load.
                ways = {where: s.url, **({"loopback": s.server} if network else {})}
                joins: dict[str, list[dict]] = {name: [] for name in ways}
                down: list[int] = []  # bytes down the shaped link in each of its joins
                for _ in range(args.join):
                    for name, url in ways.items():
                        before = s.shaper.shaper.down_bytes if s.shaper else 0
                        joins[name].append(join(browser, url, args.cpu_slowdown))
                        if s.shaper and name == where:
                            down.append(s.shaper.shaper.down_bytes - before)
                for name, pages in joins.items():
                    synced = np.array([j["synced"] for j in pages])
                    opened = np.array([j["opened"] for j in pages])
                    print(f"late join ({preset} at ticks {pages[0]['tick']}-{pages[-1]['tick']}, "
                          f"{name}{slow}, {len(pages)} new pages, snapshot and the ticks since: "
                          f"{np.median([j['bytes'] for j in pages]) / 1e6:.2f} MB):")
                    parts = {k: np.array([j[k] for j in pages]) for k in ("snapshot", "snapshotEnd")}
                    print(f"  navigation to socket open (the page's files loaded): {stats(opened)}")
                    print(f"  socket open to the snapshot's first part: "
                          f"{stats(parts['snapshot'] - opened)}")
                    print(f"  the snapshot's first part to its last: "
                          f"{stats(parts['snapshotEnd'] - parts['snapshot'])}")
                    print(f"  its last part to the first frame drawn synced: "
                          f"{stats(synced - parts['snapshotEnd'])}")
                    print(f"  navigation to the first frame drawn synced: {stats(synced)}")
                    if name == where and down:  # as sent: the socket's messages deflated
                        print(f"  down the link for the whole join (the page's files and its "
                              f"socket, compressed as sent): {np.median(down) / 1e6:.2f} MB")
            if args.photo:
                got = photos(browser, s, args.photo, args.cpu_slowdown)
                mb = np.median(got["sizes"]) / 1e6
                print(f"a phone photo chosen on one page ({mb:.1f} MB JPEG, 4000x3000; {where}{slow}, "
                      f"{args.photo} photos, two pages):")
                print(f"  chosen to the server's answer (scaled and encoded on the page, sent, "
                      f"checked and kept): {stats(got['answered'])}")
                print(f"  chosen to drawn on the sending page: {stats(got['sender'])}")
                print(f"  chosen to drawn on the other page: {stats(got['other'])}")
                print(f"  chosen to drawn on every page: {stats(got['all'])}")
            if args.scribble:
                got = scribble(browser, s, args.scribble, args.cpu_slowdown)
                work, gaps = got["work_ms"], got["interval_ms"]
                print(f"scribble ({preset}, {where}{slow}, {got['seconds']:.0f} s, {got['moves']} "
                      f"finger moves sent, {got['skipped']} skipped as late):")
                print(f"  kept up: {got['resyncs']} resyncs, {got['reconnects']} reconnects, synced "
                      f"at the end: {got['synced']}, the page {got['behind']} ticks behind the server")
                print(f"  a message's handling on the page's main thread (decoded, applied): "
                      f"{stats(got['message_ms'])} ({len(got['message_ms'])} messages)")
                print(f"  a frame's work on the page's main thread: {stats(work)} ({len(work)} frames drawn)")
                print(f"  time between drawn frames: {stats(gaps)}")
                print(f"  ticks drawn in a frame of their own: {got['drawn']} of the {got['received']} "
                      f"received ({got['drawn'] / max(got['received'], 1):.1%}; the server ticked "
                      f"{got['server_ticks']} times meanwhile)")
        finally:
            browser.close()
    print(f"after: {load()}")
    return 0
