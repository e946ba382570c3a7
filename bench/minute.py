"""The lock screen's clock: what a minute costs. Bytes a page receives a minute (the clock
message: the clock box as a PNG), the server's drawing and encoding of it, and the frame
cost of that minute's frame: on the desktop (the box drawn, uploaded with
`texture.write(viewport=...)`, a whole frame drawn and read back) and on the page (the
message's PNG decoded, `texSubImage2D`, a whole frame drawn and one pixel read back),
each beside a frame with no new minute. Both over frost grown from three touches.

python -m bench minute [--samples 20]
"""

from __future__ import annotations

import io
import sys
import tempfile
import time

import numpy as np
from PIL import Image

from app.backdrops import LIVE, load_backdrop, read_backdrop
from app.bench.options import Parser, count
from app.lockscreen import CLOCK_BOX, clock_patch
from app.serve.protocol import clock_message
from bench.serve_process import ServeProcess
from sim import Params

TOUCHES = ((380.0, 330.0), (170.0, 760.0), (600.0, 1050.0))


def figures(name: str, ms: list[float]) -> str:
    a = np.asarray(ms)
    return (f"{name}: median {np.median(a):.2f} ms, p95 {np.percentile(a, 95):.2f} ms "
            f"({len(a)} samples)")


def minutes(n: int) -> list[str]:
    return [f"2026-11-26T{10 + k // 60:02d}:{k % 60:02d}" for k in range(n)]


def server_side(samples: int) -> None:
    static = np.asarray(read_backdrop(LIVE))
    draw, encode, sizes = [], [], []
    for minute in minutes(samples):
        t0 = time.perf_counter()
        patch = clock_patch(static, minute)
        t1 = time.perf_counter()
        out = io.BytesIO()
        Image.fromarray(patch).save(out, "PNG", compress_level=6)
        sizes.append(len(clock_message(CLOCK_BOX, minute, out.getvalue())))
        draw.append((t1 - t0) * 1000)
        encode.append((time.perf_counter() - t1) * 1000)
    whole = io.BytesIO()
    Image.fromarray(load_backdrop(LIVE)).save(whole, "PNG")
    print(f"clock message: median {np.median(sizes) / 1000:.1f} kB a minute, a page "
          f"(max {max(sizes) / 1000:.1f} kB); the whole backdrop's PNG "
          f"{len(whole.getvalue()) / 1000:.1f} kB, raw {static.nbytes / 1e6:.2f} MB")
    print("server, once a minute for all pages, on a worker:")
    print("  " + figures("clock box drawn", draw))
    print("  " + figures("PNG encoded", encode))


def desktop(samples: int) -> None:
    from app.tools.offscreen import Offscreen, make_context
    from app.tools.render_png import touch_events

    ctx = make_context()
    view = {"light": [0.4, 0.5, 1.0], "features": True, "bumps": True, "background": LIVE}
    for look in ("paper", "glass"):
        off = Offscreen(ctx, Params.preset("fern", look=look), 5, view)
        off.grow(300, touch_events(TOUCHES))
        one = np.empty(4, np.uint8)

        def frame(off: Offscreen = off, one: np.ndarray = one) -> None:
            off.renderer.render(off.fbo)
            off.fbo.read_into(one, viewport=(0, 0, 1, 1), components=4)

        frame()
        plain, minute, upload, loop = [], [], [], []
        for m in minutes(samples):
            t0 = time.perf_counter()
            frame()
            t1 = time.perf_counter()
            off.renderer.set_minute(m)
            t2 = time.perf_counter()
            frame()
            t3 = time.perf_counter()
            plain.append((t1 - t0) * 1000)
            upload.append((t2 - t1) * 1000)
            minute.append((t3 - t1) * 1000)
            # the window: the box drawn on its worker (app/window/clock_drawer.py), the loop's
            # part the upload and the frame
            later = m.replace("T1", "T2", 1)  # (another minute than the one shown)
            box = off.renderer.clock_box(later)
            t4 = time.perf_counter()
            off.renderer.set_minute(later, box)
            frame()
            loop.append((time.perf_counter() - t4) * 1000)
        print(f"desktop ({look}, {ctx.info['GL_RENDERER']}):")
        print("  " + figures("a frame, no new minute", plain))
        print("  " + figures("the box drawn and uploaded", upload))
        print("  " + figures("the minute's frame (box drawn, uploaded, frame drawn)", minute))
        print("  " + figures("the window's minute frame (box drawn on its worker: "
                             "uploaded, frame drawn)", loop))
        off.release()


PAGE_TIMES = """async (n) => {
  const s = window.frost, c = s.clock, r = s.renderer, gl = r.gl, one = new Uint8Array(4);
  const frame = () => { r.render(false); gl.bindFramebuffer(gl.FRAMEBUFFER, r.frameFbo);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one); gl.bindFramebuffer(gl.FRAMEBUFFER, null); };
  const out = { plain: [], decode: [], minute: [] };
  for (let i = 0; i < n; i++) {
    r.damageAll(); let t0 = performance.now(); frame(); out.plain.push(performance.now() - t0);
    t0 = performance.now();
    await c.receive(c.last, s);  // decoded, texSubImage2D
    const t1 = performance.now(); frame();
    out.decode.push(t1 - t0); out.minute.push(performance.now() - t0);
  }
  return out;
}"""


def page(samples: int) -> None:
    from playwright.sync_api import sync_playwright

    from bench.chromium import launch

    served = ServeProcess("--port", "0", "--session-dir", tempfile.mkdtemp(), "--preset", "fern",
                          "--seed", "5", "--background", LIVE, "--clock-start", "10:00").drain()
    try:
        with sync_playwright() as pw:
            browser = launch(pw)
            tab = browser.new_context(viewport={"width": 390, "height": 844},
                                      device_scale_factor=3).new_page()
            tab.goto(served.local)
            tab.wait_for_function("window.frost && frost.synced && frost.clock.shown", timeout=60_000)
            for look in ("glass", "paper"):
                tab.evaluate(f"frost.socket.send(JSON.stringify({{type: 'look', name: '{look}'}}))")
                for x, y in TOUCHES:
                    tab.evaluate(f"frost.socket.send(JSON.stringify({{type: 'touch', x: {x}, y: {y}}}))")
                tab.wait_for_timeout(8000)
                tab.evaluate("frost.socket.send(JSON.stringify({type: 'pause'}))")
                tab.wait_for_timeout(1000)
                t = tab.evaluate(PAGE_TIMES, samples)
                tab.evaluate("frost.socket.send(JSON.stringify({type: 'pause'}))")
                print(f"page ({look}, headless Chromium, WebGL2 on SwiftShader; "
                      f"{tab.evaluate('frost.clock.last.byteLength') / 1000:.1f} kB message):")
                print("  " + figures("a frame, no new minute", t["plain"]))
                print("  " + figures("the message decoded and uploaded", t["decode"]))
                print("  " + figures("the minute's frame (decoded, uploaded, frame drawn)", t["minute"]))
            browser.close()
    finally:
        served.stop()


def main(argv: list[str] | None = None, prog: str = "python -m bench minute") -> int:
    p = Parser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--samples", type=count, default=20, metavar="N",
                   help="minutes timed in each place (default 20)")
    p.add_argument("--no-page", action="store_true", help="skip the page (no Chromium)")
    args = p.parse_args(argv)
    server_side(args.samples)
    desktop(args.samples)
    if not args.no_page:
        page(args.samples)
    return 0


if __name__ == "__main__":
    sys.exit(main())
