"""What the window writes: screenshots (each with its own session file), the session on
exit, and requests for frost-map exports; every name new, every failure reported."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from pathlib import Path

from app.images import frost_meta, save_png, timestamped_path
from app.simthread.thread import SimThread, Snapshot
from app.window.presenter import Presenter
from sim import Params
from sim.io.files import why
from sim.io.session import SessionLog

log = logging.getLogger("app.window")

# s: while the session changes, its file is saved this often, so a process killed at once
# (SIGKILL, the X server gone) loses at most this much of it.
AUTOSAVE_PERIOD = 3.0


class Capture:
    """Files of one window run, in the folders the command line named."""

    def __init__(self, thread: SimThread, presenter: Presenter, say: Callable[..., None],
                 screenshot_dir, session_dir):
        self.thread, self.presenter, self.say = thread, presenter, say
        self.screenshot_dir, self.session_dir = Path(screenshot_dir), Path(session_dir)
        self.session_path: Path | None = None  # this run's session file, made on first save
        self.screenshots: list[Path] = []
        self.names: set[str] = set()  # stems of screenshots and map folders asked for
        self.saved: tuple | None = None  # (steps, events, view) of this run's file
        self._autosave_next, self._autosave_failed = 0.0, False
        self._keeper: threading.Thread | None = None  # the autosave being written

    def keep_session(self, snapshot: Snapshot | None, now: float) -> None:
        """Save the session up to `snapshot` when it differs from the file and the last save
        is AUTOSAVE_PERIOD old (`now`, monotonic s), on a worker: a long session takes
        a tenth of a second to write, a frame must not wait for it. A failure is told
        once; the save at exit tells it again."""
        if snapshot is None or now < self._autosave_next or self._keeping():
            return
        self._autosave_next = now + AUTOSAVE_PERIOD  # looked at again then, changed or not
        session = self._session(snapshot)
        if not session.events or self.saved == (session.steps, len(session.events), session.view):
            return  # (no event: no file, as at exit)
        path = self._run_path()
        self.saved = None
        self._keeper = threading.Thread(target=self._keep, args=(session, path),
                                        name="frost-session", daemon=True)
        self._keeper.start()

    def _keeping(self) -> bool:
        return self._keeper is not None and self._keeper.is_alive()

    def wait_kept(self) -> None:
        """Until the autosave being written (if any) is done."""
        if self._keeper is not None:
            self._keeper.join()

    def _keep(self, session: SessionLog, path: Path) -> None:
        try:
            session.save(path)
        except OSError as err:
            if not self._autosave_failed:
                self.thread.notify(logging.WARNING, f"session NOT saved: {why(err, path)}")
            self._autosave_failed = True
            return
        self.saved = (session.steps, len(session.events), session.view)
        log.debug("session kept: %s (%d events, %d steps)", path, len(session.events),
                  session.steps)

    def save_session(self, snapshot: Snapshot | None, path: Path | None = None) -> Path | None:
        """The session up to the frame shown (`snapshot`) and the view it was shown with, to
        `path` (default: this run's file, once an autosave writing it is done); replay it
        with `frost replay FILE`. OSError if it cannot be written (nothing half-written).
        This run's file is not written while the session has no event (None): it would
        replay bare glass."""
        session = self._session(snapshot)
        if path is None and not session.events:
            log.info("session: no touch, melt or change to replay, so no session file")
            return None
        if path is None:
            self.wait_kept()
            path = self._run_path()
        session.save(path)
        log.info("session: %s (%d events, %d steps)", path, len(session.events), session.steps)
        return path

    def _session(self, snapshot: Snapshot | None) -> SessionLog:
        session = (self.thread.session(snapshot.steps, snapshot.events) if snapshot
                   else self.thread.session(0, 0))
        session.view = self.presenter.renderer.view()
        return session

    def _run_path(self) -> Path:
        """This run's session file, named at its first save."""
        self.session_path = self.session_path or timestamped_path(self.session_dir, "session",
                                                                  ".json")
        return self.session_path

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
