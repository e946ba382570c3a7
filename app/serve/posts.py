"""What the requests that change the frost over HTTP share (`POST /photo`, app/serve/photo.py;
`POST /weather`, app/serve/weather.py; docs/protocol.md): the Origin they must carry, their
refusals as one line of JSON, and the gap each remote address keeps between two of them.

A request that changes the server's state has a body and an Origin: an Origin naming the
Host it was sent to, with the scheme of the port (http on the HTTP port, https on the
HTTPS one), is required, as a page of another site can post to a server on loopback (no
token there) without reading its answer. A page is known by its remote address: a client
cannot choose another one for each try, as it could a cookie or a header.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field

from aiohttp import web

from app.serve.sockets import same_origin


@dataclass
class Gaps:
    """When each remote address last sent a request of one kind, and the seconds it must
    wait before the next."""

    gap: float
    last: dict[str, float] = field(default_factory=dict)  # remote address -> loop time

    def wait_left(self, remote: str, now: float) -> float:
        """Seconds before `remote` may send again (0: now); old entries forgotten."""
        if len(self.last) > 4096:
            self.last = {k: t for k, t in self.last.items() if now - t < self.gap}
        at = self.last.get(remote)
        return 0.0 if at is None else max(0.0, at + self.gap - now)

    def too_soon(self, remote: str, now: float, what: str) -> web.Response | None:
        """The 429 for `remote` (with Retry-After, whole seconds) if it sent its last `what`
        less than `gap` s before `now`, else None."""
        left = self.wait_left(remote, now)
        if left <= 0:
            return None
        wait = int(left) + 1
        return refusal(429, f"one {what} every {self.gap:g} s: try again in {wait} s", retry=wait)


def refusal(status: int, text: str, retry: int | None = None) -> web.Response:
    """A 4xx/5xx answer carrying {"error": text} (one line: the page shows it as it is);
    `retry`: the seconds its Retry-After says."""
    headers = {} if retry is None else {"Retry-After": str(retry)}
    return web.Response(status=status, text=json.dumps({"error": text}),
                        content_type="application/json", headers=headers)


def unread(status: int, text: str) -> web.Response:
    """`refusal` of a body the server will not read (none or too long): the connection
    closes after the answer (aiohttp drops what comes of the body meanwhile, for at most
    its lingering time, 10 s, so that the client gets the answer whole)."""
    response = refusal(status, text)
    response.force_close()
    return response


def origin_problem(request: web.Request) -> str | None:
    """Why `request`, which changes the server's state, is refused for its Origin, or None."""
    origin = request.headers.get("Origin")
    if origin is None:
        return "a request that changes the frost must carry an Origin (a browser's page sends one)"
    if not same_origin(origin, request.host, request.scheme):
        return f"the page's origin {origin[:60]!r} is not this server"
    return None


def head_refusal(request: web.Request, what: str, most: int,
                 too_long: Callable[[int], str]) -> web.Response | None:
    """The refusal of a POST for its head alone, else None: its Origin (403), its
    Content-Length missing (411: `what`, e.g. "a photo", must come with one) or over `most`
    bytes (413: `too_long(length)` says why)."""
    problem = origin_problem(request)
    if problem is not None:
        return refusal(403, problem)
    length = request.content_length
    if length is None:
        return unread(411, f"{what} must come with its Content-Length")
    if length > most:
        return unread(413, too_long(length))
    return None
