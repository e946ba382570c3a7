"""The snapshot a page starts from, kept for the pages to come.

A page that connects or resyncs needs the whole frost: a snapshot. The live ice is copied
on the simulation thread between two ticks (`SimThread.between_ticks`: a millisecond,
while nothing changes it), with the height grid as the pages hold it then, and tagged with
the (steps, events) of the tick it follows; its features are drawn from the copy on a
worker, and the snapshot serves every page that asks for one while the ticks published
since it are all still kept (SINCE_TICKS, SINCE_BYTES): each page gets the snapshot, then
those ticks. Drawn on the simulation thread for every page, a client opening sockets as
fast as it could had a snapshot drawn every tick (25-60 ms each) and halved everyone's
tick rate.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Set
from dataclasses import dataclass, field

import numpy as np

from app.serve import protocol
from app.serve.pages import ConnectedPage
from app.serve.workers import Workers
from app.simthread.thread import SimThread
from sim import Params
from sim.look.geometry import IceCopy, feature_scale, live_features

log = logging.getLogger("app.serve")

# A snapshot serves new pages while the ticks since it are kept: at most this many ticks
# with changes (2 s of growth) and bytes (a page that far behind would be resynced). While
# they add up to no more than the snapshot itself (or SINCE_LEAST bytes), a page never
# loads more than twice what a fresh one costs it; past that a new one is drawn for the
# next page, but not within REDRAW_GAP of the last drawing (a client opening sockets as
# fast as it could on the finest grid had one drawn every second).
SINCE_TICKS = 50
SINCE_BYTES = 6 << 20
SINCE_LEAST = 256 << 10
REDRAW_GAP = 2.0  # s

Moment = tuple[int, int]  # (steps, events) of a tick


@dataclass
class Kept:
    """A snapshot drawn, kept for the pages to come."""

    moment: Moment  # of the tick it shows
    parts: list[bytes]
    since: int = 0  # bytes of the ticks published since it
    at: float = field(default_factory=time.monotonic)  # when it was drawn

    def worth(self) -> bool:
        """Whether it and the ticks since cost a page less than twice a fresh snapshot."""
        return self.since <= max(sum(map(len, self.parts)), SINCE_LEAST)


@dataclass(frozen=True)
class Copied:
    """The ice copied between two ticks, for a snapshot (`Snapshots`)."""

    moment: Moment  # of the tick it follows
    ice: IceCopy
    heights: np.ndarray  # the height grid as the pages held it then (half floats, flat)
    params: Params


class Snapshots:
    """The snapshot cache: copies asked of the thread, drawn on a worker, kept with the
    ticks published since, and served to the pages waiting for one."""

    def __init__(self, thread: SimThread, encoder: protocol.Encoder, pages: Set[ConnectedPage],
                 workers: Workers, starting: Callable[[], tuple[str, bytes | None]]):
        """`pages`, the feed's (live); `starting`, what a page a snapshot starts gets after
        it: the state message and the lock screen's clock message (or None)."""
        self.thread, self.encoder, self.pages, self.workers = thread, encoder, pages, workers
        self._starting = starting
        self.redraws = 0  # snapshots drawn
        self._want_copy = threading.Event()  # a copy of the ice is asked for and not made
        self._lock = threading.Lock()
        self._copied: Copied | None = None  # made on the thread, not drawn yet
        self._drawing = False
        # The snapshot that serves new pages, and the messages of every tick published
        # lately (moment, messages).
        self.kept: Kept | None = None
        self._since: deque[tuple[Moment, list[bytes]]] = deque()
        self._since_bytes = 0
        self._dropped_to: Moment = (-1, -1)  # the newest tick dropped from `_since`

    def ask_redraw(self) -> None:
        """A snapshot of the whole frost for the pages waiting, at the next pump: the one
        kept, while the ticks since it are and it is worth loading (or was drawn within
        REDRAW_GAP); else the ice is copied between the next two ticks (once, however
        often it is asked meanwhile) and drawn."""
        kept = self.kept
        if kept is not None and (kept.worth() or time.monotonic() - kept.at < REDRAW_GAP):
            return  # (served at the next pump)
        self.kept = None
        if not self._want_copy.is_set() and not self._drawing:
            self._want_copy.set()
            self.thread.between_ticks(self._copy_ice)

    def pumped(self) -> None:
        """At each pump: the copy made since drawn, the kept snapshot served."""
        self._draw_copied()
        if self.kept is not None:
            self._serve()

    def _copy_ice(self) -> None:
        """The live ice and heights copied, between two ticks (`SimThread.between_ticks`)."""
        self._want_copy.clear()
        timeline = self.thread.timeline
        try:
            copied = Copied((timeline.steps, len(timeline.events)), IceCopy.of(timeline.sim),
                            timeline.geometry.heights.ravel().astype(np.float16), timeline.params)
        except Exception:  # (the thread may have died in its tick)
            log.exception("serve: the copy of the frost failed")
            return
        with self._lock:
            self._copied = copied

    def keep(self, moment: Moment, messages: list[bytes]) -> None:
        """A tick's messages kept for the pages a snapshot will start (the oldest dropped
        beyond SINCE_TICKS or SINCE_BYTES, and with them the snapshot older than they)."""
        size = sum(map(len, messages))
        self._since.append((moment, messages))
        self._since_bytes += size
        while len(self._since) > SINCE_TICKS or self._since_bytes > SINCE_BYTES:
            self._dropped_to, old = self._since.popleft()
            self._since_bytes -= sum(map(len, old))
        kept = self.kept
        if kept is not None:
            kept.since += size
            if self._dropped_to > kept.moment:
                self.kept = None  # (a page it started would miss a tick)
                if any(page.idle_waiting() for page in self.pages):
                    # One told to wait for it at this pump (it asked while it was kept):
                    # drawn anew, or that page waits after its hello for good.
                    self.ask_redraw()

    def _draw_copied(self) -> None:
        """Draw the copy made between two ticks, if any: on a worker while serving (the
        loop and the simulation go on), here otherwise (a test's pump)."""
        with self._lock:
            copied, self._copied = self._copied, None
        if copied is None:
            return
        self._drawing = True
        self.workers.run(self._draw, copied, lambda parts: self._drawn(copied, parts))

    def _draw(self, copied: Copied) -> list[bytes] | None:
        """The snapshot's messages, of the copied ice and heights (any thread); None if
        drawing failed (said in the log)."""
        params = copied.params
        try:
            features = live_features(copied.ice, params)
            return self.encoder.snapshot(copied.ice.tick, features, params.look,
                                         feature_scale(params), heights=copied.heights)
        except Exception:
            log.exception("serve: the snapshot of the frost failed")
            return None

    def _drawn(self, copied: Copied, parts: list[bytes] | None) -> None:
        """A snapshot drawn: it serves the pages waiting, and those to come while the ticks
        since it are kept; one whose next ticks were dropped meanwhile is copied anew."""
        self._drawing = False
        if parts is None:
            return
        self.redraws += 1
        if self._dropped_to > copied.moment:
            self.ask_redraw()
            return
        self.kept = Kept(copied.moment, parts, sum(map(len, self._since_after(copied.moment))))
        self._serve()

    def _since_after(self, moment: Moment) -> list[bytes]:
        """The messages of the ticks kept that came after `moment`."""
        return [m for at, messages in self._since if at > moment for m in messages]

    def _serve(self) -> None:
        """The kept snapshot and the ticks since it, to every page waiting for one."""
        assert self.kept is not None
        waiting = [page for page in self.pages if page.idle_waiting()]
        if not waiting:
            return
        moment, parts = self.kept.moment, self.kept.parts
        since = self._since_after(moment)
        state, clock = self._starting()
        for page in waiting:
            page.start(parts, state, since)
            if clock is not None:  # (a resync may have dropped the minute's message)
                page.binary(clock)
