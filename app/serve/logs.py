"""The server's log kept to a person's scale while clients flood it (docs/phone-design.md,
Security): what a flood repeats thousands of times a second is said once, then at most a
line a while, each saying how many went unsaid."""

from __future__ import annotations

import logging
import time

from aiohttp.http_exceptions import HttpProcessingError

from app.serve.pages import TokenBucket

log = logging.getLogger("app.serve")

BAD_LOG_S = 10.0  # s: at most one line a while on requests refused as malformed
# Lines on pages connected and closed: a house of them at once, then one a PAGE_LOG_S.
PAGE_LOG_BURST, PAGE_LOG_S = 16, 10.0


class BadRequestsInOneLine(logging.Filter):
    """aiohttp logs a request it cannot parse (a line over 8 KiB) as an error with a
    traceback, so anyone could fill the terminal: one line instead, and of a flood of them
    (thousands a second) the first, then at most one a BAD_LOG_S with the count since."""

    def __init__(self):
        super().__init__()
        self.said_at: float | None = None  # time.monotonic() of the last line
        self.unsaid = 0  # refused since then

    def filter(self, record: logging.LogRecord) -> bool:
        err = record.exc_info[1] if record.exc_info else None
        if not isinstance(err, HttpProcessingError):
            return True
        now = time.monotonic()
        if self.said_at is not None and now - self.said_at < BAD_LOG_S:
            self.unsaid += 1
            return False
        more = f"; {self.unsaid} more refused since the last such line" if self.unsaid else ""
        record.msg, record.args, record.exc_info = "serve: a bad request refused (%s)%s", (
            " ".join(str(err).split())[:100], more), None
        record.levelno, record.levelname = logging.INFO, "INFO"
        self.said_at, self.unsaid = now, 0
        return True


BAD_REQUESTS = BadRequestsInOneLine()


def quiet_bad_requests() -> None:
    """aiohttp's lines on malformed requests through BAD_REQUESTS, which says its first
    anew (a new server's)."""
    server_log = logging.getLogger("aiohttp.server")
    if BAD_REQUESTS not in server_log.filters:
        server_log.addFilter(BAD_REQUESTS)
    BAD_REQUESTS.said_at, BAD_REQUESTS.unsaid = None, 0


class RateLimitedLog:
    """Log lines of one kind (pages connected and closed) for a person: every one while they
    come as a person's pages do, a few at a time; of a flood (a client opening sockets as fast
    as it can) at most one a PAGE_LOG_S, each saying how many went unsaid before it."""

    def __init__(self):
        self.bucket = TokenBucket(1 / PAGE_LOG_S, PAGE_LOG_BURST)
        self.unsaid = 0

    def info(self, msg: str, *args) -> None:
        if not self.bucket.take():
            self.unsaid += 1
            return
        if self.unsaid:
            msg, args = msg + " (%d such lines unsaid before it)", (*args, self.unsaid)
        log.info(msg, *args)
        self.unsaid = 0
