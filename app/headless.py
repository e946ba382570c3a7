"""Headless mode: grow the frost offscreen (EGL) and write PNG files; no display needed."""

from __future__ import annotations

import logging
import sys
import time
from pathlib import Path

from sim import FrostSim, Params
from sim.geometry import FrostGeometry

from .render import Renderer
from .screenshot import read_image, save_png, timestamped_path

log = logging.getLogger(__name__)

WIDTH, HEIGHT = 760, 1280
PROGRESS_EVERY_S = 2.0  # a progress line at most this often on long runs
DEFAULT_FOLDER = Path("frost-out")


def make_context():
    """A standalone OpenGL context with no window (EGL), or RuntimeError saying why not."""
    try:
        import moderngl

        return moderngl.create_standalone_context(backend="egl")
    except Exception as err:  # moderngl raises bare Exceptions for missing EGL/drivers
        raise RuntimeError(f"no OpenGL available: {err}") from err


def scripted_session(ticks: int) -> list[tuple[int, float, float]]:
    """The demo with no --touch: (tick, x, y) of touches staggered over the run."""
    return [(0, WIDTH / 2, HEIGHT / 2), (ticks // 5, WIDTH * 0.25, HEIGHT * 0.25),
            (2 * ticks // 5, WIDTH * 0.72, HEIGHT * 0.78)]


class Session:
    """One headless run: simulation, geometry and renderer advanced tick by tick."""

    def __init__(self, ctx, params: Params, seed: int):
        self.sim = FrostSim(params, WIDTH, HEIGHT, seed)
        self.geometry = FrostGeometry(params, WIDTH, HEIGHT)
        self.renderer = Renderer(ctx, params, WIDTH, HEIGHT)
        self.fbo = ctx.simple_framebuffer((WIDTH, HEIGHT), components=4)
        self.touches: list[tuple[int, float, float]] = []

    def touch(self, x: float, y: float) -> None:
        self.sim.touch(x, y)
        self.touches.append((self.sim.tick, x, y))

    def step(self) -> None:
        self.sim.step()
        self.renderer.apply(self.geometry.update(self.sim))

    def snapshot(self, path: Path) -> Path:
        self.renderer.render(self.fbo)
        meta = {"parameters": self.sim.params.as_dict(), "seed": self.sim.seed,
                "touches": [list(t) for t in self.touches], "tick": self.sim.tick,
                "Software": "frost (python -m app --headless)"}
        return save_png(read_image(self.fbo), path, meta)


def run(args, params: Params) -> int:
    """`python -m app --headless ...`; returns the exit status."""
    if args.ticks < 0:
        _error(f"--ticks {args.ticks} must be 0 or more")
        return 2
    try:
        ctx = make_context()
    except RuntimeError as err:
        _error(err)
        return 1
    session = Session(ctx, params, args.seed)
    if args.touch:
        return _run_touches(session, args)
    return _run_scripted(session, args)


def _run_touches(session: Session, args) -> int:
    try:
        for x, y in args.touch:
            session.touch(x, y)
    except ValueError as err:
        _error(err)
        return 2
    _grow(session, args.ticks)
    path = Path(args.screenshot) if args.screenshot else timestamped_path(DEFAULT_FOLDER)
    print(f"wrote {session.snapshot(path)}")
    return 0


def _run_scripted(session: Session, args) -> int:
    """No touches given: a short scripted demo, a PNG after each stage."""
    folder = Path(args.screenshot).parent if args.screenshot else DEFAULT_FOLDER
    script = scripted_session(args.ticks)
    stops = [t for t, _, _ in script[1:]] + [args.ticks]
    written = []
    for (start, x, y), stop in zip(script, stops, strict=True):
        session.touch(x, y)
        _grow(session, stop - start)
        written.append(session.snapshot(folder / f"frost-demo-tick{stop:04d}.png"))
    if args.screenshot:
        written.append(session.snapshot(Path(args.screenshot)))
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


def _error(message) -> None:
    """A one-line error for the user, no traceback."""
    print(f"frost: error: {message}", file=sys.stderr)


def _grow(session: Session, ticks: int) -> None:
    """Advance `ticks` ticks, printing progress every few seconds on long runs."""
    last = time.perf_counter()
    for i in range(ticks):
        session.step()
        now = time.perf_counter()
        if now - last > PROGRESS_EVERY_S:
            print(f"tick {session.sim.tick} ({i + 1}/{ticks}), "
                  f"{len(session.sim.crystals)} crystals", flush=True)
            last = now

