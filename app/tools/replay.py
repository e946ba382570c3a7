"""`frost replay FILE.json` with no window: a recorded session drawn again offscreen,
bit for bit, and written as a PNG."""

from __future__ import annotations

import dataclasses
import logging
import sys
from pathlib import Path

from app.backdrops import BACKDROPS
from app.images import timestamped_path
from app.photos import is_photo, photo_file, store_of
from app.tools.offscreen import Offscreen, make_context
from app.tools.progress import Progress
from app.tools.render_png import DEFAULT_FOLDER, error, write
from sim import Params
from sim.io.session import DEFAULT_BACKDROP, SessionError, SessionLog
from sim.screen import HEIGHT, WIDTH

log = logging.getLogger("app.replay")


def load_session(path) -> SessionLog:
    """The session file `path` for this 760x1280 screen; SessionError saying why not."""
    log_ = SessionLog.load(path)
    if (log_.width, log_.height) != (WIDTH, HEIGHT):
        raise SessionError(f"{path}: a {log_.width}x{log_.height} session; this app renders "
                           f"{WIDTH}x{HEIGHT}")
    if not log_.bit_for_bit():
        print(f"{path}: a session grown on a {log_.source} (its own random numbers): replayed "
              "with the same touches, parameters and backdrops, not bit for bit", file=sys.stderr)
    return log_


def under(log_: SessionLog, params: Params, name: str) -> SessionLog:
    """The session `log_` as if run with `params` (the set in file `name`): its first
    parameters and each of its parameter changes become `params` with the look the session
    had there, so every change still rebuilds (or only redraws, a change of look) where it
    did, and touches, melts and clears keep their ticks. Logged: it is not the session."""
    events = [{**e, "params": _with_look(params, e["params"])} if e["kind"] == "params" else e
              for e in log_.events]
    changes = sum(e["kind"] == "params" for e in events)
    log.info("replay: what if: the session's input under %s's parameters, not its own (its "
             "first parameters and %d later changes replaced; its looks kept)", name, changes)
    return dataclasses.replace(log_, params=_with_look(params, log_.params), events=events)


def _with_look(params: Params, recorded: dict) -> dict:
    return params.replace(look=recorded.get("look", Params.look)).as_dict()


def start_view(log_: SessionLog, background: str | None = None) -> dict | None:
    """The view a replay of `log_` starts with: the session's (its light, its toggles),
    with `background` if one is imposed; a session with backdrop events (version 11 on)
    starts on the default one, and its events change it (its view's background is the
    last one shown); one without shows its view's background throughout."""
    if background is not None:
        return {**(log_.view or {}), "background": background}
    if log_.view is not None and any(e["kind"] == "backdrop" for e in log_.events):
        return {**log_.view, "background": DEFAULT_BACKDROP}
    return log_.view


def missing_photo(log_: SessionLog, store: Path) -> str | None:
    """Why a backdrop the session shows cannot be drawn (the first that is neither a
    built-in nor a photo, or a photo whose file is not in `store`, named), or None. A
    name is never taken as a path."""
    names = [e["name"] for e in log_.events if e["kind"] == "backdrop"]
    for name in dict.fromkeys(names):
        if not is_photo(name) and name not in BACKDROPS:
            return (f"backdrop {name}: neither a built-in ({', '.join(BACKDROPS)}) nor a "
                    "photo's name (photo- and 32 hex digits)")
        if is_photo(name) and not photo_file(name, store).is_file():
            return f"backdrop {name}: its file {photo_file(name, store)} is missing"
    return None


def replay_offscreen(ctx, log_: SessionLog, steps: int | None = None,
                     progress: Progress | None = None, background: str | None = None,
                     photos: Path | None = None) -> Offscreen:
    """An Offscreen that went through `log_` for `steps` steps (default: as recorded),
    shown with the session's view and backdrops (the photos found in `photos`), or
    `background` throughout if given."""
    offscreen = Offscreen(ctx, Params(**log_.params), log_.seed, start_view(log_, background),
                          log_.version, photos=photos, backdrops=background is None)
    offscreen.progress = progress
    steps = log_.steps if steps is None else steps
    if offscreen.grow(steps, log_.events) < len(log_.events):
        print(f"frost: warning: events after step {steps} were not applied", file=sys.stderr)
    return offscreen


def refuse(problem) -> int:
    """The session named on the command line cannot be replayed: a one-line error that
    points to the help, as the command line's other mistakes do; the exit status (2)."""
    error(f"{problem} (see frost replay --help)")
    return 2


def run(args, what_if: Params | None = None) -> int:
    """`frost replay FILE.json` when headless (under `what_if`'s parameters if given, see
    `under`); returns the exit status."""
    try:
        log_ = load_session(args.replay)
        if what_if is not None:
            log_ = under(log_, what_if, args.params_file)
        photos = store_of(Path(args.replay).parent)
        missing = None if args.background else missing_photo(log_, photos)
        if missing:
            raise SessionError(f"{args.replay}: cannot replay: {missing}")
        ctx = make_context()
    except SessionError as err:
        return refuse(err)
    except RuntimeError as err:  # no OpenGL context: not the command line's mistake
        error(err)
        return 1
    progress = Progress(log_.steps if args.ticks is None else args.ticks)
    try:
        offscreen = replay_offscreen(ctx, log_, args.ticks, progress, args.background, photos)
    except ValueError as err:  # an event the simulation refuses
        return refuse(f"{args.replay}: cannot replay: {err}")
    timeline = offscreen.timeline
    offscreen.meta = {"session": str(args.replay), "replayed_steps": timeline.steps}
    if what_if is not None:
        offscreen.meta["what_if_params"] = str(args.params_file)
    path = Path(args.out) if args.out else timestamped_path(DEFAULT_FOLDER)
    return write(offscreen, path, f"replayed {args.replay}: {timeline.steps} steps, "
                                  f"{len(timeline.events)} events; wrote {{}}")
