"""`frost render`: grow the frost offscreen from touches (or the scripted demo) and
write PNG files; no display needed."""

from __future__ import annotations

import sys
from pathlib import Path

from app.backdrops import view_from
from app.images import DEFAULT_FOLDER, timestamped_path
from app.lockscreen import minute_name
from app.tools.offscreen import Offscreen, make_context
from app.tools.progress import Progress
from app.weather.feed import first_event
from sim import Params
from sim.io.files import why
from sim.io.gestures import MELT_SPACING, path_points
from sim.io.timeline import touch_events
from sim.screen import HEIGHT, WIDTH


def demo_touches(ticks: int, size: tuple[int, int] = (WIDTH, HEIGHT)) -> list[tuple[int, float, float]]:
    """The demo with no --touch: (tick, x, y) of touches staggered over the run, at the
    same places on a screen of any `size`."""
    w, h = size
    return [(0, w / 2, h / 2), (ticks // 5, w * 0.25, h * 0.25),
            (2 * ticks // 5, w * 0.72, h * 0.78)]


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
    """`frost render ...`; returns the exit status."""
    weather = first_event(args, print)  # (before the context: the wait is the network's)
    try:
        ctx = make_context()
    except RuntimeError as err:
        error(err)
        return 1
    clock = getattr(args, "clock", None) or getattr(args, "clock_start", None)
    offscreen = Offscreen(ctx, params, args.seed, view_from(args),
                          minute=None if clock is None else minute_name(clock))
    offscreen.progress = Progress(args.ticks)
    if args.touch or params.window_frost:  # a window frosts from its frame untouched
        offscreen.grow(args.ticks, weather + touch_events(args.touch) + melt_events(args))
        return write(offscreen, Path(args.out) if args.out else timestamped_path(DEFAULT_FOLDER),
                     "wrote {}")
    return _run_demo(offscreen, args, weather)


def _run_demo(offscreen: Offscreen, args, weather: list[dict]) -> int:
    """No touches given: a short scripted demo, a PNG after each stage, all under one
    new name so that no earlier run's files are overwritten."""
    folder = Path(args.out).parent if args.out else DEFAULT_FOLDER
    script = demo_touches(args.ticks)
    stops = [t for t, _, _ in script[1:]] + [args.ticks]
    stem = demo_stem(folder, stops)
    written = []
    try:
        for i, ((start, x, y), stop) in enumerate(zip(script, stops, strict=True)):
            offscreen.grow(stop - start, (weather if i == 0 else []) + touch_events([(x, y)], start))
            if stop not in stops[i + 1:]:  # stages that end together (short runs) share a PNG
                written.append(offscreen.snapshot(folder / f"{stem}-tick{stop:04d}.png"))
        if args.out:
            written.append(offscreen.snapshot(Path(args.out)))
    except OSError as err:
        error(f"cannot write {why(err, folder)}")
        return 2
    files = "PNG file" if len(written) == 1 else "PNG files"
    print(f"wrote {len(written)} {files} to {folder.resolve()}: "
          + ", ".join(p.name for p in written))
    return 0


def demo_stem(folder: Path, stops: list[int]) -> str:
    """frost-demo-TIME-pPID (-N where needed): no file of the demo's exists under it."""
    also = [(folder, f"-tick{stop:04d}.png") for stop in stops]
    return timestamped_path(folder, "frost-demo", "", also).name


def write(offscreen: Offscreen, path: Path, done: str) -> int:
    """Write the frame to `path` and print `done` with the path; a path that cannot be
    written is a one-line error (exit 2), with nothing half-written left behind."""
    try:
        written = offscreen.snapshot(path)
    except OSError as err:
        error(f"cannot write {why(err, path)}")
        return 2
    print(done.format(written))
    return 0


def error(message) -> None:
    """A one-line error for the user, no traceback."""
    print(f"frost: error: {message}", file=sys.stderr)
