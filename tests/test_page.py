"""The phone page (app/web) in headless Chromium, without a server: Playwright serves its
files from disk and stands in for the WebSocket (bench.page.Page). The desktop
renderer (EGL) and numpy are the oracles. The page's WebGL is the tests' (the system's
OpenGL: llvmpipe here), or SwiftShader where the page's frost is held to the desktop's
across two rasterisers."""

from __future__ import annotations

import io
import json
import re
import time

import numpy as np
import pytest
from PIL import Image
from support.phone import launch_browser

from app.gl import shaders
from app.resources import WEB_DIR
from bench.page import (
    Page,
    browser_problem,
    compare,
    desktop_frame,
    encode,
    grow,
    hello,
    wire_deltas,
)
from sim import Params
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES

PROBLEM = browser_problem()
pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]


def sent_until(page: Page, done, what: str, timeout: float = 30.0) -> list[dict]:
    """What the page sent, once `done(sent)` holds: polled, as its messages reach the
    stand-in server only while Playwright runs; AssertionError naming `what` if it does
    not within `timeout` s (a bound on a failure, not a claim)."""
    end = time.monotonic() + timeout
    while not done(page.sent):
        if time.monotonic() > end:
            raise AssertionError(f"not sent within {timeout:g} s: {what}: {page.sent}")
        page.page.wait_for_timeout(20)
    return page.sent


@pytest.fixture(scope="module")
def swiftshader(pw):
    """Headless Chromium with WebGL on SwiftShader, not the tests' OpenGL (llvmpipe, the
    desktop renderer's): the page's frost is held to the desktop's across two rasterisers."""
    b = launch_browser(pw, "swiftshader")
    yield b
    b.close()


@pytest.fixture(scope="module", params=["glass", "paper"])
def grown(gl_ctx, request):
    """A frost of each look grown 120 ticks from three touches with a melt at tick 80:
    the desktop's frame of the page's messages, and the messages."""
    params = Params.preset("fern").replace(look=request.param)
    _off, deltas = grow(params, 3, 120, ctx=gl_ctx)
    messages = encode(deltas, params)
    return params, messages, desktop_frame(gl_ctx, params, wire_deltas(messages, params))


def webgl_renderer(page: Page) -> str:
    """What the page's WebGL says draws it (WEBGL_debug_renderer_info)."""
    return page.page.evaluate("""() => { const gl = document.createElement('canvas')
        .getContext('webgl2'); const d = gl.getExtension('WEBGL_debug_renderer_info');
        return gl.getParameter(d.UNMASKED_RENDERER_WEBGL); }""")


def page_source() -> str:
    """The text of every module of the page."""
    return "".join(path.read_text(encoding="utf-8") for path in sorted(WEB_DIR.glob("*.js")))


def test_the_page_takes_each_looks_defines_from_the_hello(browser):
    """The page keeps no copy of the desktop's #defines, material or light (frost serve's
    are sim.look.material's): each look's programs are built with the hello's, here other
    ones."""
    assert not re.search(r"\b(LOOK_DEFINES|FEATURE_DEFINES|MATERIAL|defaultLight)\b", page_source())
    params = Params.preset("fern")
    said = hello(params)
    assert set(said["defines"]) == set(LOOK_DEFINES) == set(FEATURE_DEFINES)
    defines = {look: {"ice": ["FILM"], "feature": []} for look in said["defines"]}
    with Page({**said, "defines": defines}, [], browser=browser) as page:
        got = page.page.evaluate("(r => [r.defines, r.features.defines])(frost.renderer)")
    by_pass = {part: {look: d[part] for look, d in defines.items()} for part in ("ice", "feature")}
    assert got == [by_pass, by_pass["feature"]]


def test_the_page_draws_with_the_tile_and_depth_of_the_hello(browser):
    """The page keeps no copy of the desktop's tile side and feature depth: it takes the
    hello's (frost serve's are sim.look.material's TILE and MAX_DEPTH), here other ones."""
    assert not re.search(r"\b(TILE|MAX_DEPTH)\b", page_source())
    params = Params.preset("fern")
    with Page({**hello(params), "tile": 32, "max_depth": 128.0}, [], browser=browser) as page:
        got = page.page.evaluate("(r => [r.tile, r.tiles.cols, r.tiles.rows, r.damage.cols,"
                                 " r.features.maxDepth])(frost.renderer)")
    assert got == [32, 24, 40, 24, 128]  # 760 / 32 = 23.75 and 1280 / 32 columns and rows


def test_the_page_takes_its_screen_from_the_hello(browser):
    """The page keeps no copy of the screen's size (frost serve's is sim.screen's SIZE): a
    hello's screen of 380x640 px, on a viewport of as many CSS px, is a renderer of that
    size, a pane that fills the canvas one px a px, and a click at CSS px (100, 200) is a
    touch at the pane's (100, 200) (a pane of 760x1280 would be shown at half its px)."""
    params = Params.preset("fern")
    said, s = hello(params), params.grid_spacing
    said = {**said, "screen": [380, 640], "grid": [380 // s + 1, 640 // s + 1]}
    with Page(said, [], viewport=(380, 640), scale=1, browser=browser) as page:
        p = page.page
        assert p.evaluate("frost.renderer.size") == [380, 640]
        assert p.evaluate("frost.canvasSize()") == [380, 640]
        assert p.evaluate("frost.pane()") == {"x": 0, "y": 0, "w": 380, "h": 640, "scale": 1}
        p.mouse.click(100, 200)
        sent = sent_until(page, lambda sent: any(m.get("phase") == "up" for m in sent), "the click's up")
    down = next(m for m in sent if m["phase"] == "down" and m["type"] == "touch")
    assert abs(down["x"] - 100) < 1 and abs(down["y"] - 200) < 1, down


def test_half_floats_as_numpy(browser):
    """Every half decodes as numpy does; numbers round to the nearest half (ties to even,
    subnormals, overflow) as numpy's astype(float16)."""
    rng = np.random.default_rng(5)
    bits = np.arange(1 << 16, dtype=np.uint16)
    halves = bits.view(np.float16).astype(np.float64)
    finite = np.isfinite(halves)
    # Ties and their neighbours, subnormals, the largest half and beyond, random values.
    mids = (halves[finite][:-1] + np.diff(halves[finite]) / 2)
    samples = np.concatenate([mids[::97], np.nextafter(mids[::89], 0), rng.normal(0, 30, 2000),
                              rng.uniform(-1e-6, 1e-6, 500), [65504, 65519.99, 65520, 1e6, -0.0]])
    samples = samples.astype(np.float32).astype(np.float64)
    with Page(hello(Params.preset("fern")), [], browser=browser) as page:
        out = page.page.evaluate("""async ([values]) => {
            const m = await import('./web/protocol.js');
            const dec = []; for (let h = 0; h < 65536; h++) dec.push(m.halfToFloat(h));
            return [dec, values.map(m.floatToHalf)]; }""", [samples.tolist()])
    decoded = np.array([np.nan if v is None else v for v in out[0]])
    assert np.array_equal(decoded[finite], halves[finite])
    with np.errstate(over="ignore"):
        expected = samples.astype(np.float16).view(np.uint16)
    assert np.array_equal(np.array(out[1], np.uint16), expected)


@pytest.mark.parametrize("read", ["typed", "view"])
def test_the_page_decodes_what_the_server_encodes(browser, grown, read):
    """Both ways the page reads a message (typed arrays on a little-endian machine with
    Float16Array, as here; a DataView on any other) give what decode_geometry gives, to
    the bit."""
    from app.serve.protocol import decode_geometry

    params, messages, _ = grown
    with Page(hello(params), messages, browser=browser) as page:
        assert page.page.evaluate("import('./web/protocol.js').then((p) => p.READ)") == "typed"
        for i in (0, 1, 40, len(messages) - 1, *(i for i, m in enumerate(messages) if m[2] & 2)):
            m = decode_geometry(messages[i])
            got = page.page.evaluate("""async ([bytes, read]) => {
                const p = await import('./web/protocol.js');
                const d = p.decodeDelta(new Uint8Array(bytes).buffer, read);
                return {...d, heights: Array.from(d.heights), features: Array.from(d.features)}; }""",
                                     [list(messages[i]), read])
            assert got["tick"] == m["tick"] and got["look"] == m["look"]
            assert got["reset"] == bool(m["flags"] & 1)
            assert got["clearBox"] == (list(m["clear_box"]) if m["clear_box"] else None)
            assert [tuple(r) for r in got["runs"]] == m["runs"]
            assert np.array_equal(np.array(got["heights"], np.float32), m["heights"])
            assert np.array_equal(np.array(got["features"], np.float32).reshape(-1, 6), m["vertices"])


def test_the_page_refuses_a_run_that_reaches_past_the_grid_as_the_server_does(browser):
    """A run that starts on the grid's last height and runs two long leaves the grid: the
    page refuses it, as decode_geometry does (the oracle); one ending on that height is
    taken."""
    from app.serve.protocol import _message, decode_geometry

    params = Params.preset("fern")
    cols, rows = hello(params)["grid"]
    cells = cols * rows
    bad, good = ((_message(0, "glass", 7, (cols, rows), 16.0, [run], np.ones(run[1], np.float16),
                           b"", None)) for run in ((cells - 1, 2), (cells - 2, 2)))
    with pytest.raises(ValueError, match="leaves the grid"):
        decode_geometry(bad)
    assert decode_geometry(good)["runs"] == [(cells - 2, 2)]
    with Page(hello(params), [], browser=browser) as page:
        got = page.page.evaluate("""async (messages) => {
            const p = await import('./web/protocol.js');
            return messages.map((bytes) => {
                try { return p.decodeDelta(new Uint8Array(bytes).buffer).runs; }
                catch (err) { return err instanceof p.ProtocolError ? 'refused' : String(err); } }); }""",
                                 [list(bad), list(good)])
    assert got == ["refused", [[cells - 2, 2]]]


def test_the_page_draws_the_frost_as_the_desktop_does(swiftshader, grown):
    """The page's frame of the messages against the desktop renderer's frame of the same
    messages: only the two rasterisers differ (SwiftShader, llvmpipe)."""
    params, messages, desktop = grown
    with Page(hello(params), messages, browser=swiftshader) as page:
        assert "SwiftShader" in webgl_renderer(page)
        shown = page.pixels()
    with Page(hello(params), [], browser=swiftshader) as page:
        bare = page.pixels()
    assert compare(desktop, bare)["within8"] < 0.97  # the frost is there to compare
    got = compare(desktop, shown)
    assert got["mad"] < 0.1 and got["within8"] > 0.9995, got


def test_the_height_texture_holds_heights_and_slopes_as_numpy(browser, grown):
    """After every message, the page's height texture (its mirror) holds each vertex's
    height and numpy.gradient's slopes of the grid the messages give (app.serve.protocol's
    apply_geometry), as half floats: the rows each message touched and their neighbours
    were rewritten."""
    from app.serve.protocol import apply_geometry, decode_geometry

    params, messages, _ = grown
    cols, rows = hello(params)["grid"]
    grid = np.zeros(rows * cols, np.float32)
    for m in messages:
        apply_geometry(grid, decode_geometry(m))
    gy, gx = np.gradient(grid.reshape(rows, cols), float(params.grid_spacing))
    want = np.stack((grid.reshape(rows, cols), gx, gy), axis=-1).astype(np.float16)
    with Page(hello(params), messages, browser=browser) as page:
        texels = page.page.evaluate("Array.from(frost.renderer.heights.texels)")
        # The same rows worked out again by the page's own floatToHalf (a browser without
        # Float16Array), from a texture emptied first.
        fallback = page.page.evaluate("""() => { const r = frost.renderer.heights;
            const had = !!r.halves;
            r.halves = null;
            r.texels.fill(0);
            r.uploadRows(0, r.gridSize[1]);
            return [had, Array.from(r.texels)]; }""")
    assert fallback[0]  # (this Chromium has Float16Array: the first texels are its)
    assert np.abs(want).max() > 0.1
    for values in (texels, fallback[1]):
        got = np.array(values, np.uint16).view(np.float16).reshape(rows, cols, 3)
        assert np.array_equal(got, want)


def test_a_page_reconnects_and_holds_what_the_new_connection_gives(browser, grown):
    """The socket closes after the whole frost is drawn; the page reconnects (after its
    backoff) and the new connection's hello and messages (half the frost) replace what it
    held."""
    params, messages, _ = grown
    half = messages[:len(messages) // 2]
    with Page(hello(params), half, browser=browser) as page:
        want = page.pixels()
    with Page(hello(params), messages, browser=browser, later=[half], hang_up=False) as page:
        assert not np.array_equal(page.pixels(), want)  # the whole frost
        page.socket.close(code=1001, reason="going away")
        total = len(messages) + len(half) + 2  # and two hellos
        # (each applied as it comes: pixels() draws the pane as it is, no frame waited for)
        page.page.wait_for_function(f"frost.hellos === 2 && frost.messages === {total}")
        assert np.array_equal(page.pixels(), want)


def test_a_page_that_reconnects_shows_its_frost_until_the_new_snapshot_comes(browser, grown):
    """A hello always comes before a snapshot: from it until the snapshot is in, the page
    draws nothing, so the screen keeps the frost it had (not clear glass between the two),
    then shows the new connection's."""
    params, messages, _ = grown
    with Page(hello(params), messages, browser=browser, later=[[]], hang_up=False) as page:
        p = page.page
        p.wait_for_function("frost.frames > 1 && !frost.blitDamage")
        before = p.screenshot()
        page.socket.close(code=1001, reason="going away")
        p.wait_for_function("frost.hellos === 2 && frost.connected")
        p.evaluate("new Promise((done) => { let n = 0; const f = () => ++n < 10 ? "
                   "requestAnimationFrame(f) : done(); requestAnimationFrame(f); })")
        assert p.evaluate("[frost.midSnapshot, frost.synced]") == [True, False]
        assert p.screenshot() == before
        page.socket.send(messages[0])  # (the frost's first tick: a reset, then its ice)
        p.wait_for_function("!frost.midSnapshot && frost.frames > 0 && !frost.blitDamage")
        p.evaluate("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
        assert p.screenshot() != before


def test_on_the_same_rasteriser_the_page_draws_the_desktops_pixels(pw, grown, gl_ctx,
                                                                    monkeypatch):
    """Chromium's WebGL on the system's OpenGL (ANGLE over EGL: Mesa's llvmpipe, the
    desktop renderer's rasteriser here): the page's frame is the desktop's, bit for bit,
    the shaders compiled in the page's dialect, GLSL ES 3.00 (the desktop's own, 3.30 core,
    differs by 1-2 / 255 on under 1 % of the pixels: tests/test_look.py)."""
    params, messages, _desktop = grown
    monkeypatch.setattr(shaders, "DESKTOP", "es")
    desktop = desktop_frame(gl_ctx, params, wire_deltas(messages, params))
    b = launch_browser(pw, "gl-egl")
    try:
        with Page(hello(params), messages, browser=b) as page:
            renderer = webgl_renderer(page)
            if "llvmpipe" not in renderer:
                pytest.skip(f"Chromium's OpenGL is not llvmpipe here: {renderer}")
            shown = page.pixels()
    finally:
        b.close()
    assert np.array_equal(shown, desktop), compare(shown, desktop)


def test_a_lost_gpu_context_comes_back_with_the_frost(browser, grown):
    """The context lost (a phone took the GPU away) and restored: the page reconnects
    and draws the frost of the new connection's snapshot as before."""
    params, messages, _ = grown
    with Page(hello(params), messages, browser=browser, later=[messages], hang_up=False) as page:
        before, p = page.pixels(), page.page
        shown = p.screenshot()
        p.evaluate("window.lose = document.getElementById('frost').getContext('webgl2')"
                   ".getExtension('WEBGL_lose_context'); lose.loseContext()")
        p.wait_for_function("frost.lost === 1")
        p.evaluate("lose.restoreContext()")
        p.wait_for_function(f"frost.hellos === 2 && frost.messages === {2 * len(messages) + 2}"
                            " && frost.shownBackdrop === 'dusk'")
        p.wait_for_function("frost.frames > 0 && !frost.dirty")
        assert np.array_equal(page.pixels(), before)
        assert p.screenshot() == shown  # and on the screen


def test_drawing_only_what_changed_gives_the_whole_frames_pixels(browser, grown):
    """Each message applied and only its damage drawn (in the pane's texture, then on the
    canvas): the same pixels as the whole frame drawn again."""
    import base64

    from app.serve.protocol import Encoder, decode_geometry
    from sim.look.geometry import GeometryDelta

    params, messages, _ = grown
    # Then features alone (no height changes), shifted onto clear glass, and a wipe alone.
    cols, rows = hello(params)["grid"]
    feats = max((decode_geometry(m)["vertices"] for m in messages), key=len).copy()
    feats[:, 0] = np.clip(feats[:, 0] + 150, 0, 759)
    none = np.zeros((0, cols), np.float32)
    enc = Encoder(cols, rows)
    box = (feats[:, 0].min(), feats[:, 1].min(), feats[:, 0].mean(), feats[:, 1].mean())
    messages = [*messages, enc.delta(GeometryDelta(1, slice(0, 0), none, feats, look=params.look)),
                enc.delta(GeometryDelta(2, slice(0, 0), none, feats[:0], look=params.look,
                                        clear_box=tuple(map(float, box))))]
    with Page(hello(params), [], browser=browser) as page:
        p = page.page
        differ = p.evaluate("""async (msgs) => {
            const proto = await import('./web/protocol.js');
            const r = frost.renderer;
            for (const b64 of msgs) {
              const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
              r.apply(proto.decodeDelta(bytes.buffer));
              r.render();
            }
            const partial = r.readFrame();
            r.render(true);
            const whole = r.readFrame();
            let n = 0;
            for (let i = 0; i < whole.length; i++) n += partial[i] !== whole[i];
            return n; }""", [base64.b64encode(m).decode() for m in messages])
        assert differ == 0
    with Page(hello(params), messages, browser=browser, viewport=(390, 844), scale=3) as page:
        p = page.page
        p.wait_for_function("frost.frames > 1 && !frost.blitDamage")
        parts = p.screenshot()
        p.evaluate("frost.dirty = true")
        p.wait_for_function("!frost.dirty")
        assert p.screenshot() == parts


def test_what_the_screen_does_not_show_is_drawn_when_it_does(browser, grown):
    """With a view (the part of the pane a phone's screen shows), a frame draws the tiles
    it touches, each as the whole frame has it, and nothing else; the changes outside wait
    and are drawn once the view takes them in."""
    from sim.look.material import TILE

    params, messages, _ = grown
    view = [200, 300, 470, 650]
    with Page(hello(params), messages, browser=browser) as page:
        got = page.page.evaluate("""(view) => {
            const r = frost.renderer, gl = r.gl;
            r.render(true);
            const whole = r.readFrame();
            const mark = () => {  // the frame's texture all magenta
              gl.bindFramebuffer(gl.FRAMEBUFFER, r.frameFbo);
              gl.clearColor(1, 0, 1, 1);
              gl.clear(gl.COLOR_BUFFER_BIT);
              gl.bindFramebuffer(gl.FRAMEBUFFER, null);
            };
            mark();
            r.damageAll();
            const box = r.render(false, view);
            const seen = r.readFrame();
            const again = r.render(false, view);  // (nothing left there)
            const rest = r.render(false, [0, 0, 760, 1280]);
            const all = r.readFrame();
            mark();
            r.damageAll();
            r.render(false, [-50, -50, 900, 1400]);  // (a view past the pane: all of it)
            const over = r.readFrame();
            const b64 = (a) => btoa(Array.from(a, (c) => String.fromCharCode(c)).join(""));
            return { whole: b64(whole), seen: b64(seen), all: b64(all), over: b64(over),
                     box, again, rest }; }""", view)
    import base64

    def image(key):
        return np.frombuffer(base64.b64decode(got[key]), np.uint8).reshape(1280, 760, 4)

    whole, seen = image("whole"), image("seen")
    tx0, ty0 = view[0] // TILE * TILE, view[1] // TILE * TILE
    tx1, ty1 = -(-view[2] // TILE) * TILE, -(-view[3] // TILE) * TILE
    inside = np.zeros((1280, 760), bool)
    inside[ty0:ty1, tx0:tx1] = True
    assert got["box"] == [tx0, ty0, tx1, ty1]
    assert np.array_equal(seen[inside], whole[inside])
    assert (seen[~inside] == [255, 0, 255, 255]).all()
    assert got["again"] is None
    assert got["rest"] == [0, 0, 760, 1280]
    assert np.array_equal(image("all"), whole)
    assert np.array_equal(image("over"), whole)
    assert whole[inside].std() > 0  # (the frost is in the view)


def shown_span(offset: float, scale: float, screen: int, size: int) -> list[int]:
    """The pane px [first, end) any part of which lies on a screen `screen` px long, the
    pane starting at `offset` with `scale` screen px to each of its px: each one tried."""
    shown = [c for c in range(size) if offset + (c + 1) * scale > 0 and offset + c * scale < screen]
    return [shown[0], shown[-1] + 1]


def test_the_visible_part_of_the_pane_holds_every_pane_px_the_screen_shows(browser):
    """At any scale, the visible part (what a frame draws) reaches every pane px a screen px
    falls on, a cut one at each edge included, and no px the screen does not show."""
    screens = [(1170, 2532, "fill"), (1080, 2400, "fill"), (2400, 1080, "fill"), (1000, 1000, "fill"),
               (1170, 2532, "pane"), (591, 1280, "fill"), (333, 777, "fill")]
    with Page(hello(Params.preset("fern")), [], browser=browser) as page:
        got = page.page.evaluate("""async (screens) => {
            const f = await import('./web/fit.js');
            return screens.map(([w, h, fit]) => {
              const rect = f.paneRect(w, h, fit);
              return [rect, f.visiblePane(rect, w, h)]; }); }""", screens)
    for (w, h, fit), (rect, view) in zip(screens, got, strict=True):
        x0, x1 = shown_span(rect["x"], rect["scale"], w, 760)
        y0, y1 = shown_span(rect["y"], rect["scale"], h, 1280)
        assert view == [x0, y0, x1, y1], (w, h, fit)


def test_the_programs_warmed_while_a_snapshot_comes_leave_no_trace(swiftshader, grown):
    """Between the hello and its snapshot the page runs each program of the hello's look
    once (SwiftShader builds a program's code at its first draw), on a px it then wipes: the
    frost drawn after is the same, px for px, as a page's that never waited."""
    params, messages, _ = grown
    with Page(hello(params), messages, browser=swiftshader) as page:
        want = page.pixels()
    with Page(hello(params), [], browser=swiftshader, hang_up=False) as page:
        p = page.page
        p.wait_for_function("frost.warm === null")
        assert p.evaluate("Object.keys(frost.renderer.iceProgs)") == [params.look]
        corner = p.evaluate("""() => {  // the features' texture where the warming drew
            const r = frost.renderer, gl = r.gl, out = new Uint8Array(8 * 8 * 4);
            gl.bindFramebuffer(gl.FRAMEBUFFER, r.features.fbo);
            gl.readPixels(0, r.size[1] - 8, 8, 8, gl.RGBA, gl.UNSIGNED_BYTE, out);
            gl.bindFramebuffer(gl.FRAMEBUFFER, null);
            return Array.from(out); }""")
        assert not any(corner)
        for m in messages:
            page.socket.send(m)
        p.wait_for_function(f"frost.messages === {len(messages) + 1} && frost.frames > 1"
                            " && !frost.blitDamage")
        got = page.pixels()
    assert np.array_equal(got, want)


def test_a_snapshots_features_alone_are_drawn(browser):
    """A snapshot of features on clear glass (no height anywhere): each triangle's tiles
    hold ice, so the ice pass draws it (everything is damaged by the snapshot's reset, but
    only the tiles known to hold ice are drawn)."""
    from app.serve import protocol
    from sim.look.geometry import feature_scale

    params = Params.preset("fern")
    cols, rows = hello(params)["grid"]
    heights = np.zeros(cols * rows, np.float16)
    feats = np.array([[300, 900, 4.0, 0.3, 0, 0.95], [340, 900, 4.0, 0.3, 0, 0.95],
                      [300, 940, 4.0, 0.3, 0, 0.95]], np.float32)
    enc = protocol.Encoder(cols, rows)
    with Page(hello(params), enc.snapshot(7, feats, params.look, feature_scale(params),
                                          heights=heights), browser=browser) as page:
        shown = page.pixels()
    with Page(hello(params), enc.snapshot(7, feats[:0], params.look, feature_scale(params),
                                          heights=heights), browser=browser) as page:
        bare = page.pixels()
    inside = (slice(902, 915), slice(302, 315))  # (y, x): well inside the triangle
    assert (np.abs(shown[inside].astype(int) - bare[inside]).sum(axis=-1) > 8).all()
    assert np.array_equal(shown[:800], bare[:800])  # (and nothing else changed)


def test_the_pages_metadata_json_reads_back_as_pythons_would_write_it(browser):
    """The screenshot's JSON (png.js pyJson) as Python's json.dumps writes it (the oracle):
    whole numbers as ints, other numbers as floats, a negative zero (a light's component)
    still a float, never the int 0."""
    values = {"light": [0.5, -1.25, 3], "n": 7, "name": "é"}
    with Page(hello(Params.preset("fern")), [], browser=browser) as page:
        written, zero = page.page.evaluate("""async ([values]) => {
            const m = await import('./web/png.js');
            return [m.pyJson(values), m.pyJson({zero: -0, list: [-0, 1]})]; }""", [values])
        floats = [1e-7, 1.5e-7, 1e-6, 1e-5, 0.0001, 0.000123, 123.456, 2.5e15 + 0.5, 1.5e-300,
                  -3.25e-9, 0.1 + 0.2, 1 / 3, 5e-324, 1.7976931348623157e308]
        spelled = page.page.evaluate("""async ([xs]) => {
            const m = await import('./web/png.js'); return m.pyJson(xs); }""", [floats])
    assert written == json.dumps(values)
    assert zero == json.dumps({"zero": -0.0, "list": [-0.0, 1]})
    assert spelled == json.dumps(floats)  # Python's repr of each (none whole: a whole one is an int)


def test_screenshot_png_carries_the_desktops_keys(browser, grown):
    from app.images import frost_meta

    params, messages, _ = grown
    meta = {"parameters": params.as_dict(), "seed": 3, "touches": [[0, 380.0, 640.0]]}
    with Page(hello(params), messages, browser=browser, meta=meta) as page:
        png = bytes(page.page.evaluate("async () => Array.from(await frost.screenshotPng())"))
        shown = page.pixels()
    with Image.open(io.BytesIO(png)) as im:
        text = dict(im.text)
        pixels = np.asarray(im.convert("RGB"))
    desktop_keys = set(frost_meta("x", params, 0, 0, [], view={}))
    assert set(text) == desktop_keys
    assert json.loads(text["tick"]) == 120 and json.loads(text["seed"]) == 3
    assert json.loads(text["parameters"]) == params.as_dict()
    assert json.loads(text["touches"]) == [[0, 380.0, 640.0]]
    assert json.loads(text["view"])["background"] == "dusk"
    assert np.array_equal(pixels, shown)


def test_fingers_become_touches_and_melts_in_screen_px(browser):
    """A phone (390x844 CSS px, 3 device px each): the pane covers the screen (cropped left
    and right), its canvas holding a px for each pane px the screen shows (not 3 a CSS px:
    the pane has no more to show); a tap sends a touch at the pane's px under it, a second
    finger melts, a drag sends moves, each finger its own id."""
    params = Params.preset("fern")
    with Page(hello(params), [], viewport=(390, 844), scale=3, browser=browser, touch=True) as page:
        size = page.page.evaluate("[frost.canvasSize(), frost.pane()]")
        # A pane px covers 844 / 1280 CSS px (the height fills the screen): 1280 canvas px
        # high, 390 * 1280 / 844 = 591.5 wide, to the nearest even 592 (the crop the same
        # each side); the pane 760 wide, cropped 84 each side.
        assert size[0] == [592, 1280]
        pane = size[1]
        assert pane["h"] == 1280 and pane["w"] == 760 and pane["scale"] == 1
        assert pane["y"] == 0 and pane["x"] == (592 - 760) // 2 == -84
        # CSS px of pane px (x, y): the canvas stretched over 390 x 844 CSS px.
        css = lambda x, y: ((pane["x"] + x) * 390 / 592, y * 844 / 1280)  # noqa: E731
        cdp = page.context.new_cdp_session(page.page)

        def touch(kind, points):
            cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": [
                {"x": x, "y": y, "id": i} for i, (x, y) in points]})

        touch("touchStart", [(1, css(380, 640))])
        touch("touchStart", [(1, css(380, 640)), (2, css(100, 200))])
        touch("touchMove", [(1, css(390, 650)), (2, css(110, 220))])
        page.page.wait_for_timeout(100)
        touch("touchEnd", [])
        sent = sent_until(page, lambda sent: sum(m["phase"] == "up" for m in sent) >= 2, "both ups")
    kinds = [(m["type"], m["phase"], m["id"]) for m in sent]
    assert kinds[:2] == [("touch", "down", 0), ("melt", "down", 1)]
    assert ("touch", "move", 0) in kinds and ("melt", "move", 1) in kinds
    assert {("touch", "up", 0), ("melt", "up", 1)} <= set(kinds)
    down = sent[0]
    assert abs(down["x"] - 380) < 0.5 and abs(down["y"] - 640) < 0.5
    melt = sent[1]
    assert abs(melt["x"] - 100) < 0.5 and abs(melt["y"] - 200) < 0.5
    move = next(m for m in sent if m["phase"] == "move" and m["id"] == 0)
    assert abs(move["x"] - 390) < 0.5 and abs(move["y"] - 650) < 0.5


def test_a_click_on_a_landscape_screen_lands_on_the_pane_under_it(browser):
    """A landscape window (a desktop browser, a phone turned) with the menu's "whole pane"
    remembered: the pane is letterboxed left and right, so the pane's x offset counts; a
    click at the pane's px (100, 200) and a right button's drag send those px."""
    params = Params.preset("fern")
    with Page(hello(params), [], viewport=(1280, 720), scale=1, browser=browser,
              init="localStorage.setItem('frost.fit', 'pane')") as page:
        # The pane shown smaller than its px (720 / 1280): the canvas keeps the screen's px.
        assert page.page.evaluate("frost.canvasSize()") == [1280, 720]
        pane = page.page.evaluate("frost.pane()")
        assert pane["y"] == 0 and pane["x"] == (1280 - pane["w"]) // 2 > 300
        css = lambda x, y: (pane["x"] + x * pane["scale"], pane["y"] + y * pane["scale"])  # noqa: E731
        mouse = page.page.mouse
        mouse.click(*css(100, 200))
        mouse.move(*css(700, 1200))
        mouse.down(button="right")
        mouse.move(*css(650, 1100))
        page.page.wait_for_timeout(100)
        mouse.up(button="right")
        sent = sent_until(page, lambda sent: any(m["phase"] == "up" and m["type"] == "melt" for m in sent),
                          "the melt's up")
    down = next(m for m in sent if m["phase"] == "down" and m["type"] == "touch")
    assert abs(down["x"] - 100) < 1 and abs(down["y"] - 200) < 1, down
    melt = next(m for m in sent if m["phase"] == "down" and m["type"] == "melt")
    assert abs(melt["x"] - 700) < 1 and abs(melt["y"] - 1200) < 1, melt
    move = next(m for m in sent if m["phase"] == "move" and m["type"] == "melt")
    assert abs(move["x"] - 650) < 1 and abs(move["y"] - 1100) < 1, move


def test_a_tap_by_each_corner_is_the_panes_and_the_menus_round_button_alone_is_the_menus(browser):
    """A 390x844 phone at 1 device px a CSS px: a tap 10 px in from each corner of the
    screen is a touch at the pane px under it (the top right one fell in the menu button's
    40x40 square, outside its round button, and reached nothing); a tap on the button
    opens the menu and is no touch."""
    params = Params.preset("fern")
    with Page(hello(params), [], viewport=(390, 844), scale=1, browser=browser, touch=True) as page:
        p = page.page
        corners = [(10, 10), (380, 10), (10, 834), (380, 834)]
        for x, y in corners:
            p.touchscreen.tap(x, y)
        button = p.locator("#open").bounding_box()
        p.touchscreen.tap(button["x"] + button["width"] / 2, button["y"] + button["height"] / 2)
        p.wait_for_selector("#panel", state="visible")
        p.touchscreen.tap(*corners[0])  # the first corner again, the menu open
        ups = lambda: sum(m["phase"] == "up" for m in page.sent)  # noqa: E731
        for _ in range(300):  # (the socket's messages reach `sent` as Playwright runs)
            if ups() >= 5:
                break
            p.wait_for_timeout(100)
        downs = page.sent
    # The pane covers the screen: a pane px is 844 / 1280 CSS px (the height fills it), and
    # the pane, 760 * 844 / 1280 = 501.1 CSS px wide, is centred (55.6 px cropped each side).
    scale = 844 / 1280
    x0 = (390 - 760 * scale) / 2
    got = [(m["x"], m["y"]) for m in downs if m["type"] == "touch" and m["phase"] == "down"]
    assert len(got) == 5, downs
    for (x, y), (gx, gy) in zip([*corners, corners[0]], got, strict=True):
        # (within a pane px: the canvas's pane is centred to the whole px)
        assert abs(gx - (x - x0) / scale) <= 1 and abs(gy - y / scale) <= 1, ((x, y), (gx, gy))


def test_a_finger_lifted_before_a_frame_sends_its_last_move_and_one_off_the_pane_its_edge(browser):
    """Moves go out once a frame, but a finger lifted before the next frame still sends
    where it went before its up; a finger dragged past the pane's right edge (onto the
    black beside it) moves to the edge's last px, not nowhere."""
    params = Params.preset("fern")
    with Page(hello(params), [], viewport=(1280, 720), scale=1, browser=browser) as page:
        p = page.page
        # Covering 1280 CSS px with 760 pane px: a canvas px a pane px, 760 x 720 * 760 /
        # 1280 = 427.5 (the nearest even: 428), stretched over the screen.
        assert p.evaluate("frost.canvasSize()") == [760, 428]
        pane = p.evaluate("frost.paneCss()")
        css = lambda x, y: (pane["x"] + x * pane["sx"], pane["y"] + y * pane["sy"])  # noqa: E731
        p.evaluate("""([events]) => {
            const c = document.getElementById('frost');
            for (const [type, id, x, y] of events) {
                c.dispatchEvent(new PointerEvent(type, {clientX: x, clientY: y, pointerId: id,
                    button: 0, bubbles: true, cancelable: true}));
            } }""", [[["pointerdown", 7, *css(100, 200)], ["pointermove", 7, *css(300, 400)],
                      ["pointerup", 7, *css(300, 400)]]])  # one task: no frame between them
        p.wait_for_timeout(100)
        mouse = p.mouse
        mouse.move(*css(700, 600))
        mouse.down()
        mouse.move(pane["x"] + pane["w"] + 100, css(700, 600)[1])  # beside the pane
        p.wait_for_timeout(100)
        mouse.up()
        sent = sent_until(page, lambda sent: sum(m["phase"] == "up" for m in sent) >= 2, "both ups")
    first = [(m["phase"], round(m.get("x", -1)), round(m.get("y", -1))) for m in sent[:3]]
    assert first == [("down", 100, 200), ("move", 300, 400), ("up", -1, -1)], sent[:3]
    edge = [m for m in sent[3:] if m["phase"] == "move"]
    assert edge and all(759.9 < m["x"] < 760 and abs(m["y"] - 600) < 1 for m in edge), edge


def test_a_tap_is_timed_to_its_first_drawn_frost_and_growth(browser):
    """After a tap, a delta with ice or a ridge far from it counts for nothing; ice within
    12 px of it, however thin or thick, is its first frost (frost.frostLatencies) but not
    growth; a ridge there (a link frozen onto the seed) is its growth (frost.latencies).
    Each is timed once, at the frame that draws it."""
    from app.serve.protocol import Encoder
    from sim.look.geometry import GeometryDelta

    params = Params.preset("fern")
    cols, rows = hello(params)["grid"]
    s = params.grid_spacing
    enc = Encoder(cols, rows)

    def ice(tick, x, y, h, ridge=None):  # the grid vertex nearest (x, y) raised to h px
        r, c = round(y / s), round(x / s)
        row = enc.heights.reshape(rows, cols)[r].astype(np.float32)
        row[c] = h
        feats = np.zeros((0, 6), np.float32)
        if ridge is not None:  # a triangle of a ridge with a corner at `ridge`
            rx, ry = ridge
            feats = np.array([[rx, ry, 0.5, 0, 0, 1], [rx + 7, ry, 0.5, 0, 0, 1],
                              [rx, ry + 1, 0.0, 0, 0, 1]], np.float32)
        return enc.delta(GeometryDelta(tick, slice(r, r + 1), row[None, :], feats,
                                       look=params.look))

    with Page(hello(params), [], viewport=(390, 844), scale=3, browser=browser, touch=True) as page:
        p = page.page
        pane = p.evaluate("frost.paneCss()")
        p.touchscreen.tap(pane["x"] + 380 * pane["sx"], pane["y"] + 640 * pane["sy"])
        p.wait_for_function("frost.watch !== null")
        counts = "[frost.frostLatencies.length, frost.latencies.length]"
        for tick, (x, y, h), ridge, want in (
                (1, (380, 400, 2.0), (380, 420), [0, 0]),  # far from the tap
                (2, (384, 644, 0.5), None, [1, 0]),  # thin ice there: its frost
                (3, (376, 636, 3.0), None, [1, 0]),  # thick ice there: not yet growth
                (4, (380, 400, 0.0), (385, 646), [1, 1])):  # a ridge there: growth
            frames = p.evaluate("frost.frames")
            page.socket.send(ice(tick, x, y, h, ridge))
            # the frame that draws it (a tap's latency is taken in that same frame): not a
            # wait of a frame's usual time, which a loaded machine overran
            p.wait_for_function(f"frost.tick === {tick} && frost.frames > {frames}")
            assert p.evaluate(counts) == want, (tick, want)
        assert p.evaluate("frost.watch") is None


def test_a_frame_that_throws_is_said_once_and_the_next_frame_still_runs(browser):
    """A bad value set on `frost` (its phone part taken away: each frame's tilt step then
    throws) stopped every frame after the first, for good. Now each frame fails alike and
    is counted, the reason is logged once and said in the status line, and once the value
    is put back the next frame draws and the status line is clear again."""
    params = Params.preset("fern")
    with Page(hello(params), [], browser=browser) as page:
        p = page.page
        errors: list[str] = []
        p.on("console", lambda m: m.type == "error" and errors.append(m.text))
        p.evaluate("window.kept = frost.phone; frost.phone = null")
        p.wait_for_function("frost.frameErrors >= 10")  # frame after frame, each failing
        reason = p.evaluate("frost.frameError")
        assert "null" in reason and "frame" in reason, reason  # the TypeError's own words
        assert p.evaluate("document.getElementById('status').textContent") == f"a frame failed: {reason}"
        p.evaluate("null")  # (the console's messages reach Python as Playwright runs)
        assert len(errors) == 1 and errors[0].startswith(f"frost: a frame failed: {reason}"), errors
        frames = p.evaluate("frost.frames")
        p.evaluate("frost.phone = window.kept; frost.dirty = true")
        p.wait_for_function(f"frost.frames > {frames}")
        assert p.evaluate("[frost.frameError, document.getElementById('status').textContent]") == [None, ""]


def test_keys_and_the_menu_go_to_the_server(browser):
    """Keys by their GLFW names (S takes a screenshot on the page instead); the menu's
    choices as their messages; the menu shows the server's state."""
    params = Params.preset("fern")
    state = {**hello(params), "presets": ["fern", "c-3"], "preset": "fern",
             "backdrops": ["dusk", "lockscreen"], "paused": True}
    with Page(state, [], browser=browser) as page:
        p = page.page
        for key in ("Space", "c", "3", "BracketRight", "ArrowLeft", "s", "Shift"):
            p.keyboard.press(key)
        assert p.input_value("#preset") == "fern" and p.inner_text("#pause") == "Resume"
        p.click("#open")
        p.select_option("#preset", "c-3")
        p.select_option("#look", "paper")
        p.select_option("#backdrop", "lockscreen")
        for button in ("#pause", "#clear"):
            p.click(button)
        sent_until(page, lambda sent: len(sent) >= 10, "the keys and the menu's five")
        # A refusal (a notice): the menu goes back to what is in force, and says why.
        page.socket.send(json.dumps({"type": "notice", "text": "no such preset"}))
        p.wait_for_function("document.getElementById('status').textContent === 'no such preset'")
        assert p.input_value("#preset") == "fern"
    assert page.sent == [{"type": "key", "key": k} for k in ("SPACE", "C", "3", "RIGHT_BRACKET", "LEFT")] + [
        {"type": "preset", "name": "c-3"}, {"type": "look", "name": "paper"},
        {"type": "backdrop", "name": "lockscreen"}, {"type": "pause"}, {"type": "clear"}]


def test_keys_reach_the_frost_again_once_the_menu_is_closed(browser):
    """A keyboard user opens the menu, picks something, closes it: the keys that follow
    (Space, 3) go to the server, not to the menu's button left focused (where Space would
    open the menu again)."""
    params = Params.preset("fern")
    state = {**hello(params), "presets": ["fern", "c-3"], "preset": "fern",
             "backdrops": ["dusk", "lockscreen"]}
    with Page(state, [], browser=browser) as page:
        p = page.page
        p.click("#open")
        p.click("#pause")
        p.click("#open")
        for key in ("Space", "3"):
            p.keyboard.press(key)
        sent_until(page, lambda sent: len(sent) >= 3, "the pause and two keys")
        assert p.is_hidden("#panel")
    assert page.sent == [{"type": "pause"}, {"type": "key", "key": "SPACE"},
                         {"type": "key", "key": "3"}]


def test_a_snapshot_is_drawn_once_whole_not_part_by_part(browser, monkeypatch):
    """A snapshot comes in parts (a frosted pane's in three): the page draws no frame
    while one is under way, so nobody sees half a frost (and a slow phone spends no whole
    pane's draw on it); the last part's frame draws all of it."""
    from app.serve import protocol
    from sim.look.geometry import feature_scale

    monkeypatch.setattr(protocol, "PART_VERTICES", 3)  # a part a triangle
    params = Params.preset("fern")
    cols, rows = hello(params)["grid"]
    heights = np.zeros(cols * rows, np.float16)
    heights[rows // 2 * cols:rows // 2 * cols + cols] = 3.0  # a ridge of ice across the pane
    feats = np.array([[x, y, 1.0, 0, 0, 1] for x0 in (100, 300, 500)
                      for x, y in ((x0, 600), (x0 + 40, 600), (x0, 640))], np.float32)
    parts = protocol.Encoder(cols, rows).snapshot(7, feats, params.look, feature_scale(params),
                                                  heights=heights)
    assert [p[2] for p in parts] == [1 | 4, 4, 4 | 8]
    with Page(hello(params), [], browser=browser) as page:
        p = page.page
        ten_frames = ("new Promise((done) => { let n = 0; const f = () => ++n < 10 ? "
                      "requestAnimationFrame(f) : done(); requestAnimationFrame(f); })")
        p.evaluate(ten_frames)  # (what the backdrop asked drawn)
        frames = p.evaluate("frost.frames")
        for part in parts[:2]:
            page.socket.send(part)
        p.wait_for_function(f"frost.messages === {1 + 2}")
        p.evaluate(ten_frames)
        assert p.evaluate("[frost.frames, frost.synced]") == [frames, False]
        page.socket.send(parts[2])
        p.wait_for_function(f"frost.synced && frost.frames > {frames}")
        shown = page.pixels()
    with Page(hello(params), parts, browser=browser) as whole:
        assert np.array_equal(shown, whole.pixels())
    assert shown.std() > 0  # (not a blank pane)


def test_the_snapshot_work_bench_times_each_step_of_a_late_joins_snapshot(swiftshader, capsys):
    """`python -m bench page --snapshot-work N` grows the window pane, gives the page its
    snapshot N times and prints a median and p99 for each step, the landscape phone's the
    rows its screen shows."""
    from bench.page import snapshot_work

    # (in the tests' browser: a second Playwright beside it would refuse to start)
    assert snapshot_work(2, 40, "swiftshader", browser=swiftshader) == 0
    out = capsys.readouterr().out
    assert "window, glass, tick 40: a snapshot of" in out
    for step in ("applied", "its features rasterized", "the whole pane drawn",
                 "portrait 390x844 phone shows drawn (pane px 84-677 x 0-1280)",
                 "landscape 844x390 phone shows drawn (pane px 0-760 x 464-816)"):
        assert re.search(re.escape(step) + r".*: median \d+\.\d ms, p99 \d+\.\d ms", out), step
