"""The session file `frost serve` writes, as the window writes its own (one
`SessionKeeper`): every input of every page with its tick, replayable with `frost replay`."""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path

from app.serve.feed import Feed
from app.session_keeper import AUTOSAVE_PERIOD, SessionKeeper
from sim.io.session import SessionLog

log = logging.getLogger("app.serve")


class SessionFiles:
    """The session file of a serve run: kept every few seconds while it changes, and at
    the end; none without an event (nor without a folder: tests)."""

    def __init__(self, feed: Feed, folder):
        self.feed = feed
        self.keeper = SessionKeeper(folder, log)
        self.task: asyncio.Task | None = None
        self.stopped = False

    @property
    def folder(self) -> Path | None:
        return self.keeper.folder

    @folder.setter
    def folder(self, folder: Path | None) -> None:
        self.keeper.folder = folder

    def start(self) -> None:
        if self.folder is not None:
            self.task = asyncio.create_task(self.keep())

    def stop(self) -> None:
        """The autosave ends; the session is written (after the save in flight, if any).
        Once: the server's end may come twice (its signal, then its cleanup)."""
        if self.stopped:
            return
        self.stopped = True
        if self.task is not None:
            self.task.cancel()
        self.keeper.finish(self.session())

    def session(self) -> SessionLog:
        snap, thread = self.feed.latest, self.feed.thread
        session = thread.session(snap.steps, snap.events) if snap else thread.session(0, 0)
        session.view = self.feed.view()
        return session

    async def keep(self) -> None:
        while True:
            await asyncio.sleep(AUTOSAVE_PERIOD)
            self.keeper.keep(self.session)
