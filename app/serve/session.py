"""The session file `frost serve` writes, as the window writes its own (app/window/capture.py):
every input of every page with its tick, replayable with `frost replay`."""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path

from app.images import timestamped_path
from app.serve.feed import Feed
from sim.io.files import why
from sim.io.session import SessionLog

log = logging.getLogger("app.serve")

AUTOSAVE_PERIOD = 3.0  # s, as the window's


class SessionFiles:
    """The session file of a serve run, as the window writes its own: kept every few
    seconds while it changes, and at the end; none without an event (nor without a
    folder: tests)."""

    def __init__(self, feed: Feed, folder):
        self.feed, self.folder = feed, None if folder is None else Path(folder)
        self.path: Path | None = None
        self.saved: tuple[int, int] | None = None
        self.task: asyncio.Task | None = None

    def start(self) -> None:
        if self.folder is not None:
            self.task = asyncio.create_task(self.keep())

    def stop(self) -> None:
        if self.task is not None:
            self.task.cancel()
        if self.folder is not None:
            self.save()

    def session(self) -> SessionLog:
        snap, thread = self.feed.latest, self.feed.thread
        session = thread.session(snap.steps, snap.events) if snap else thread.session(0, 0)
        session.view = self.feed.view()
        return session

    async def keep(self) -> None:
        while True:
            await asyncio.sleep(AUTOSAVE_PERIOD)
            session = self.session()
            if session.events and self.saved != (session.steps, len(session.events)):
                try:
                    await asyncio.to_thread(session.save, self._path())
                    self.saved = (session.steps, len(session.events))
                except OSError as err:
                    log.warning("session NOT saved: %s", why(err, self.path))

    def save(self) -> Path | None:
        session = self.session()
        if not session.events:
            log.info("session: no touch, melt or change to replay, so no session file")
            return None
        try:
            path = session.save(self._path())
        except OSError as err:
            log.warning("session NOT saved: %s", why(err, self.path))
            return None
        log.info("session: %s (%d events, %d steps)", path, len(session.events), session.steps)
        return path

    def _path(self) -> Path:
        assert self.folder is not None
        self.path = self.path or timestamped_path(self.folder, "session", ".json")
        return self.path
