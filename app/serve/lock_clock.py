"""The lock screen's clock on the pages: each minute the simulation thread records (and each
new temperature outside, drawn under the time) is sent as the clock box's new pixels only
(`protocol.clock_message`, drawn and encoded on a worker), to every live page and to each
page that a snapshot starts."""

from __future__ import annotations

import io
import logging
from collections import deque
from collections.abc import Set

import numpy as np
from PIL import Image

from app.backdrops import LIVE, read_backdrop
from app.lockscreen import CLOCK_BOX, DEFAULT_MINUTE, clock_patch, outside_line
from app.serve import protocol
from app.serve.pages import ConnectedPage
from app.serve.workers import Workers
from app.simthread.thread import SimThread, Snapshot

log = logging.getLogger("app.serve")


class LockClock:
    """The minute the pages show over the lock screen, and its message."""

    def __init__(self, thread: SimThread, pages: Set[ConnectedPage], workers: Workers, kept: int):
        """`pages`, the feed's (live: read at each send); `kept`, how many messages' sizes
        are kept for the bench."""
        self.thread, self.pages, self.workers = thread, pages, workers
        self._face: tuple[str, str] | None = None  # the (minute, outside) asked for last
        self.message: tuple[tuple[str, str], bytes] | None = None  # the latest drawn
        self.sizes: deque[int] = deque(maxlen=kept)  # for the bench
        self._static: np.ndarray | None = None  # the static lock screen, read once

    def current(self) -> bytes | None:
        """The message of the minute shown, for a page a snapshot starts (None while the
        lock screen is not the backdrop, or before its first minute is drawn)."""
        return self.message[1] if self._face is not None and self.message else None

    def tell(self, snap: Snapshot, live: bool) -> None:
        """After a tick: the thread records the minutes over the lock screen (`show_clock`;
        `live`, whether it is the backdrop), and a minute (or a temperature outside) not sent
        yet is drawn and sent."""
        self.thread.show_clock("pages", live)
        if not live:
            self._face = None  # (sent again when the lock screen comes back)
            return
        # (the thread records a minute from its next tick)
        face = (snap.minute or DEFAULT_MINUTE, outside_line(snap.weather))
        if face == self._face:
            return
        self._face = face
        self.workers.run(self._draw, face, lambda message: self._drawn(face, message))

    def _draw(self, face: tuple[str, str]) -> bytes | None:
        """The clock message of `face`, (minute, outside) (any thread); None if drawing
        failed (logged)."""
        minute, outside = face
        try:
            if self._static is None:
                self._static = np.asarray(read_backdrop(LIVE))
            out = io.BytesIO()
            Image.fromarray(clock_patch(self._static, minute, outside)).save(out, "PNG",
                                                                          compress_level=6)
            return protocol.clock_message(CLOCK_BOX, minute, out.getvalue())
        except Exception:
            log.exception("serve: the lock screen's clock failed")
            return None

    def _drawn(self, face: tuple[str, str], message: bytes | None) -> None:
        """A minute's message drawn: to every live page, unless a newer minute was asked
        for meanwhile or the lock screen has gone."""
        if message is None or face != self._face:
            return
        self.message = (face, message)
        self.sizes.append(len(message))
        for page in self.pages:
            if not page.waiting:
                page.binary(message)
