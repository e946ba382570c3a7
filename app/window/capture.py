"""What the window writes: screenshots (each with its own session file), the session on
exit, and requests for frost-map exports; every name new, every failure reported."""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path

from app.images import frost_meta, save_png, timestamped_path
from app.session_keeper import SessionKeeper
from app.simthread.thread import SimThread, Snapshot
from app.window.presenter import Presenter
from sim import Params
from sim.io.files import why
from sim.io.session import SessionLog

log = logging.getLogger("app.window")


class Capture:
    """Files of one window run, in the folders the command line named."""

    def __init__(self, thread: SimThread, presenter: Presenter, say: Callable[..., None],
                 screenshot_dir, session_dir):
        self.thread, self.presenter, self.say = thread, presenter, say
        self.screenshot_dir, self.session_dir = Path(screenshot_dir), Path(session_dir)
        # this run's session file (a failed autosave told on the HUD, once)
        self.keeper = SessionKeeper(self.session_dir, log,
                                    lambda text: thread.notify(logging.WARNING, text))
        self.screenshots: list[Path] = []
        self.names: set[str] = set()  # stems of screenshots and map folders asked for

    @property
    def session_path(self) -> Path | None:
        """This run's session file, once saved."""
        return self.keeper.path

    def keep_session(self, snapshot: Snapshot | None, now: float) -> None:
        """The autosave (`SessionKeeper.keep`) of the session up to `snapshot` (`now`:
        monotonic s)."""
        if snapshot is not None:
            self.keeper.keep(lambda: self._session(snapshot), now)

    def save_session(self, snapshot: Snapshot | None, path: Path | None = None) -> Path | None:
        """The session up to the frame shown (`snapshot`) and the view it was shown with, to
        `path` (OSError if it cannot be written; nothing half-written); replay it with
        `frost replay FILE`. Without `path`: this run's file at the end
        (`SessionKeeper.finish`, which says what it did)."""
        session = self._session(snapshot)
        if path is None:
            return self.keeper.finish(session)
        session.save(path)
        log.info("session: %s (%d events, %d steps)", path, len(session.events), session.steps)
        return path

    def _session(self, snapshot: Snapshot | None) -> SessionLog:
        session = (self.thread.session(snapshot.steps, snapshot.events) if snapshot
                   else self.thread.session(0, 0))
        session.view = self.presenter.renderer.view()
        return session

    def screenshot(self, snapshot: Snapshot | None, params: Params) -> None:
        """The frame shown, as a PNG stating what made it (all from the snapshot shown and
        the renderer's view), and its own session file: replaying it ends on this frame."""
        self.presenter.render_phone()
        meta = frost_meta("window, key S", snapshot.params if snapshot else params, self.thread.seed,
                          snapshot.stats.tick if snapshot else 0, self.thread.touch_ticks(snapshot),
                          view=self.presenter.renderer.view())
        path = self.fresh_name(".png")
        try:
            meta["session"] = str(self.save_session(snapshot, self.session_dir / f"{path.stem}.json"))
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
