"""The phone page against the desktop: the same frost drawn by the desktop renderer (EGL,
headless) and by the page (app/web, WebGL2 in headless Chromium), compared pixel for pixel,
and the page's frame time at 760x1280.

The page is driven without a server: Playwright serves app/web, the shaders and the
backdrops from disk and stands in for the WebSocket, sending the hello and the geometry
messages of the protocol (app.serve.protocol) for the deltas the desktop renderer applied.

python -m bench page [--preset fern] [--look paper] [--ticks 300] [--frames 60]
    [--out DIR]
python -m bench page --phone-app [--out DIR]   (bench/phoneapp.py)
python -m bench page --local [--cpu-slowdown 4]   (bench/local.py: the phone's own frost)
Or, through `frost serve` (bench/network.py), on loopback or a phone-like network:
python -m bench page --taps N | --join N | --scribble S | --photo N [--network wifi|4g]
    [--cpu-slowdown 4]
"""

from __future__ import annotations

import io
import json
import mimetypes
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from app.backdrops import DEFAULT_BACKDROP, load_backdrop
from app.bench.options import Parser, count, slowdown
from app.resources import SHADER_DIR, WEB_DIR
from app.serve.hello import hello_fields
from bench.chromium import ANGLE, browser_problem, launch
from bench.local import GROW_TICKS, WINDOW_TICKS
from bench.network import JOIN_TICKS
from bench.shaper import PROFILES, profile
from sim import Params, all_presets
from sim.look.geometry import GeometryDelta
from sim.screen import HEIGHT, WIDTH

ORIGIN = "http://frost.test"  # the page's address when Playwright serves it from disk
# Touches the bench grows its frost from (screen px), and a warm finger's melt (x, y, r)
# two thirds of the way (a wipe of the page's features, then the survivors re-sent).
TOUCHES = ((380.0, 640.0), (200.0, 300.0), (560.0, 1000.0))
MELT = (380.0, 600.0, 40.0)


def hello(params: Params, backdrop: str = DEFAULT_BACKDROP) -> dict:
    """A hello as `frost serve` sends it (`app.serve.hello`), for `params` at tick 0."""
    s = params.grid_spacing
    return {"type": "hello", **hello_fields(params, backdrop, (WIDTH // s + 1, HEIGHT // s + 1)),
            "tick": 0, "paused": False, "look": params.look, "backdrop": backdrop}


def bench_events(ticks: int) -> list[dict]:
    """The bench's touches at tick 0 and its melt two thirds of the way."""
    from sim.io.timeline import touch_events

    x, y, r = MELT
    return [*touch_events(TOUCHES), {"tick": 2 * ticks // 3, "kind": "melt", "x": x, "y": y, "r": r}]


def grow(params: Params, seed: int, ticks: int, events=None, ctx=None):
    """(Offscreen with the frost grown with `events` (default: bench_events), every delta
    its renderer applied, in order: a rebuild's reset as an empty reset delta)."""
    from app.tools.offscreen import Offscreen, make_context
    from sim.io.timeline import grow as grow_timeline

    off = Offscreen(ctx or make_context(), params, seed)
    deltas: list[GeometryDelta] = []

    def applied(result) -> None:
        off.show(result)
        if result.reset:
            deltas.append(reset_delta(off.sim.tick, params))
        deltas.extend(result.deltas)

    def step(delta: GeometryDelta) -> None:
        off.renderer.apply(delta)
        deltas.append(delta)

    grow_timeline(off.timeline, ticks, bench_events(ticks) if events is None else events,
                  applied, step)
    return off, deltas


def reset_delta(tick: int, params: Params) -> GeometryDelta:
    cols = WIDTH // params.grid_spacing + 1
    return GeometryDelta(tick, slice(0, 0), np.zeros((0, cols), np.float32),
                         np.zeros((0, 6), np.float32), reset=True, look=params.look)


@lru_cache(maxsize=4)
def backdrop_png(name: str) -> bytes:
    """Backdrop `name` as a PNG, as the page asks for it (made once a process: every page of
    a run asks for the same)."""
    buf = io.BytesIO()
    Image.fromarray(load_backdrop(name)).save(buf, format="PNG")
    return buf.getvalue()


class Page:
    """The page in headless Chromium, served from disk, fed `messages` over a stand-in
    WebSocket; what the page sends is kept in `sent`. Use as a context manager; `browser`
    (launch) is shared if given, else the page starts its own."""

    def __init__(self, hello_message: dict, messages: list[bytes], viewport=(WIDTH, HEIGHT),
                 scale: float = 1.0, browser=None, touch: bool = False, later=(),
                 angle: str = "swiftshader", hang_up: bool = True, meta: dict | None = None,
                 init: str | None = None):
        # `later`: what each later connection gets (with `hang_up` a socket is closed once
        # its messages are sent, while a later connection is to come). `meta`: what GET /meta
        # answers (as frost serve's), else 404. `init`: a script run before the page's own
        # (e.g. a choice in localStorage).
        self.hello, self.messages, self.meta = hello_message, messages, meta
        self.connections, self.hang_up = [messages, *later], hang_up
        self.viewport, self.scale, self.touch = viewport, scale, touch
        self.browser, self.angle, self.init = browser, angle, init
        self._pw: Any = None  # playwright, when this page started its own
        self.sent: list[dict] = []

    def __enter__(self) -> Page:
        if self.browser is None:
            from playwright.sync_api import sync_playwright

            self._pw = sync_playwright().start()
            self.browser = launch(self._pw, self.angle)
        self.context = self.browser.new_context(
            viewport={"width": self.viewport[0], "height": self.viewport[1]},
            device_scale_factor=self.scale, has_touch=self.touch, is_mobile=self.touch)
        if self.init:
            self.context.add_init_script(self.init)
        self.page = self.context.new_page()
        self.page.route(f"{ORIGIN}/**", self._serve)
        self.page.route_web_socket(f"{ORIGIN.replace('http', 'ws')}/ws**", self._socket)
        self.page.goto(f"{ORIGIN}/")
        self.page.wait_for_function(
            f"window.frost && (window.frost.error || window.frost.messages >= {len(self.messages) + 1})",
            timeout=60_000)
        self.page.wait_for_function(
            "window.frost.error || (window.frost.frames > 0 && window.frost.hello"
            " && window.frost.shownBackdrop === window.frost.hello.backdrop)")
        error = self.page.evaluate("window.frost.error")
        if error:
            raise RuntimeError(f"the page failed: {error}")
        return self

    def __exit__(self, *exc) -> None:
        self.context.close()
        if self._pw is not None:
            self.browser.close()
            self._pw.stop()

    def _serve(self, route) -> None:
        path = route.request.url[len(ORIGIN):].split("?")[0]
        if path == "/":
            return route.fulfill(path=str(WEB_DIR / "index.html"))
        for prefix, folder in (("/web/", WEB_DIR), ("/shaders/", SHADER_DIR)):
            name = path[len(prefix):]
            # (a page module's own folder too: /web/local/shared.js, which weather_local.js
            # imports; no other depth, and nothing outside the folder)
            if path.startswith(prefix) and ("/" not in name or name.count("/") == 1
                                            and name.startswith("local/") and ".." not in name):
                file = folder / name
                if file.is_file():
                    kind = "text/javascript" if file.suffix == ".js" else mimetypes.guess_type(file.name)[0]
                    return route.fulfill(body=file.read_bytes(), content_type=kind or "text/plain")
        if path == "/meta" and self.meta is not None:
            return route.fulfill(body=json.dumps(self.meta), content_type="application/json")
        if path.startswith("/backdrops/") and path.endswith(".png"):
            return route.fulfill(body=backdrop_png(path[len("/backdrops/"):-4]), content_type="image/png")
        return route.fulfill(status=404, body="not found")

    def _socket(self, ws) -> None:
        self.socket = ws  # the latest, for tests that send more
        ws.on_message(lambda m: self.sent.append(json.loads(m)))
        ws.send(json.dumps(self.hello))
        messages = self.connections.pop(0)
        for message in messages:
            ws.send(message)
        if self.connections and self.hang_up:
            ws.close(code=1001, reason="going away")

    def pixels(self) -> np.ndarray:
        """The page's frame, H x W x 3 uint8, top row first."""
        import base64

        raw = base64.b64decode(self.page.evaluate("window.frost.framePixels()"))
        return np.frombuffer(raw, np.uint8).reshape(HEIGHT, WIDTH, 4)[:, :, :3].copy()

    def frame_times(self, n: int) -> np.ndarray:
        """Milliseconds of `n` full frames, each waited for."""
        return np.asarray(self.page.evaluate(f"window.frost.frameTimes({n})"))


def encode(deltas: list[GeometryDelta], params: Params) -> list[bytes]:
    """The geometry messages a server sends for `deltas`, in order."""
    from app.serve.protocol import Encoder

    s = params.grid_spacing
    enc = Encoder(WIDTH // s + 1, HEIGHT // s + 1)
    return [enc.delta(d) for d in deltas]


def wire_deltas(messages: list[bytes], params: Params) -> list[GeometryDelta]:
    """The deltas as a page receives them (heights as half floats, vertices in 1/16 px,
    normals in 1/127): `messages` decoded back, each as the rows its height runs touch."""
    from app.serve.protocol import RESET, apply_geometry, decode_geometry

    s = params.grid_spacing
    cols, rows = WIDTH // s + 1, HEIGHT // s + 1
    grid = np.zeros(rows * cols, np.float32)
    out = []
    for message in messages:
        m = decode_geometry(message)
        apply_geometry(grid, m)
        touched = [r for start, count in m["runs"]
                   for r in range(start // cols, (start + count - 1) // cols + 1)]
        lo, hi = (min(touched), max(touched) + 1) if touched else (0, 0)
        out.append(GeometryDelta(m["tick"], slice(lo, hi), grid.reshape(rows, cols)[lo:hi].copy(),
                                 m["vertices"], reset=bool(m["flags"] & RESET),
                                 clear_box=m["clear_box"], look=m["look"],
                                 height_scale=m["height_scale"]))
    return out


def desktop_frame(ctx, params: Params, deltas: list[GeometryDelta]) -> np.ndarray:
    """`deltas` applied in order by a fresh desktop renderer, its frame."""
    from app.gl.renderer import Renderer
    from app.images import read_image

    renderer = Renderer(ctx, params, WIDTH, HEIGHT)
    for delta in deltas:
        renderer.apply(delta)
    fbo = ctx.simple_framebuffer((WIDTH, HEIGHT), components=4)
    renderer.render(fbo)
    return read_image(fbo)


def desktop_frame_times(off, n: int) -> np.ndarray:
    """Milliseconds of `n` full frames of the desktop renderer (EGL), each waited for."""
    import time

    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        off.renderer.render(off.fbo)
        off.fbo.read(viewport=(0, 0, 1, 1))
        times.append((time.perf_counter() - t0) * 1e3)
    return np.asarray(times)


def compare(a: np.ndarray, b: np.ndarray) -> dict:
    """Mean absolute difference (of 255) and the share of pixels whose every channel is
    within 8/255, of two H x W x 3 uint8 images."""
    d = np.abs(a.astype(np.int16) - b.astype(np.int16))
    return {"mad": float(d.mean()), "within8": float((d.max(axis=2) <= 8).mean()),
            "max": int(d.max())}


def difference_image(a: np.ndarray, b: np.ndarray, gain: float = 8.0) -> np.ndarray:
    d = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(axis=2)
    return np.clip(d * gain, 0, 255).astype(np.uint8)


SNAPSHOT_WORK = """async ([parts, n, phones]) => {
  const proto = await import("./web/protocol.js");
  const fit = await import("./web/fit.js");
  const r = frost.renderer, gl = r.gl, one = new Uint8Array(4);
  const buffers = parts.map((b64) => Uint8Array.from(atob(b64), (c) => c.charCodeAt(0)).buffer);
  const wait = () => {  // (WebGL only queues its work: a 1-px read waits for all of it)
    gl.bindFramebuffer(gl.FRAMEBUFFER, r.frameFbo);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  };
  const timed = (f) => { wait(); const t0 = performance.now(); f(); wait(); return performance.now() - t0; };
  // What a covering pane shows of itself on each phone's screen (CSS px; pane px).
  const views = phones.map(([w, h]) => fit.visiblePane(fit.paneRect(w, h, "fill"), w, h));
  const out = { apply: [], features: [], whole: [], views: views.map(() => []), shown: views };
  for (let i = 0; i < n; i++) {
    out.apply.push(timed(() => { for (const b of buffers) r.apply(proto.decodeDelta(b)); }));
    out.features.push(timed(() => r.features.drawQueued()));
    out.whole.push(timed(() => r.render(true)));
    views.forEach((v, k) => out.views[k].push(timed(() => r.render(true, v))));
  }
  return out;
}"""
PHONES = {"portrait 390x844": (390, 844), "landscape 844x390": (844, 390)}


def snapshot_work(n: int, ticks: int, angle: str, browser=None) -> int:
    """`--snapshot-work N`: the window pane grown `ticks` ticks by the simulation alone,
    its snapshot (as frost serve draws one for a late join) given to the page N times, each
    step's time printed (ms, waited for on the GPU); in `browser` (launch's) if given."""
    import base64

    from playwright.sync_api import sync_playwright

    from app.serve.protocol import Encoder
    from sim.io.timeline import Timeline
    from sim.look.geometry import IceCopy, feature_scale, live_features

    params = Params.preset("window")
    timeline = Timeline(params, 0, WIDTH, HEIGHT)
    for _ in range(ticks):
        timeline.step()
    g = timeline.geometry
    features = live_features(IceCopy.of(timeline.sim), params)
    parts = Encoder(g.cols, g.rows).snapshot(ticks, features, params.look, feature_scale(params),
                                             heights=g.heights.ravel().astype(np.float16))
    print(f"window, {params.look}, tick {ticks}: a snapshot of {sum(map(len, parts)) / 1e6:.2f} MB "
          f"in {len(parts)} parts, {len(features) // 3} triangles; each step {n} times, "
          "waited for on the GPU (a 1-px read)")
    def measure(browser) -> dict:
        with Page(hello(params), [], viewport=PHONES["portrait 390x844"], scale=3, touch=True,
                  browser=browser) as page:
            return page.page.evaluate(SNAPSHOT_WORK, [[base64.b64encode(p).decode() for p in parts],
                                                      n, list(PHONES.values())])

    if browser is not None:
        got = measure(browser)
    else:
        with sync_playwright() as pw:
            browser = launch(pw, angle)
            got = measure(browser)
            browser.close()
    stat = lambda ms: f"median {np.median(ms):.1f} ms, p99 {np.percentile(ms, 99):.1f} ms"  # noqa: E731
    print("  applied (decoded, heights uploaded, tiles marked; the page's main thread): "
          f"{stat(got['apply'])}")
    print(f"  its features rasterized: {stat(got['features'])}")
    print(f"  the whole pane drawn ({WIDTH}x{HEIGHT}): {stat(got['whole'])}")
    for (name, _), times, (x0, y0, x1, y1) in zip(PHONES.items(), got["views"], got["shown"],
                                                  strict=True):
        print(f"  what a {name} phone shows drawn (pane px {x0}-{x1} x {y0}-{y1}): {stat(times)}")
    return 0


def main(argv: list[str] | None = None, prog: str = "python -m bench page") -> int:
    p = Parser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--preset", choices=list(all_presets()), metavar="NAME",
                   help="parameter set to grow (default fern; window with --join)")
    p.add_argument("--look", choices=("paper", "glass"), help="default: the preset's")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--ticks", type=count, help="ticks to grow (default 300; with --join "
                   f"{JOIN_TICKS}: the frosted window pane; with --local {GROW_TICKS}, the worker's "
                   f"p99 window; with --local --preset window {WINDOW_TICKS}: the full pane)")
    p.add_argument("--frames", type=count, default=60, help="page frames timed (default 60)")
    p.add_argument("--angle", choices=list(ANGLE), default="swiftshader",
                   help="the page's WebGL: Chromium's SwiftShader (default) or the system's "
                        "OpenGL through EGL (gl-egl)")
    p.add_argument("--taps", type=count, help="instead: touch to first drawn growth through frost "
                   "serve on loopback, over this many taps")
    p.add_argument("--phone-app", action="store_true", help="instead: the page as a phone app through "
                   "frost serve (black share of the screen, tilt, screenshots in --out as .webp)")
    p.add_argument("--join", type=count, metavar="N", help="instead: N pages opened one after "
                   "another on a pane grown --ticks ticks: time to a synced page")
    p.add_argument("--scribble", type=count, metavar="S", help="instead: a finger dragged over "
                   "the pane for S seconds: whether the page keeps up, its frame times, the "
                   "share of ticks it draws")
    p.add_argument("--photo", type=count, metavar="N", help="instead: N phone photos (4 MB "
                   "JPEGs, 4000x3000) chosen on one page: time until every page (two) shows it")
    p.add_argument("--snapshot-work", type=count, metavar="N", help="instead: the page's own work on "
                   "a late join's snapshot, N times (the window pane grown --ticks ticks by the "
                   "simulation alone; no server): applying it, its features, the whole pane "
                   "drawn and the part a portrait and a landscape phone shows")
    p.add_argument("--local", action="store_true", help="instead: the phone's own frost (the page "
                   "installed, the server stopped): the worker's tick, the page's frames under "
                   "--cpu-slowdown (default 4 here), the Python tick beside; with --preset window the "
                   "frosted window grown to the full pane (its worker's tick, its frosted share), then "
                   "the fern in the same page")
    p.add_argument("--network", metavar="PROFILE", help="with --taps, --join, --scribble, --photo: the "
                   "page reaches the server through a shaping proxy: " + "; ".join(
                       x.describe() for x in PROFILES.values()) + " (default: loopback)")
    p.add_argument("--cpu-slowdown", type=slowdown, default=None, metavar="N",
                   help="with --taps, --join, --scribble, --photo, --local: the page's CPU N times slower "
                   "(Chromium's throttling; 4 is Lighthouse's phone; default 1, 4 with --local)")
    p.add_argument("--out", help="write desktop.png, page.png, difference.png here")
    args = p.parse_args(argv)
    network = None
    if args.network is not None:
        try:
            network = profile(args.network)
        except ValueError as err:
            p.error(f"argument --network: {err}")
    served = args.taps or args.join or args.scribble or args.photo
    if args.local:
        if browser_problem():
            print(f"frost: error: {browser_problem()}")
            return 2
        from bench.local import run as local
        return local(args, args.cpu_slowdown or 4.0, TOUCHES)
    args.cpu_slowdown = args.cpu_slowdown or 1.0
    if not served and (network or args.cpu_slowdown != 1):
        p.error("--network and --cpu-slowdown go with --taps, --join, --scribble or --photo "
                "(the parity bench has no server)")
    problem = browser_problem()
    if problem:
        print(f"frost: error: {problem}")
        return 2
    if args.snapshot_work:
        return snapshot_work(args.snapshot_work, args.ticks or JOIN_TICKS, args.angle)
    if args.phone_app:
        from bench.phoneapp import run as phone_app

        return phone_app(args.out, args.angle, launch)
    if served:
        from bench.network import run
        return run(args, network, launch)
    args.preset = args.preset or "fern"
    args.ticks = args.ticks or 300
    params = Params.preset(args.preset)
    if args.look:
        params = params.replace(look=args.look)
    try:
        off, deltas = grow(params, args.seed, args.ticks)
    except RuntimeError as err:  # no EGL context
        print(f"frost: error: {err}")
        return 2
    desktop = off.frame()
    messages = encode(deltas, params)
    wire = desktop_frame(off.renderer.ctx, params, wire_deltas(messages, params))
    with Page(hello(params), messages, angle=args.angle) as page:
        shown = page.pixels()
        times = page.frame_times(args.frames)
    print(f"{args.preset}, {params.look}, {args.ticks} ticks, {len(messages)} messages, "
          f"{sum(map(len, messages)) / 1e3:.0f} kB")
    for name, a, b in (("page vs desktop", desktop, shown),
                       ("page vs desktop fed the page's messages", wire, shown),
                       ("desktop fed the messages vs desktop", desktop, wire)):
        got = compare(a, b)
        print(f"{name}: mean abs difference {got['mad']:.4f}/255, within 8/255 {got['within8']:.4%}, "
              f"largest {got['max']}")
    for name, t in ((f"page (Chromium, {args.angle})", times),
                    ("desktop (EGL)", desktop_frame_times(off, args.frames))):
        print(f"{name} frame time at {WIDTH}x{HEIGHT}: median {np.median(t):.1f} ms, "
              f"p99 {np.percentile(t, 99):.1f} ms ({args.frames} frames)")
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        Image.fromarray(desktop).save(out / "desktop.png")
        Image.fromarray(shown).save(out / "page.png")
        Image.fromarray(wire).save(out / "desktop-wire.png")
        Image.fromarray(difference_image(desktop, shown)).save(out / "difference.png")
        Image.fromarray(difference_image(wire, shown)).save(out / "difference-wire.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
