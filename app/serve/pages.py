"""One connected page: its bounded outgoing queue and the task that writes it, its input
rate limit. A page that falls behind is dropped to a resync (its queue cleared, a snapshot
sent again); it never makes the tick or another page wait."""

from __future__ import annotations

import asyncio
import logging
import time
from collections import deque
from collections.abc import Callable, Sequence

from aiohttp import web

from app.serve import protocol

log = logging.getLogger("app.serve")

# A live page more than this many ticks (2 s) behind, or with this many bytes queued (a
# snapshot's 3 MB at most and more than a second of the largest deltas), is resynced.
MAX_BEHIND_TICKS = 50
MAX_BEHIND_BYTES = 6 << 20
# Input: at most RATE messages a second, in bursts of at most BURST (a token bucket).
RATE, BURST = float(protocol.RATE_TEXT), float(protocol.RATE_TEXT)
# Changes (a preset, look, backdrop, key, pause, step or clear) at most CHANGE_RATE a second
# in bursts of CHANGE_BURST: each may regrow the whole frost, and the simulation thread
# applies one a tick at best; more are refused with a notice (a person never needs more).
CHANGE_RATE, CHANGE_BURST = 5.0, 10.0
# Touches and melts a page's fingers may leave, at most POINT_RATE a second in bursts of
# POINT_BURST: a finger swept at 5 000 px/s leaves about 420 melts of the default warm finger
# (12 px apart) or 180 seeds (4 hc apart); a page asking for more (each a session event) has
# the rest of its path skipped, the finger going on from where it is.
POINT_RATE, POINT_BURST = 500.0, 500.0


class TokenBucket:
    """Takes one token per message; refills at `rate` a second up to `burst`."""

    def __init__(self, rate: float = RATE, burst: float = BURST, clock=time.monotonic):
        self.rate, self.burst, self.clock = rate, burst, clock
        self.tokens, self.at = burst, clock()

    def take(self) -> bool:
        return self.grant(1) == 1

    def grant(self, wanted: int) -> int:
        """Takes up to `wanted` tokens; how many it took."""
        now = self.clock()
        self.tokens = min(self.burst, self.tokens + (now - self.at) * self.rate)
        self.at = now
        granted = min(wanted, int(self.tokens))
        self.tokens -= granted
        return granted


class ConnectedPage:
    """A WebSocket's outgoing side. States: waiting (for a snapshot; gets no deltas) and
    live. `ask_snapshot` is called when it waits with nothing left to write."""

    def __init__(self, ws: web.WebSocketResponse, name: str, ask_snapshot: Callable[[], None],
                 wake: Callable[[], None] = lambda: None):
        self.ws, self.name, self.ask_snapshot, self.wake = ws, name, ask_snapshot, wake
        self.queue: deque[tuple[str | bytes, bool]] = deque()  # (message, ends a tick)
        self.behind_ticks = self.behind_bytes = 0
        self.waiting, self.busy, self.closed = True, False, False
        self.resyncs = 0
        self.bucket = TokenBucket()
        self.changes = TokenBucket(CHANGE_RATE, CHANGE_BURST)
        self.points = TokenBucket(POINT_RATE, POINT_BURST)
        self.fingers: dict[tuple[str, int], tuple[float, float]] = {}  # a drag's last spot
        self._ready = asyncio.Event()
        # The server's end: `end` called; `gone` is set once the socket's handler is over.
        self.ending, self.gone = False, asyncio.Event()

    def end(self) -> None:
        """The server ends: the page's socket is closed by its handler, woken by `wake`
        (app/serve/sockets.py), which reads, and counts, what the page sent until it
        answers the close."""
        if not self.ending:
            self.ending = True
            self.wake()

    def text(self, message: str) -> None:
        self._put(message, False)

    def binary(self, message: bytes) -> None:
        """A binary message outside the ticks (the lock screen's clock)."""
        self._put(message, False)

    def tick(self, messages: list[bytes]) -> None:
        """One tick's messages, unless the page waits for a snapshot; a page too far behind
        is resynced instead."""
        if self.waiting or self.closed:
            return
        if self.behind_ticks >= MAX_BEHIND_TICKS or self.behind_bytes >= MAX_BEHIND_BYTES:
            self.resync("fell behind")
            return
        for i, m in enumerate(messages):
            self._put(m, i == len(messages) - 1)

    def resync(self, reason: str) -> None:
        """Drop what is queued; a snapshot follows once the message being written is out."""
        log.info("serve: page %s resyncs (%s)", self.name, reason)
        self.queue.clear()
        self.behind_ticks = self.behind_bytes = 0
        self.waiting, self.resyncs = True, self.resyncs + 1
        self.text(protocol.text("resync", reason=reason))

    def start(self, parts: list[bytes], state: str, since: Sequence[bytes] = ()) -> None:
        """The snapshot (its parts), the state now and the ticks' messages published since
        the snapshot's tick (`since`): the page is live from here on."""
        self.waiting = False
        self.text(state)
        for p in (*parts, *since):
            self._put(p, False)

    def idle_waiting(self) -> bool:
        """Waiting for a snapshot with nothing being written: ready for one."""
        return self.waiting and not self.busy and not self.queue and not self.closed

    def _put(self, message: str | bytes, ends_tick: bool) -> None:
        self.queue.append((message, ends_tick))
        self.behind_ticks += ends_tick
        self.behind_bytes += len(message)
        self._ready.set()

    async def write(self) -> None:
        """Send the queue as it fills, until the socket closes."""
        while not self.closed:
            if self.ws.closed:  # closing: nothing may follow its close frame
                self.closed = True
                break
            if not self.queue:
                self._ready.clear()  # (before asking: a kept snapshot is queued at once)
                if self.waiting:
                    self.ask_snapshot()
                await self._ready.wait()
                continue
            message, ends_tick = self.queue.popleft()
            self.behind_ticks -= ends_tick
            self.behind_bytes -= len(message)
            self.busy = True
            try:
                await self._send(message)
            except (ConnectionError, RuntimeError):
                self.closed = True
            except Exception:
                log.exception("serve: page %s: writing failed", self.name)
                self.closed = True
            finally:
                self.busy = False

    async def _send(self, message: str | bytes) -> None:
        """Send one message. The send runs as a task of its own, which the writer awaits
        shielded: a browser's socket compresses (permessage-deflate), and aiohttp
        compresses a large message in a shielded task of its own too; the writer cancelled
        mid-send (its page gone) would leave that task's failure ("Cannot write to closing
        transport") unretrieved, and asyncio would print it as a traceback. Here the send
        runs on to its end and `_retrieved` takes whatever it met."""
        sending = asyncio.ensure_future(self._send_now(message))
        sending.add_done_callback(_retrieved)
        await asyncio.shield(sending)

    async def _send_now(self, message: str | bytes) -> None:
        # (The task starts a moment after it is made: nothing may follow a close frame
        # sent meanwhile, so the socket is asked again in the step that writes.)
        if self.ws.closed:
            raise ConnectionResetError("the socket closed")
        if isinstance(message, bytes):
            await self.ws.send_bytes(message)
        else:
            await self.ws.send_str(message)

    def close(self) -> None:
        self.closed = True
        self._ready.set()


def _retrieved(task: asyncio.Future) -> None:
    """A send's end, seen: a page gone mid-send is no error (its close is logged)."""
    if not task.cancelled():
        task.exception()

