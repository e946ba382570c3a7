"""The simulation thread's snapshots, encoded once a tick and fanned out to every page.

Runs on the asyncio loop, which the thread's wake-up schedules after each tick. A page
that connects or resyncs needs the whole frost: the live ice is drawn anew
(`FrostGeometry.redraw`, into a geometry of its own) on the simulation thread between two
ticks (`SimThread.between_ticks`), so it reads a simulation that nothing changes
meanwhile, and it is tagged with the (steps, events) of the snapshot it follows. The
heights come from the encoder's grid (the sum of every delta sent). Beside the desktop
window the feed is one more reader of the window's thread (`SimThread.subscribe`).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
from collections import deque

from app.backdrops import BACKDROPS
from app.serve import protocol
from app.serve.controls import Controls
from app.serve.pages import Page
from app.simthread.thread import SimThread, Snapshot
from sim import Params, all_presets
from sim.look.geometry import FrostGeometry, GeometryDelta
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES, MAX_DEPTH, TILE, Material, default_light
from sim.params import LOOKS
from sim.screen import SIZE

log = logging.getLogger("app.serve")

# Per-tick figures kept for the bench (six minutes).
SIZES_KEPT = 9000


class Feed:
    """One simulation thread, its encoder and the pages it feeds."""

    def __init__(self, params: Params, seed: int, touches=(), melt_radius: float = 24.0,
                 backdrop: str = "dusk", thread: SimThread | None = None):
        """A feed of a new simulation thread, or of `thread` (the desktop window's, which
        starts it, reads its notices and keeps the session file)."""
        self._loop: asyncio.AbstractEventLoop | None = None
        self._pumping = threading.Event()  # a pump is scheduled
        self.own_thread = thread is None
        if thread is None:
            self.thread = SimThread(params, seed, touches, *SIZE, wake=self._woken)
            self._drain = self.thread.drain
        else:
            self.thread = thread
            self._drain = thread.subscribe(self._woken)
        geometry = self.thread.geometry
        self.encoder = protocol.Encoder(geometry.cols, geometry.rows)
        self.controls = Controls(self.thread, params, melt_radius, backdrop, self.notice,
                                 self.tick)
        self.pages: set[Page] = set()
        self.latest: Snapshot | None = None
        # Where the session stood at the latest snapshot published: (steps, events), as
        # a session file of it would count them (a redraw is tagged with its own).
        self.moment = (0, 0)
        self.error: str | None = None
        self.redraws = 0
        # For the bench: bytes sent a tick, the thread's tick time (ms)
        self.sizes: deque[int] = deque(maxlen=SIZES_KEPT)
        self.tick_ms: deque[float] = deque(maxlen=SIZES_KEPT)
        self._state: dict = {}
        self._want_redraw = threading.Event()  # a redraw is asked for and not begun
        self._lock = threading.Lock()
        self._redraw: tuple[tuple[int, int], GeometryDelta] | None = None

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        if self.own_thread:
            self.thread.start()

    def tick(self) -> int:
        return self.latest.stats.tick if self.latest else 0

    # ---- the simulation thread's side ---------------------------------------------------

    def _woken(self) -> None:
        """The thread's wake-up: after every tick (on its thread) and for its notices."""
        loop = self._loop
        if loop is not None and not self._pumping.is_set():
            self._pumping.set()
            with contextlib.suppress(RuntimeError):  # the loop is closed: the end
                loop.call_soon_threadsafe(self.pump)

    def _make_redraw(self) -> None:
        """The live frost drawn anew, between two ticks (`SimThread.between_ticks`)."""
        self._want_redraw.clear()
        thread = self.thread
        timeline = thread.timeline
        moment = (timeline.steps, len(timeline.events))
        try:
            delta = FrostGeometry(thread.params, *thread.size).redraw(thread.sim)
        except Exception:  # (the thread may have died in its tick)
            log.exception("serve: the snapshot of the frost failed")
            return
        with self._lock:
            self._redraw = (moment, delta)

    # ---- the loop's side -----------------------------------------------------------------

    def ask_redraw(self) -> None:
        """A snapshot of the whole frost for the pages waiting, drawn between the next two
        ticks (once, however often it is asked meanwhile)."""
        if not self._want_redraw.is_set():
            self._want_redraw.set()
            self.thread.between_ticks(self._make_redraw)

    def pump(self) -> None:
        """Publish every snapshot the thread made since the last pump."""
        self._pumping.clear()
        for snap in self._drain():
            self._publish(snap)
            self._serve_redraw()
        self._serve_redraw()
        if not self.own_thread:
            return  # (the window reads the thread's notices)
        while not self.thread.notices.empty():
            level, text = self.thread.notices.get()
            log.log(level, "%s", text)

    def _publish(self, snap: Snapshot) -> None:
        if snap.error:
            log.error("simulation thread died: %s", snap.error)
            self.error = snap.error
            return
        reset, messages = snap.reset, []
        for delta in (*snap.melts, *(() if snap.delta is None else (snap.delta,))):
            messages.append(self.encoder.delta(delta, reset=reset))
            reset = False
        if reset:
            messages.append(self.encoder.bare(snap.stats.tick, reset=True))
        if snap.reset and not self.own_thread:  # (the window's keys change them too)
            self.controls.params = snap.params
        self.latest, self.moment = snap, (snap.steps, snap.events)
        self.sizes.append(sum(map(len, messages)))
        self.tick_ms.append(snap.stats.tick_ms)
        self._send_state()
        if snap.message:
            self.notice(snap.message)
        if messages:
            for page in self.pages:
                page.tick(messages)

    def _serve_redraw(self) -> None:
        with self._lock:
            ready = self._redraw
            if ready is None or ready[0] > self.moment:
                return  # none, or its snapshot is not published yet
            self._redraw = None
        moment, delta = ready
        waiting = [p for p in self.pages if p.idle_waiting()]
        if moment < self.moment:  # the frost moved on before it was published: draw it again
            if waiting:
                self.ask_redraw()
            return
        self.redraws += 1
        parts = self.encoder.snapshot(delta.tick, delta.features, delta.look, delta.height_scale)
        state = protocol.text("state", **self.state())
        for page in waiting:
            page.start(parts, state)

    # ---- JSON ----------------------------------------------------------------------------

    def state(self) -> dict:
        snap, c = self.latest, self.controls
        return {"paused": bool(snap and snap.stats.paused), "preset": c.preset(),
                "look": c.params.look, "backdrop": c.backdrop, "tick": self.tick()}

    def _send_state(self) -> None:
        state = self.state()
        changed = {k: v for k, v in state.items() if self._state.get(k) != v and k != "tick"}
        self._state = state
        if changed:
            self.broadcast(protocol.text("state", **changed, tick=state["tick"]))

    def hello(self) -> str:
        m = Material()
        uniforms = {"u_ice_color": m.ice_color, "u_ambient": m.ambient, "u_diffuse": m.diffuse,
                    "u_specular": m.specular, "u_shininess": m.shininess,
                    "u_opacity": m.opacity, "u_density": m.density, "u_relief": m.relief,
                    "u_refraction": m.refraction}
        defines = {look: {"ice": list(LOOK_DEFINES[look]), "feature": list(FEATURE_DEFINES[look])}
                   for look in LOOKS}
        return protocol.text(
            "hello", protocol=protocol.VERSION, screen=list(SIZE),
            grid=list(self.encoder.grid), spacing=self.controls.params.grid_spacing,
            presets=list(all_presets()), looks=list(LOOKS), backdrops=list(BACKDROPS),
            view=self.view(), uniforms=uniforms, defines=defines, tile=TILE, max_depth=MAX_DEPTH,
            melt_radius=self.controls.melt_radius, **self.state())

    def view(self) -> dict:
        """The view a session file records (what the pages show by default)."""
        return {"light": [float(v) for v in default_light()], "features": True, "bumps": True,
                "background": self.controls.backdrop}

    def notice(self, text: str) -> None:
        self.broadcast(protocol.text("notice", text=text))

    def broadcast(self, message: str) -> None:
        for page in self.pages:
            if not page.waiting:
                page.text(message)

