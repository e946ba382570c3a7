"""Connections a slow or hostile client cannot pile up (docs/phone-design.md, Security).

aiohttp waits for a request's head (its request line and headers) without end, and
keeps an idle connection an hour: a client that opens connections and never finishes a
head held one file descriptor each, and at Debian's default limit of 1 024 no page could
connect, even after they were gone. Here each connection is wrapped:

- its request's head must arrive in full (to the blank line) within HEAD_S seconds of its
  first byte, or of the connection for the first request; else the connection is closed;
- once the server has taken a page's WebSocket on it (`untimed`), it is no longer timed
  (a refused upgrade leaves it timed);
- at most MAX_CONNECTIONS are open at once: one more takes the place of the oldest idle
  one (kept alive, waiting for its next request), else of the oldest still waiting for its
  head, else of the oldest that is not a page's WebSocket; else it is closed as it comes.
  So a flood of them cannot lock a person's page out: neither connections that never finish
  a head (the person's head arrives and is answered long before its connection is the
  oldest unfinished) nor connections that ask and then idle, opened as fast as a client
  can (a person's connection, its head on its way, is never taken for one of them);
- a head longer than MAX_HEAD_BYTES is closed as its bytes pass the mark;
- an idle connection between requests is closed after IDLE_S (aiohttp's keep-alive).

Only `POST /photo` (app/serve/photo.py) and `POST /weather` (app/serve/weather.py) have a
body: a head's Content-Length bytes after it are passed on as they are, not read as heads,
and must arrive within BODY_S of the head's end, else the connection is closed; without a
Content-Length (a chunked body) all that follows is its body, under the same deadline (the
route answers 411 and closes).
Any other request has no body, so any byte after its head starts the next head.
"""

from __future__ import annotations

import asyncio
import logging
import re

from aiohttp import web

log = logging.getLogger("app.serve")

HEAD_S = 10.0
IDLE_S = 15.0
# 16 pages, each with a few files' connections, fit many times over.
MAX_CONNECTIONS = 256
# A page's heads are under 2 KiB; aiohttp keeps a head's lines until it is whole, up to
# 128 of 8 KiB each (1 MiB): 256 of them held 700 MB.
MAX_HEAD_BYTES = 64 * 1024
LOG_S = 10.0  # s: at most one line a while on connections closed to make room
# s the requests still open when the server ends are given to finish, then again once
# cancelled (aiohttp's shutdown_timeout, 60 s by default: a photo half sent held the exit
# a minute). The session is written before: nothing they could still do is kept.
SHUTDOWN_S = 0.5
END_OF_HEAD = b"\r\n\r\n"
# The routes with a body, and the time a body may take (a photo's few MB over a slow link).
BODY_PATHS = frozenset({b"/photo", b"/weather"})
BODY_S = 120.0
UNTIL_CLOSE = -1  # a body without a Content-Length: the rest of the connection
_LENGTH = re.compile(rb"\r\ncontent-length:[ \t]*([0-9]{1,18})[ \t]*(?=\r\n)", re.IGNORECASE)


def body_length(head: bytes) -> int:
    """The bytes of body that follow the head `head` (its request line and headers, up to
    the blank line): 0 but for a POST to one of BODY_PATHS (any query), its Content-Length, or
    UNTIL_CLOSE where it has none (or says it twice)."""
    line = head.split(b"\r\n", 1)[0].split(b" ")
    if len(line) < 2 or line[0] != b"POST" or line[1].split(b"?", 1)[0] not in BODY_PATHS:
        return 0
    found = _LENGTH.findall(b"\r\n" + head + b"\r\n")
    return int(found[0]) if len(found) == 1 else UNTIL_CLOSE


def awaits_request(handler: asyncio.Protocol) -> bool:
    """Whether aiohttp's handler of a connection waits for its next request (kept alive
    between two, or new), as aiohttp itself tells before it closes an idle connection
    (RequestHandler._process_keepalive). aiohttp has no public way to ask (its docs and
    issues offer none): this reads its private `_waiter`, here alone, and
    tests/test_serve_guard.py fails the day aiohttp changes it."""
    waiter = getattr(handler, "_waiter", None)
    return waiter is not None and not waiter.done()


def untimed(transport) -> None:
    """`transport` (a request's) carries a page's WebSocket from now on."""
    protocol = transport.get_protocol() if transport is not None else None
    if isinstance(protocol, Guarded):
        protocol.untimed()


class GuardedRunner(web.AppRunner):
    """An AppRunner whose sites hand every connection to a `Guarded` wrapper."""

    def __init__(self, app: web.Application, **kwargs):
        kwargs.setdefault("keepalive_timeout", IDLE_S)
        kwargs.setdefault("shutdown_timeout", SHUTDOWN_S)
        super().__init__(app, **kwargs)
        self.conns: dict[Guarded, None] = {}  # open ones, oldest first
        self.evicted = 0  # closed to make room for a newer one
        self.refused = 0  # closed as they came: every slot a page's
        self.timed_out = 0  # closed for a head not finished in HEAD_S
        self.too_long = 0  # closed for a head longer than MAX_HEAD_BYTES
        self.said: tuple[float, int] | None = None  # (when, evicted) of the last line on it

    @property
    def server(self):
        inner = super().server
        if inner is None:
            return None
        return lambda: Guarded(inner(), self)

    def admit(self, conn: Guarded) -> bool:
        """Whether `conn` gets a slot, an older one closed for it where all are taken."""
        if len(self.conns) >= MAX_CONNECTIONS:
            victim = next((c for c in self.conns if c.idle()), None) \
                or next((c for c in self.conns if c.timer is not None and not c.body), None) \
                or next((c for c in self.conns if not c.page), None)
            if victim is None:
                self.refused += 1
                return False
            self.evicted += 1
            self._say_evicted()
            del self.conns[victim]
            victim.close()
        self.conns[conn] = None
        return True

    def _say_evicted(self) -> None:
        """A line in the log on the first connection closed for another, then at most one a
        LOG_S (a flood opens thousands a second), each with the count since the last."""
        now = asyncio.get_running_loop().time()
        if self.said is not None and now - self.said[0] < LOG_S:
            return
        since = self.evicted - (self.said[1] if self.said else 0)
        log.warning("serve: %d connections open: the oldest idle or unfinished ones make room "
                    "for new ones (%d closed since the last such line, %d in all)",
                    MAX_CONNECTIONS, since, self.evicted)
        self.said = (now, self.evicted)


class Guarded(asyncio.Protocol):
    """aiohttp's protocol for one connection, behind the deadlines of the module doc."""

    def __init__(self, inner: asyncio.Protocol, runner: GuardedRunner):
        self.inner, self.runner = inner, runner
        self.transport: asyncio.Transport | None = None
        self.timer: asyncio.TimerHandle | None = None
        self.parts: list[bytes] = []  # the unfinished head's bytes so far
        self.head = 0  # their length
        self.tail = b""  # their last bytes (an end of head may straddle two reads)
        self.body = 0  # bytes of a body still to pass (UNTIL_CLOSE: all that follows)
        self.page = False  # a page's WebSocket: no longer timed
        self.served = False  # connection_made reached aiohttp

    def connection_made(self, transport) -> None:
        self.transport = transport
        if not self.runner.admit(self):
            transport.abort()
            return
        self.served = True
        self._start_timer()
        self.inner.connection_made(transport)

    def idle(self) -> bool:
        """Whether aiohttp waits for this connection's next request (kept alive between two),
        its head not begun."""
        return (self.served and not self.page and self.timer is None
                and awaits_request(self.inner))

    def close(self) -> None:
        self._stop_timer()
        if self.transport is not None:
            self.transport.abort()

    def data_received(self, data: bytes) -> None:
        if self.page or self._watch(data):
            self.inner.data_received(data)

    def _watch(self, data: bytes) -> bool:
        """Follow the heads (and the photo's body) in `data`: each head finished stops its
        timer, a body starts its own, a byte after them starts the next head's; False (the
        connection closed) if a head grew too long."""
        while data:
            if self.body:
                if self.body == UNTIL_CLOSE:
                    return True
                taken = min(self.body, len(data))
                self.body -= taken
                data = data[taken:]
                if not self.body:
                    self._stop_timer()
                continue
            if self.timer is None:
                self._start_timer()
            seen = self.tail + data
            end = seen.find(END_OF_HEAD)
            if end < 0:
                self.tail = seen[-(len(END_OF_HEAD) - 1):]
                self.parts.append(data)
                self.head += len(data)
                if self.head > MAX_HEAD_BYTES:
                    self.runner.too_long += 1
                    self.close()
                    return False
                return True
            self._stop_timer()
            cut = end - len(self.tail)  # where the end begins in `data` (< 0: in the tail)
            head = b"".join(self.parts) + data[:max(cut, 0)]
            head = head[:len(head) + cut] if cut < 0 else head
            self.parts, self.head, self.tail = [], 0, b""
            data = seen[end + len(END_OF_HEAD):]
            self.body = body_length(head)
            if self.body:
                self._start_timer(BODY_S)
        return True

    def untimed(self) -> None:
        """The connection is a page's WebSocket now: its bytes are frames, not heads."""
        self.page = True
        self._stop_timer()
        self.parts, self.head, self.tail, self.body = [], 0, b"", 0

    def _start_timer(self, seconds: float | None = None) -> None:
        loop = asyncio.get_running_loop()
        self.timer = loop.call_later(HEAD_S if seconds is None else seconds, self._expire)

    def _stop_timer(self) -> None:
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None

    def _expire(self) -> None:
        self.timer = None
        self.runner.timed_out += 1
        self.close()

    def eof_received(self):
        return self.inner.eof_received() if self.served else None

    def connection_lost(self, exc) -> None:
        self._stop_timer()
        self.runner.conns.pop(self, None)
        if self.served:
            self.inner.connection_lost(exc)

    def pause_writing(self) -> None:
        self.inner.pause_writing()

    def resume_writing(self) -> None:
        self.inner.resume_writing()
