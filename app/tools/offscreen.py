"""Frost drawn with no window: an EGL context, and `Offscreen`, the run that every
offline tool (render, replay, figure sheets) draws from."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from app.gl.renderer import Renderer
from app.images import frost_meta, read_image, save_image
from app.lockscreen import outside_line
from app.tools.progress import Progress
from sim import Params
from sim.io.files import one_line
from sim.io.session import VERSION
from sim.io.timeline import Applied, Timeline, grow
from sim.screen import HEIGHT, SIZE, WIDTH

# The standalone contexts tried in turn, by platform: on Linux EGL (no display needed),
# then GLX (a display); elsewhere the platform's own (CGL on a Mac, WGL on Windows: they
# have no EGL). Each an OpenGL 3.3 core context, as the shaders need (app/gl/shaders.py).
BACKENDS = {"linux": ("egl", None), "other": (None,)}
GL_REQUIRED = 330


def make_context():
    """A standalone OpenGL 3.3 context with no window from the first backend of BACKENDS
    that gives one, or RuntimeError naming why each could not, in one line."""
    try:
        import moderngl
    except ImportError as err:
        raise RuntimeError(f"no OpenGL: moderngl does not import ({err})") from err
    why = []
    for backend in BACKENDS["linux" if sys.platform.startswith("linux") else "other"]:
        settings = {"backend": backend} if backend else {}
        try:
            # moderngl types **settings as one dict argument; backend is a keyword it reads
            return moderngl.create_standalone_context(require=GL_REQUIRED,
                                                      **settings)  # type: ignore[arg-type]
        except Exception as err:  # moderngl raises bare Exceptions for missing EGL/drivers
            why.append(f"{backend or 'the platform default'}: {one_line(str(err))}")
    raise RuntimeError("no OpenGL 3.3 context could be made here (" + "; ".join(why) + ")")


class Offscreen:
    """A Timeline (simulation, geometry, events) and a renderer fed every delta in order."""

    def __init__(self, ctx, params: Params, seed: int, view: dict | None = None,
                 version: int = VERSION, minute: str | None = None, photos: Path | None = None,
                 backdrops: bool = True):
        """`minute`: the lock screen's clock until a clock event says otherwise (default
        app.lockscreen.DEFAULT_MINUTE); `photos`: the folder photo backdrops are found in;
        `backdrops`: whether backdrop events change the backdrop (not when one is imposed)."""
        self.timeline = Timeline(params, seed, WIDTH, HEIGHT, version=version)
        self.renderer = Renderer(ctx, params, WIDTH, HEIGHT)
        self.renderer.photos, self.backdrops = photos, backdrops
        if minute is not None:
            self.renderer.minute = minute
        self.renderer.set_view(view)
        self.fbo = ctx.simple_framebuffer(SIZE, components=4)
        self.meta: dict = {}  # more PNG metadata, e.g. the session file replayed
        self.progress: Progress | None = None  # told of every step when set

    @property
    def sim(self):
        return self.timeline.sim

    def grow(self, steps: int, events=(), on_tick=None) -> int:
        """`steps` steps with `events` applied at their ticks (sim.io.timeline.grow), every
        result shown; `on_tick(sim)` after each step. How many events applied."""
        def tick(sim) -> None:
            if self.progress:
                self.progress.step(sim)
            if on_tick:
                on_tick(sim)
        return grow(self.timeline, steps, events, self.show, self.renderer.apply, tick)

    def show(self, applied: Applied) -> None:
        """Hand an event result to the renderer: a rebuild clears it, melts update it, a
        clock event redraws the lock screen's clock (a weather event the temperature under
        it), a backdrop event changes the backdrop."""
        if applied.backdrop is not None and self.backdrops:
            self.renderer.set_backdrop(applied.backdrop)
        if applied.minute is not None or applied.weather is not None:
            outside = None if applied.weather is None else outside_line(applied.weather)
            self.renderer.set_minute(applied.minute or self.renderer.minute, outside=outside)
        if applied.reset:
            self.renderer.reset()
        for delta in applied.deltas:
            self.renderer.apply(delta)

    def frame(self) -> np.ndarray:
        """The frost drawn now: H x W x 3 uint8, top row first."""
        self.renderer.render(self.fbo)
        return read_image(self.fbo)

    def touches(self) -> list[tuple[int, float, float]]:
        """(tick, x, y) of the touches the frost now grows from, as a live run states them."""
        return self.timeline.touch_ticks()

    def snapshot(self, path: Path, software: str = "frost render") -> Path:
        meta = frost_meta(software, self.sim.params, self.sim.seed, self.sim.tick,
                          self.touches(), view=self.renderer.view(), **self.meta)
        return save_image(self.frame(), path, meta)

    def release(self) -> None:
        self.fbo.release()

