"""This run's session file, kept as the window and `frost serve` both keep it: saved every
AUTOSAVE_PERIOD while it changes (so a process killed at once, by SIGKILL or a lost
display, loses at most that much), each save written by a worker (a long session takes a
tenth of a second to write: a frame or the server's event loop must not wait for it), and
once more at the end, after the save in flight, so the file ends with the last state."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from pathlib import Path

from app.images import timestamped_path
from sim.io.files import why
from sim.io.session import SessionLog

# s between two looks at whether the session changed since its file was written.
AUTOSAVE_PERIOD = 3.0


def _what(session: SessionLog) -> tuple:
    """What a file holds of a session: its steps, its events and the view it was shown with."""
    return (session.steps, len(session.events), session.view)


class SessionKeeper:
    """The session file of one run in `folder` (None: no file, as in tests), named at its
    first save. `warn(text)` tells the person of a failed autosave (once: the save at the
    end tells it again); `log` takes the lines of the final save."""

    def __init__(self, folder, log: logging.Logger, warn: Callable[[str], None] | None = None,
                 clock: Callable[[], float] = time.monotonic):
        self.folder = None if folder is None else Path(folder)
        self.log, self.clock = log, clock
        self.warn = warn or (lambda text: log.warning("%s", text))
        self.path: Path | None = None
        self.saved: tuple | None = None  # `_what` of the file written last
        self._next = 0.0  # (clock) when the session is looked at again
        self._failed = False
        self._writer: threading.Thread | None = None

    def keep(self, make: Callable[[], SessionLog], now: float | None = None) -> None:
        """The autosave: when AUTOSAVE_PERIOD has passed since the last look (`now`, default
        the clock's) and no save is being written, `make()` the session and, if it has
        events and differs from the file, write it on a worker. Returns at once."""
        now = self.clock() if now is None else now
        if self.folder is None or now < self._next or self.writing():
            return
        self._next = now + AUTOSAVE_PERIOD  # looked at again then, changed or not
        session = make()
        if not session.replayable() or self.saved == _what(session):
            return  # (no event: no file, as at the end)
        path = self._run_path()
        self.saved = None
        self._writer = threading.Thread(target=self._write, args=(session, path),
                                        name="frost-session", daemon=True)
        self._writer.start()

    def writing(self) -> bool:
        return self._writer is not None and self._writer.is_alive()

    def wait(self) -> None:
        """Until the save being written (if any) is done."""
        if self._writer is not None:
            self._writer.join()

    def finish(self, session: SessionLog) -> Path | None:
        """The save at the end: once the save in flight is done (else it could land after
        this one and replace it), `session` written to this run's file and said in the log;
        a failure said too (None). No file while it has no event: it would replay bare glass."""
        if self.folder is None:
            return None
        if not session.replayable():  # (the clock's minutes alone: nothing to replay)
            self.log.info("session: no touch, melt or change to replay, so no session file")
            return None
        self.wait()
        try:
            path = session.save(self._run_path())
        except OSError as err:
            self.log.warning("session NOT saved: %s", why(err, self.path))
            return None
        self.saved = _what(session)
        self.log.info("session: %s (%d events, %d steps)", path, len(session.events), session.steps)
        return path

    def _write(self, session: SessionLog, path: Path) -> None:
        try:
            session.save(path)
        except OSError as err:
            if not self._failed:
                self.warn(f"session NOT saved: {why(err, path)}")
            self._failed = True
            return
        self.saved = _what(session)
        self.log.debug("session kept: %s (%d events, %d steps)", path, len(session.events),
                       session.steps)

    def _run_path(self) -> Path:
        """This run's session file, named at its first save."""
        assert self.folder is not None
        self.path = self.path or timestamped_path(self.folder, "session", ".json")
        return self.path
