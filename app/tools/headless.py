"""Headless mode: grow the frost offscreen (EGL) and write PNG files; no display needed."""

from __future__ import annotations

import logging
import sys
import time
from pathlib import Path

from app.gl.renderer import Renderer
from app.images import read_image, save_png, timestamped_path
from sim import Params
from sim.files import why
from sim.gestures import MELT_SPACING, path_points
from sim.screen import HEIGHT, WIDTH, check_touch
from sim.session import Applied, SessionError, SessionLog, Timeline, apply_due, replay

log = logging.getLogger(__name__)

PROGRESS_EVERY_S = 2.0  # a progress line at most this often on long runs
DEFAULT_FOLDER = Path("frost-out")


def make_context():
    """A standalone OpenGL context with no window (EGL), or RuntimeError saying why not."""
    try:
        import moderngl

        # moderngl types **settings as one dict argument; backend is a keyword it reads
        return moderngl.create_standalone_context(backend="egl")  # type: ignore[arg-type]
    except Exception as err:  # moderngl raises bare Exceptions for missing EGL/drivers
        raise RuntimeError(f"no OpenGL available: {err}") from err


def scripted_session(ticks: int) -> list[tuple[int, float, float]]:
    """The demo with no --touch: (tick, x, y) of touches staggered over the run."""
    return [(0, WIDTH / 2, HEIGHT / 2), (ticks // 5, WIDTH * 0.25, HEIGHT * 0.25),
            (2 * ticks // 5, WIDTH * 0.72, HEIGHT * 0.78)]


class Progress:
    """A line on stdout every PROGRESS_EVERY_S seconds of a long run, counting against
    the whole run's ticks (all its stages together)."""

    def __init__(self, total: int):
        self.total, self.done = total, 0
        self._last = time.perf_counter()

    def step(self, sim) -> None:
        self.done += 1
        now = time.perf_counter()
        if now - self._last >= PROGRESS_EVERY_S:
            print(f"tick {sim.tick} ({self.done}/{self.total}), {len(sim.crystals)} crystals "
                  "(Ctrl-C stops)", flush=True)
            self._last = now


class Session:
    """One headless run: a Timeline (simulation, geometry, events) and a renderer fed
    every delta in order."""

    def __init__(self, ctx, params: Params, seed: int):
        self.timeline = Timeline(params, seed, WIDTH, HEIGHT)
        self.renderer = Renderer(ctx, params, WIDTH, HEIGHT)
        self.fbo = ctx.simple_framebuffer((WIDTH, HEIGHT), components=4)
        self.touches: list[tuple[int, float, float]] = []
        self.meta: dict = {}  # more PNG metadata, e.g. the session file replayed
        self.progress: Progress | None = None  # told of every step when set

    @property
    def sim(self):
        return self.timeline.sim

    def touch(self, x: float, y: float) -> None:
        check_touch(x, y)
        self.show(self.timeline.apply([{"kind": "touch", "x": x, "y": y}]))
        self.touches.append((self.sim.tick, x, y))

    def show(self, applied: Applied) -> None:
        """Hand an event result to the renderer: a rebuild clears it, melts update it."""
        if applied.reset:
            self.renderer.reset()
        for delta in applied.deltas:
            self.renderer.apply(delta)

    def step(self) -> None:
        for delta in self.timeline.step():
            self.renderer.apply(delta)
        if self.progress:
            self.progress.step(self.sim)

    def snapshot(self, path: Path) -> Path:
        self.renderer.render(self.fbo)
        meta = {"parameters": self.sim.params.as_dict(), "seed": self.sim.seed,
                "touches": [list(t) for t in self.touches], "tick": self.sim.tick,
                "view": self.renderer.view(),
                "Software": "frost (frost render)", **self.meta}
        return save_png(read_image(self.fbo), path, meta)


def melt_events(args) -> list[dict]:
    """--melt and --melt-path as melt events in tick order (a path: a melt every half
    radius along it)."""
    r = args.melt_radius
    events = [{**m, "r": m["r"] or r} for m in args.melt]
    for path in args.melt_path:
        spots = [path["points"][0]]
        for a, b in zip(path["points"], path["points"][1:], strict=False):
            spots.extend(path_points(a, b, MELT_SPACING * r))
        events.extend({"tick": path["tick"], "kind": "melt", "x": x, "y": y, "r": r}
                      for x, y in spots)
    return sorted(events, key=lambda e: e["tick"])


def run(args, params: Params) -> int:
    """`frost render ...` and a headless `frost replay ...`; returns the exit status."""
    if args.ticks is not None and args.ticks < 0:
        _error(f"--ticks {args.ticks} must be 0 or more")
        return 2
    try:
        ctx = make_context()
    except RuntimeError as err:
        _error(err)
        return 1
    if args.replay:
        return _run_replay(ctx, args)
    session = Session(ctx, params, args.seed)
    if args.touch or params.window_frost:  # a window frosts from its frame untouched
        return _run_touches(session, args)
    if args.melt or args.melt_path:
        _error("--melt and --melt-path need --touch (the scripted demo takes none)")
        return 2
    return _run_scripted(session, args)


def _run_touches(session: Session, args) -> int:
    try:
        for x, y in args.touch:
            session.touch(x, y)
    except ValueError as err:
        _error(err)
        return 2
    melts, at = melt_events(args), 0
    session.progress = Progress(args.ticks)
    for _ in range(args.ticks):
        at = apply_due(session.timeline, melts, at, session.show)
        session.step()
    apply_due(session.timeline, melts, at, session.show)
    path = Path(args.out) if args.out else timestamped_path(DEFAULT_FOLDER)
    return _write(session, path, "wrote {}")


def load_session(path) -> SessionLog:
    """The session file `path` for this 760x1280 screen; SessionError saying why not."""
    log_ = SessionLog.load(path)
    if (log_.width, log_.height) != (WIDTH, HEIGHT):
        raise SessionError(f"{path}: a {log_.width}x{log_.height} session; this app renders "
                           f"{WIDTH}x{HEIGHT}")
    return log_


def replay_session(ctx, log_: SessionLog, steps: int | None = None,
                   progress: Progress | None = None) -> Session:
    """A Session that went through `log_` (see sim.session.replay) with its renderer,
    shown with the session's view, stating the replay's touches."""
    session = Session(ctx, Params(**log_.params), log_.seed)
    session.renderer.set_view(log_.view)
    session.timeline = replay(log_, steps, session.show, session.renderer.apply,
                              progress.step if progress else None)
    session.touches = replayed_touches(session.timeline.events, WIDTH, HEIGHT)
    return session


def replayed_touches(events: list[dict], width: int, height: int) -> list[tuple[int, float, float]]:
    """(tick, x, y) of the touches a replay ended with, as a live run states them: a
    clear drops them, a parameter change replants them at tick 0, off-screen ones never
    counted."""
    touches: list[tuple[int, float, float]] = []
    for e in events:
        if e["kind"] == "touch" and 0 <= e["x"] < width and 0 <= e["y"] < height:
            touches.append((e["tick"], float(e["x"]), float(e["y"])))
        elif e["kind"] == "clear":
            touches = []
        elif e["kind"] == "params":
            touches = [(0, x, y) for _, x, y in touches]
    return touches


def _run_replay(ctx, args) -> int:
    try:
        log_ = load_session(args.replay)
    except SessionError as err:
        _error(err)
        return 2
    progress = Progress(log_.steps if args.ticks is None else args.ticks)
    try:
        session = replay_session(ctx, log_, args.ticks, progress)
    except ValueError as err:  # an event the simulation refuses, e.g. a touch off the screen
        _error(f"{args.replay}: cannot replay: {err}")
        return 2
    session.meta = {"session": str(args.replay), "replayed_steps": session.timeline.steps}
    path = Path(args.out) if args.out else timestamped_path(DEFAULT_FOLDER)
    return _write(session, path, f"replayed {args.replay}: {session.timeline.steps} steps, "
                                 f"{len(session.timeline.events)} events; wrote {{}}")


def _write(session: Session, path: Path, done: str) -> int:
    """Write the frame to `path` and print `done` with the path; a path that cannot be
    written is a one-line error (exit 2), with nothing half-written left behind."""
    try:
        written = session.snapshot(path)
    except OSError as err:
        _error(f"cannot write {why(err, path)}")
        return 2
    print(done.format(written))
    return 0


def _run_scripted(session: Session, args) -> int:
    """No touches given: a short scripted demo, a PNG after each stage."""
    folder = Path(args.out).parent if args.out else DEFAULT_FOLDER
    script = scripted_session(args.ticks)
    stops = [t for t, _, _ in script[1:]] + [args.ticks]
    written = []
    session.progress = Progress(args.ticks)
    try:
        for (start, x, y), stop in zip(script, stops, strict=True):
            session.touch(x, y)
            for _ in range(stop - start):
                session.step()
            written.append(session.snapshot(folder / f"frost-demo-tick{stop:04d}.png"))
        if args.out:
            written.append(session.snapshot(Path(args.out)))
    except OSError as err:
        _error(f"cannot write {why(err, folder)}")
        return 2
    print(f"wrote {len(written)} PNG files to {folder.resolve()}: "
          + ", ".join(p.name for p in written))
    return 0


def _error(message) -> None:
    """A one-line error for the user, no traceback."""
    print(f"frost: error: {message}", file=sys.stderr)
