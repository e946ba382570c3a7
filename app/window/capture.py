"""What the window writes: screenshots (each with its own session file), the session on
exit, and requests for frost-map exports; every name new, every failure reported."""

from __future__ import annotations

import json
import logging
from collections.abc import Callable
from pathlib import Path

from app.images import save_png, timestamped_path
from app.simthread.thread import SimThread, Snapshot
from app.window.presenter import Presenter
from sim import Params
from sim.files import why

log = logging.getLogger("app.window")


class Capture:
    """Files of one window run, in the folders the command line named."""

    def __init__(self, thread: SimThread, presenter: Presenter, say: Callable[..., None],
                 screenshot_dir, session_dir):
        self.thread, self.presenter, self.say = thread, presenter, say
        self.screenshot_dir, self.session_dir = Path(screenshot_dir), Path(session_dir)
        self.session_path: Path | None = None  # this run's session file, made on first save
        self.screenshots: list[Path] = []
        self.names: set[str] = set()  # stems of screenshots and map folders asked for

    def save_session(self, snap: Snapshot | None, path: Path | None = None) -> Path | None:
        """The session up to the frame shown (`snap`) and the view it was shown with, to
        `path` (default: this run's file); replay it with `frost replay FILE`. OSError if it
        cannot be written (nothing half-written is left). This run's file is not written
        while the session has no event (None): it would replay bare glass."""
        log_ = self.thread.session(snap.steps, snap.events) if snap else self.thread.session(0, 0)
        log_.view = self.presenter.renderer.view()
        if path is None and not log_.events:
            log.info("session: no touch, melt or change to replay, so no session file")
            return None
        if path is None:
            self.session_path = self.session_path or timestamped_path(
                self.session_dir, "session", ".json")
            path = self.session_path
        log_.save(path)
        log.info("session: %s (%d events, %d steps)", path, len(log_.events), log_.steps)
        return path

    def screenshot(self, snap: Snapshot | None, params: Params) -> None:
        """The frame shown, as a PNG stating what made it (all from the snapshot shown and
        the renderer's view), and its own session file: replaying it ends on this frame."""
        self.presenter.render_phone()
        meta = {"params": json.dumps((snap.params if snap else params).as_dict()),
                "seed": str(self.thread.seed), "touches": json.dumps(snap.touches if snap else []),
                "tick": str(snap.stats.tick if snap else 0),
                "view": json.dumps(self.presenter.renderer.view())}
        path = self.fresh_name(".png")
        try:
            meta["session"] = str(self.save_session(snap, self.session_dir / f"{path.stem}.json"))
        except OSError as err:
            self.say(f"screenshot's session NOT saved: {why(err, path.stem + '.json')}",
                     logging.WARNING)
        try:
            path = save_png(self.presenter.read_phone(), path, meta)
        except OSError as err:
            self.say(f"screenshot NOT saved: {why(err, path)}", logging.WARNING)
            return
        self.screenshots.append(path)
        self.say(f"screenshot: {path}")

    def export_maps(self) -> None:
        """The maps of the next tick's frost, written by a worker that reports back."""
        folder = self.fresh_name("")
        self.thread.send("export", folder)
        self.say(f"frost maps: exporting to {folder}/")

    def fresh_name(self, suffix: str) -> Path:
        """A new name in the screenshot folder whose stem no screenshot, screenshot
        session, map folder or earlier request (written or failed) of this run has."""
        shots = self.screenshot_dir
        path = timestamped_path(shots, suffix=suffix, taken=self.names, also=(
            (shots, ".png"), (shots, ""), (self.session_dir, ".json")))
        self.names.add(path.stem)
        return path
