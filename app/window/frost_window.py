"""The interactive phone window: GLFW, click-to-seed, keyboard tuning, HUD, screenshots.

Each frame the main thread drains every snapshot of the simulation thread, applies the
geometry deltas in order, renders the phone into an offscreen 760x1280 framebuffer when
it changed, and draws that letterboxed into the window with the HUD on top. Only this
thread calls GL.
"""

from __future__ import annotations

import contextlib
import json
import logging
import math
import signal
import time
from pathlib import Path

import glfw
import moderngl

from app.gl.renderer import Renderer
from app.gl.shaders import load_program
from app.images import read_image, save_png, timestamped_path
from app.simthread.thread import SimThread, Snapshot, Stats
from app.window.hud import Hud
from app.window.keys import help_lines, key_table
from app.window.record import Recorder
from app.window.view import PHONE, cursor_to_phone, fit_scale, letterbox
from sim import Params, preset_name
from sim.files import why
from sim.gestures import DRAG_SPACING_HC, MELT_SPACING, path_points

from . import tuning

log = logging.getLogger("app.window")

TITLE = "frost"
HUD_PERIOD = 0.25  # s between HUD stats refreshes
LOG_PERIOD = 2.0  # s between stats lines in the log
IDLE_WAIT = 0.1  # s to wait for events while minimized or idle
MESSAGE_SECONDS = 4.0
BACKDROP = (0.08, 0.08, 0.09)  # the letterbox bars
# Actions that repeat while their key is held.
REPEATING = {"single_step", "scale", "shift", "light"}
# What the two click latencies of the log measure: the first frame showing the seed's
# frost, and the first frame showing a crystal that froze onto that seed.
HELP = help_lines("\t")  # the help overlay, key and description in two columns
LATENCY_NOTES = {"frost": "seed shown", "growth": "first crystal frozen onto the seed"}
MAX_LIGHT_TILT = 0.95  # |xy| of the unit light vector: it never grazes the glass
RECORD_CATCHUP = 4  # ticks a slow frame may still add to a recording


class WindowError(RuntimeError):
    pass


def display_problem() -> str | None:
    """None when GLFW can reach the display; else why not (e.g. DISPLAY=:99 with no X
    server there). On success GLFW stays initialized for the window: disconnecting the
    only client would make a bare X server (Xvfb) reset, and a connection made during the
    reset fails."""
    errors: list[str] = []
    glfw.set_error_callback(lambda code, text: errors.append(_text(text)))
    ok = glfw.init()
    glfw.set_error_callback(None)
    return None if ok else "; ".join(errors) or "GLFW could not start"


def open_window(scale: float | None) -> tuple:
    """A GLFW window for the phone at `scale` (default: fit the monitor); (window, scale)."""
    if scale is not None and not 0.05 <= scale <= 4.0:
        raise WindowError(f"--scale {scale} must be in [0.05, 4]")
    errors: list[str] = []
    glfw.set_error_callback(lambda code, text: errors.append(f"{_text(text)} ({code:#x})"))
    if not glfw.init():
        raise WindowError(f"GLFW could not start: {'; '.join(errors) or 'no reason given'}")
    scale = scale or fit_scale(_workarea())
    size = (max(1, round(PHONE[0] * scale)), max(1, round(PHONE[1] * scale)))
    _window_hints()
    window = glfw.create_window(*size, TITLE, None, None)
    if not window:
        glfw.terminate()
        raise WindowError(f"cannot open a {size[0]}x{size[1]} OpenGL 3.3 core window: "
                          f"{'; '.join(errors) or 'no reason given'}")
    glfw.make_context_current(window)
    glfw.swap_interval(1)
    glfw.set_window_aspect_ratio(window, *PHONE)
    return window, scale


def _window_hints() -> None:
    """Every GLFW hint in one place: OpenGL 3.3 core (runs the GLSL ES 3.00 shaders)."""
    glfw.default_window_hints()
    glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
    glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
    glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
    glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
    glfw.window_hint(glfw.RESIZABLE, True)
    glfw.window_hint(glfw.DOUBLEBUFFER, True)
    glfw.window_hint(glfw.SCALE_TO_MONITOR, False)


def _workarea() -> tuple[int, int]:
    monitor = glfw.get_primary_monitor()
    if not monitor:
        return 0, 0
    _, _, w, h = glfw.get_monitor_workarea(monitor)
    return w, h


def moved_light(light, dx: float, dy: float) -> tuple[float, float, float]:
    """The light direction moved on the screen (x right, y down), kept toward the viewer."""
    x, y = float(light[0]) + dx, float(light[1]) + dy
    r = math.hypot(x, y)
    if r > MAX_LIGHT_TILT:
        x, y = x * MAX_LIGHT_TILT / r, y * MAX_LIGHT_TILT / r
    return x, y, math.sqrt(max(0.0, 1.0 - x * x - y * y))


class FrostWindow:
    """One window, its GL objects and the simulation thread feeding it."""

    def __init__(self, window, args, params: Params):
        self.window, self.args = window, args
        self.ctx = moderngl.create_context()
        self.renderer = Renderer(self.ctx, params, *PHONE)
        self.phone = self.ctx.framebuffer(
            color_attachments=[self.ctx.texture(PHONE, 4)],
            depth_attachment=self.ctx.depth_renderbuffer(PHONE))
        self.phone.color_attachments[0].filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.blit = load_program(self.ctx, "blit.vert", "blit.frag")
        self.blit["u_texture"].value = 0
        self.quad = self.ctx.vertex_array(self.blit, [])
        self.hud = Hud(self.ctx)
        self.keys = key_table(lambda name: getattr(glfw, f"KEY_{name}"))
        self.actions = self._action_table()
        self.params = params
        self.sim = SimThread(params, args.seed, args.touch or (), *PHONE,
                             wake=glfw.post_empty_event, script=getattr(args, "script", ()))
        self.recorder = Recorder(args.screenshot_dir,
                                 lambda text: self.sim.notify(logging.WARNING, text))
        self.renderer.set_view(getattr(args, "view", None))  # a replayed session's view
        self._init_state()
        self._connect()

    def _init_state(self) -> None:
        self.latest: Snapshot | None = None
        self.dirty, self.running, self.status = True, True, 0
        self.interrupted = False  # ended by Ctrl-C (SIGINT)
        self.frames, self.renders, self.render_ms, self.snapshots = 0, 0, 0.0, 0
        self.frame_ms = 0.0  # render + present, moving average
        self.new_ticks = 0  # snapshots since the last recorded frame
        self.fps, self.drag_from, self.clicks_pending = 0.0, None, []
        self.melt_from = None  # where a right-button drag (the warm finger) last melted
        self.pointer = None  # the cursor position of the last motion event, window px
        self.melts_sent = 0  # by the current right-button drag
        self.message, self.message_until = "", 0.0
        self.screenshots: list[Path] = []
        self.names: set[str] = set()  # stems of screenshots and map folders asked for
        self.session_path: Path | None = None
        self.latencies: list[tuple[str, int, float]] = []  # (kind, ticks, ms)
        self.started = time.monotonic()
        self.fb_size = glfw.get_framebuffer_size(self.window)
        self.window_size = glfw.get_window_size(self.window)
        self.iconified, self._damaged = False, True
        self._log_mark = (0, self.started)
        self._hud_next, self._log_next = 0.0, self.started + LOG_PERIOD
        self._fps_mark = (0, self.started)
        self._hud_stats: list[str] = []

    def _connect(self) -> None:
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_mouse_button_callback(self.window, self._on_button)
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)
        glfw.set_framebuffer_size_callback(self.window, self._on_framebuffer)
        glfw.set_window_size_callback(self.window, self._on_window_size)
        glfw.set_window_iconify_callback(self.window, self._on_iconify)
        glfw.set_window_refresh_callback(self.window, lambda *_: self._damage())

    # ---- the frame loop -------------------------------------------------------------

    def loop(self) -> int:
        self.sim.start()
        deadline = self.started + (self.args.max_seconds or math.inf)
        while self.running and not glfw.window_should_close(self.window):
            self._drain()
            if time.monotonic() >= deadline:
                log.info("window: --max-seconds %.1f reached", self.args.max_seconds)
                break
            if self._minimized():
                self.new_ticks = 0  # nothing to record while nothing is shown
                glfw.wait_events_timeout(IDLE_WAIT)
                continue
            self._frame()
            glfw.wait_events_timeout(IDLE_WAIT)
        return self.status

    def close(self) -> None:
        self.sim.stop()
        self.recorder.close()
        self._drain_notices()
        try:
            self._save_session()
        except OSError as err:
            log.warning("session NOT saved: %s", why(err, self.session_path))
        self._summary()

    def _save_session(self, path: Path | None = None) -> Path:
        """The session up to the frame shown and the view it was shown with, to `path`
        (default: this run's file, made on first use); replay it with --replay FILE.
        OSError if it cannot be written (nothing half-written is left)."""
        snap = self.latest
        log_ = self.sim.session(snap.steps, snap.events) if snap else self.sim.session(0, 0)
        log_.view = self.renderer.view()
        if path is None:
            self.session_path = self.session_path or timestamped_path(
                self.args.session_dir, "session", ".json")
            path = self.session_path
        log_.save(path)
        log.info("session: %s (%d events, %d steps)", path, len(log_.events), log_.steps)
        return path

    def _drain(self) -> None:
        for snap in self.sim.drain():
            self._apply(snap)
        self._drain_notices()

    def _drain_notices(self) -> None:
        """Messages of the workers (map exports, recordings) to the HUD and the log."""
        while not self.sim.notices.empty():
            self._say(*self.sim.notices.get()[::-1])

    def _apply(self, snap: Snapshot) -> None:
        if snap.error:
            log.error("simulation thread died: %s", snap.error)
            self.running, self.status = False, 1
            return
        if snap.reset:
            self.renderer.reset()
            self.dirty = True
            if self.sim.script:  # a replayed parameter change
                self.params = snap.params
        for melt in snap.melts:
            self.renderer.apply(melt)
            self.dirty = True
        if snap.delta is not None:
            self.renderer.apply(snap.delta)
            self.dirty = self.dirty or _changes(snap.delta)
        self.snapshots += 1
        if snap.message:
            self._say(snap.message)
        self.new_ticks += 1
        self.clicks_pending.extend(("frost", c, snap.stats.tick) for c in snap.clicks)
        self.clicks_pending.extend(("growth", c, snap.stats.tick) for c in snap.grown)
        self.latest = snap

    def _minimized(self) -> bool:
        return self.iconified or 0 in self.fb_size

    def _frame(self) -> None:
        now = time.monotonic()
        t0 = time.perf_counter()
        presented = self.frames
        if self.dirty:
            self._render_phone()
        if self.new_ticks and self.recorder.active:
            # One recorded frame per tick (25 per second), whatever the frame rate.
            for _ in range(min(self.new_ticks, RECORD_CATCHUP)):
                self.recorder.offer(lambda: read_image(self.phone))
        self.new_ticks = 0
        if self.dirty or now >= self._hud_next or self._damaged:
            self._present(now)
        if self.frames > presented:
            self.frame_ms = 0.9 * self.frame_ms + 100.0 * (time.perf_counter() - t0)

    def _damage(self) -> None:
        self._damaged = True

    def _render_phone(self) -> None:
        t0 = time.perf_counter()
        self.phone.use()
        self.renderer.render(self.phone)
        self.render_ms = 0.9 * self.render_ms + 100.0 * (time.perf_counter() - t0)
        self.renders += 1

    def _present(self, now: float) -> None:
        fb = self.fb_size
        screen = self.ctx.screen
        screen.use()
        self.ctx.viewport = (0, 0, *fb)
        screen.clear(*BACKDROP)
        self.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        self.ctx.viewport = letterbox(fb)
        self.blit["u_rect"].value = (-1.0, -1.0, 1.0, 1.0)
        self.phone.color_attachments[0].use(0)
        self.quad.render(moderngl.TRIANGLE_STRIP, vertices=4)
        self.ctx.viewport = (0, 0, *fb)
        self._draw_hud(fb, now)
        glfw.swap_buffers(self.window)
        self.frames += 1
        self.dirty = self._damaged = False
        self._after_present(now)

    def _draw_hud(self, fb, now: float) -> None:
        if now >= self._hud_next:
            self._update_fps(now)
            self._hud_stats = self._stats_lines(now)
            self._hud_next = now + HUD_PERIOD
        self.hud.draw(fb, self._hud_stats, HELP)

    def _after_present(self, now: float) -> None:
        for kind, (click_tick, t_click), tick in self.clicks_pending:
            ms = (time.monotonic() - t_click) * 1000.0
            self.latencies.append((kind, tick - click_tick, ms))
            log.info("click-to-first-%s: %d ticks, %.1f ms (%s)", kind, tick - click_tick, ms,
                     LATENCY_NOTES[kind])
        self.clicks_pending = []
        if now >= self._log_next:
            self._log_next = now + LOG_PERIOD
            frames, since = self._log_mark
            self._log_mark = (self.frames, now)
            log.info("stats: %.1f fps over %.1f s  %s", (self.frames - frames) / (now - since),
                     now - since, "  ".join(self._stats_lines(now)[:3]))

    def _update_fps(self, now: float) -> None:
        frames, since = self._fps_mark
        if now - since >= 0.5:
            self.fps = (self.frames - frames) / (now - since)
            self._fps_mark = (self.frames, now)

    # ---- HUD text ----------------------------------------------------------------------

    def _stats_lines(self, now: float) -> list[str]:
        s = self.latest.stats if self.latest else Stats(0, 0.0, 0, 0, 0.0, 0, False)
        p = self.latest.params if self.latest else self.params  # what the frame shows
        r = self.renderer
        state = [w for w, on in (("PAUSED", s.paused),
                                 (f"REC {self.recorder.count} frames", self.recorder.active)) if on]
        lines = [
            f"fps {self.fps:5.1f}  frame {self.frame_ms:5.1f} ms  render {self.render_ms:5.1f} ms",
            f"tick {s.tick}  {s.tick_ms:5.1f} ms  rate {s.rate:4.1f}/s  overruns {s.overruns}",
            f"crystals {s.crystals}  water {s.water}  preset {preset_name(p)}",
            f"hc {p.hc:g}  D {p.D:g}  humidity {p.humidity}  step {p.step:g}  bump {p.bump:g}  "
            f"grow {_onoff(p.grow)}",
            f"features {_onoff(r.show_features)}  bumps {_onoff(r.show_bumps)}  "
            "light ({:.2f}, {:.2f}, {:.2f})".format(*r.light),
            "  ".join(state) or "running",
        ]
        if now < self.message_until:
            lines.append(self.message)
        return lines + ["H help"]

    def _say(self, text: str, level: int = logging.INFO) -> None:
        log.log(level, "%s", text)
        self.message, self.message_until = text, time.monotonic() + MESSAGE_SECONDS
        self._hud_next = 0.0

    # ---- input ---------------------------------------------------------------------------

    def _on_key(self, _window, key, _scancode, action, _mods) -> None:
        binding = self.keys.get(key)
        if binding is None or action == glfw.RELEASE:
            return
        if action == glfw.REPEAT and binding.action not in REPEATING:
            return
        self.actions[binding.action](binding.arg)
        self._hud_next = 0.0  # show the change at once

    def _on_button(self, _window, button, action, _mods) -> None:
        if button == glfw.MOUSE_BUTTON_RIGHT:
            self._warm_finger(action)
            return
        if button != glfw.MOUSE_BUTTON_LEFT:
            return
        if action == glfw.RELEASE:
            self.drag_from = None
            return
        spot = self._pointer_phone()  # where the events put it, not where it is by now
        if spot is None:
            return
        tick = self.latest.stats.tick if self.latest else 0
        self.sim.send("touch", (spot, (tick, time.monotonic())))
        self.drag_from = spot

    def _warm_finger(self, action) -> None:
        """Right button down: melt under the cursor, and along the path while it is held."""
        if action == glfw.RELEASE:
            if self.melt_from is not None:
                log.info("warm finger: %d melts of radius %g px", self.melts_sent,
                         self.args.melt_radius)
            self.melt_from = None
            return
        self.melt_from, self.melts_sent = self._pointer_phone(), 0
        if self.melt_from is not None:
            self._send_melt(self.melt_from)

    def _send_melt(self, spot) -> None:
        self.sim.send("melt", (*spot, self.args.melt_radius))
        self.melts_sent += 1

    def _on_cursor(self, _window, x, y) -> None:
        self.pointer = (x, y)
        if self.melt_from is not None:
            self._melt_drag()
        spot = self.drag_from and self._pointer_phone()
        if not spot:
            return
        points = path_points(self.drag_from, spot, DRAG_SPACING_HC * self.params.hc)
        for point in points:
            self.sim.send("touch", (point, None))
        if points:
            self.drag_from = points[-1]

    def _melt_drag(self) -> None:
        spot = self._pointer_phone()
        if spot is None:
            return
        points = path_points(self.melt_from, spot, MELT_SPACING * self.args.melt_radius)
        for point in points:
            self._send_melt(point)
        if points:
            self.melt_from = points[-1]

    def _pointer_phone(self):
        """Where the events so far put the cursor (a drag follows its path even when the
        frame loop runs behind the pointer), in phone px; None outside the phone."""
        if self.pointer is None:
            return self._cursor_phone()
        return cursor_to_phone(self.pointer, self.window_size, self.fb_size)

    def _cursor_phone(self):
        return cursor_to_phone(glfw.get_cursor_pos(self.window), self.window_size, self.fb_size)

    # Sizes come from callbacks: each GLFW call from Python waits for the GIL, which the
    # simulation thread may hold for a few ms, so the frame loop makes as few as it can.
    def _on_framebuffer(self, _window, w: int, h: int) -> None:
        self.fb_size = (w, h)
        self._damage()

    def _on_window_size(self, _window, w: int, h: int) -> None:
        self.window_size = (w, h)

    def _on_iconify(self, _window, iconified: int) -> None:
        self.iconified = bool(iconified)

    # ---- actions (the key table's action names) --------------------------------------------

    def _action_table(self) -> dict:
        return {"pause": lambda _: self.sim.send("pause"),
                "single_step": lambda _: self.sim.send("step"),
                "clear": self._clear, "screenshot": self._screenshot,
                "record": lambda _: self.recorder.toggle(),
                "export_maps": self._export_maps,
                "scale": self._scale, "shift": self._shift, "preset": self._preset,
                "toggle_param": self._toggle_param,
                "toggle_view": self._toggle_view, "light": self._move_light,
                "toggle_hud": self._toggle_hud, "toggle_help": self._toggle_help,
                "quit": self._quit}

    def _clear(self, _arg) -> None:
        self.sim.send("clear")
        self._say("cleared")

    def _quit(self, _arg) -> None:
        self.running = False

    def interrupt(self) -> None:
        """Ctrl-C: end the loop at the next frame, as Esc does."""
        self.running, self.interrupted = False, True

    def _toggle_hud(self, _arg) -> None:
        self.hud.visible = not self.hud.visible
        self._damage()

    def _toggle_help(self, _arg) -> None:
        self.hud.show_help = not self.hud.show_help
        self._damage()

    def _toggle_view(self, name: str) -> None:
        setattr(self.renderer, name, not getattr(self.renderer, name))
        self.dirty = True
        self._say(f"{name} {_onoff(getattr(self.renderer, name))}")

    def _move_light(self, arg) -> None:
        self.renderer.light = moved_light(self.renderer.light, *arg)
        self.dirty = True

    def _scale(self, arg) -> None:
        self._tune(tuning.scaled, *arg)

    def _shift(self, arg) -> None:
        self._tune(tuning.shifted, *arg)

    def _toggle_param(self, name: str) -> None:
        self._tune(tuning.toggled, name)

    def _preset(self, name: str) -> None:
        self._tune(tuning.preset, name)

    def _tune(self, change, *arg) -> None:
        try:
            params = change(self.params, *arg)
        except ValueError as err:
            self._say(f"refused: {err}", logging.WARNING)
            return
        changed = tuning.differences(self.params, params)
        if not changed:
            self._say("params: unchanged")
            return
        self.params = params
        self.sim.send("params", params)
        self._say("params: " + " ".join(f"{k}={_number(v)}" for k, v in changed.items()))

    def _screenshot(self, _arg) -> None:
        """The frame shown, as a PNG stating what made it (all from the snapshot shown and
        the renderer's view), and its own session file: replaying it ends on this frame."""
        self._render_phone()
        snap = self.latest
        meta = {"params": json.dumps((snap.params if snap else self.params).as_dict()),
                "seed": str(self.sim.seed), "touches": json.dumps(snap.touches if snap else []),
                "tick": str(snap.stats.tick if snap else 0),
                "view": json.dumps(self.renderer.view())}
        path = self._fresh_name(".png")
        try:
            meta["session"] = str(self._save_session(
                Path(self.args.session_dir) / f"{path.stem}.json"))
        except OSError as err:
            self._say(f"screenshot's session NOT saved: {why(err, path.stem + '.json')}",
                      logging.WARNING)
        try:
            path = save_png(read_image(self.phone), path, meta)
        except OSError as err:
            self._say(f"screenshot NOT saved: {why(err, path)}", logging.WARNING)
            return
        self.screenshots.append(path)
        self._say(f"screenshot: {path}")

    def _export_maps(self, _arg) -> None:
        """The maps of the next tick's frost, written by a worker that reports back."""
        folder = self._fresh_name("")
        self.sim.send("export", folder)
        self._say(f"frost maps: exporting to {folder}/")

    def _fresh_name(self, suffix: str) -> Path:
        """A new name in the screenshot folder whose stem no screenshot, screenshot
        session, map folder or earlier request (written or failed) of this run has."""
        shots = Path(self.args.screenshot_dir)
        path = timestamped_path(shots, suffix=suffix, taken=self.names, also=(
            (shots, ".png"), (shots, ""), (Path(self.args.session_dir), ".json")))
        self.names.add(path.stem)
        return path

    # ---- the end --------------------------------------------------------------------------

    def _summary(self) -> None:
        elapsed = max(time.monotonic() - self.started, 1e-9)
        s = self.latest.stats if self.latest else Stats(0, 0.0, 0, 0, 0.0, 0, False)
        lat = ", ".join(f"{k} {t} ticks {ms:.0f} ms" for k, t, ms in self.latencies) or "none"
        log.info("summary: %.1f s, %d frames (%.1f fps), %d phone renders, %d ticks "
                 "(%.1f ticks/s), %d overruns, %d screenshots, latency %s, exit status %d",
                 elapsed, self.frames, self.frames / elapsed, self.renders, self.snapshots,
                 self.snapshots / elapsed, s.overruns, len(self.screenshots), lat, self.status)


def _changes(delta) -> bool:
    return delta.reset or delta.rows.stop > delta.rows.start or len(delta.features) > 0


def _number(v) -> str:
    if isinstance(v, bool):
        return _onoff(v)
    return f"{v:g}" if isinstance(v, float) else str(v)


def _text(text) -> str:
    return text.decode(errors="replace") if isinstance(text, bytes) else str(text)


def _onoff(flag: bool) -> str:
    return "on" if flag else "off"


def run(args, params: Params) -> int:
    """Open the phone window and run until it closes; the exit status."""
    try:
        window, scale = open_window(args.scale)
    except WindowError as err:
        log.error("%s", err)
        return 1
    log.info("window: %dx%d at scale %.2f, framebuffer %dx%d",
             *glfw.get_window_size(window), scale, *glfw.get_framebuffer_size(window))
    app = None
    try:
        app = FrostWindow(window, args, params)
        with _ctrl_c_ends(app):
            status = app.loop()
    except Exception:
        log.exception("window failed")
        if app is not None:
            app.status = 1
        return 1
    finally:
        if app is not None:
            app.close()
        glfw.terminate()
    if app.interrupted:  # closed and saved; the caller says so and exits 130
        raise KeyboardInterrupt
    return status


@contextlib.contextmanager
def _ctrl_c_ends(app: FrostWindow):
    """While the window runs, SIGINT ends the frame loop like Esc (and marks it
    interrupted) instead of raising KeyboardInterrupt wherever the main thread is, e.g.
    inside a GLFW callback, where ctypes would swallow it. Left alone when ignored."""
    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        yield
        return
    signal.signal(signal.SIGINT, lambda *_: app.interrupt())
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
