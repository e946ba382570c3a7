"""A page's WebSocket (docs/protocol.md): its Origin checked, a place among MAX_PAGES, the
hello, its messages applied one by one; a malformed one, or one over its limits, closes
that socket alone, in one line of the log."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from urllib.parse import urlsplit

from aiohttp import WSMessage, WSMsgType, web

from app.serve import MAX_PAGES, guard, protocol
from app.serve.appkeys import FEED, PAGE_LINES
from app.serve.feed import Feed
from app.serve.pages import CHANGE_RATE, ConnectedPage
from app.serve.turns import PageQueue

log = logging.getLogger("app.serve")

HEARTBEAT = 20.0  # s: a socket that answers no ping within half of it is closed
# s a page has, once the server ends, to answer its socket's close: until then what it sent
# before it saw the close is still read, and counted (`count_late`); then it is cut off.
CLOSE_S = 2.0
GOING_AWAY = 1001  # the close code of the server's end
ENDING = b"frost serve is ending"  # and its reason, which the page shows
# What a page's input sent once the server is ending is counted as, in the end's warning.
LATE_NAMES = {"touch": "touches", "melt": "melts"}  # (any other: "changes")


def same_origin(origin: str, host: str, scheme: str = "http") -> bool:
    """A WebSocket's Origin header names the scheme (http on the HTTP port, https on the
    HTTPS one), host and port the request was made to."""
    parts = urlsplit(origin)
    return parts.scheme == scheme and parts.netloc.lower() == host.lower()


async def socket(request: web.Request) -> web.WebSocketResponse:
    """GET /ws: a page's socket, from its hello to its close."""
    feed: Feed = request.app[FEED]
    origin = request.headers.get("Origin")
    if origin is not None and not same_origin(origin, request.host, request.scheme):
        raise web.HTTPForbidden(text="frost: the page's origin is not this server\n")
    # permessage-deflate for every page that asks (every browser does): a frosted pane's
    # snapshot goes as a third of its bytes (docs/protocol.md, "Compression").
    ws = web.WebSocketResponse(max_msg_size=protocol.MAX_INPUT_BYTES, heartbeat=HEARTBEAT,
                               compress=True, timeout=CLOSE_S)
    if len(feed.pages) >= MAX_PAGES:  # closed at once, with words the page can show (a 503
        await ws.prepare(request)      # reaches a browser's page as "connection lost")
        await ws.close(code=protocol.TRY_AGAIN_LATER,
                       message=f"{MAX_PAGES} pages are connected already".encode())
        return ws
    await ws.prepare(request)
    guard.untimed(request.transport)  # frames from now on, not request heads
    drained = Drained(ws, lambda data: count_late(feed, data))
    page = ConnectedPage(ws, f"{request.remote}:{id(ws) & 0xFFFF:04x}", feed.ask_redraw,
                         drained.wake)
    feed.pages.add(page)
    page.text(feed.hello())
    writer = asyncio.create_task(page.write())
    queue = feed.controls.turns.open()  # its commands, sent to the thread in turns
    lines = request.app[PAGE_LINES]
    lines.info("serve: page %s connected (%d pages)", page.name, len(feed.pages))
    try:
        async for msg in ws:
            if msg is WOKEN:  # the server's end (`ConnectedPage.end`)
                break
            problem = _handle_message(feed, page, queue, msg)
            if problem is not None:
                lines.info("serve: page %s closed: %s", page.name, problem.reason)
                await ws.close(code=problem.code, message=problem.reason.encode()[:120])
                break
        if page.ending and not ws.closed:  # the server's end: what the page sent until
            drained.counting = True         # it answers the close is read, and counted
            await ws.close(code=GOING_AWAY, message=ENDING)
    finally:
        page.close()
        feed.pages.discard(page)
        feed.controls.turns.close(queue)
        writer.cancel()
        page.gone.set()
    return ws


# The message `Drained.wake` hands the socket's handler in place of the page's next one.
WOKEN = WSMessage(WSMsgType.TEXT, "", "frost serve is ending")


class Drained:
    """A page's socket whose messages are all read by its handler, to the last, when the
    server ends: its handler woken from its wait for the next message (`wake`), then the
    frames aiohttp's `close` reads, and drops, while it waits for the page's own close,
    told to `seen` (each data frame's data) once `counting`. aiohttp has no hook for
    either: its queue of the socket's frames is wrapped (`_reader`, where aiohttp keeps
    it; tests/test_serve_ending.py fails the day aiohttp changes it)."""

    def __init__(self, ws: web.WebSocketResponse, seen: Callable[[str | bytes], None]):
        self.ws, self.seen, self.counting = ws, seen, False
        self.queue = getattr(ws, "_reader", None)
        if self.queue is not None:
            ws._reader = self  # type: ignore[assignment]

    def __getattr__(self, name: str):
        return getattr(self.queue, name)

    def wake(self) -> None:
        """The handler's next message is WOKEN (after those already queued); without the
        queue, the socket is closed at once (uncounted, as aiohttp closes it)."""
        if self.queue is not None:
            self.queue.feed_data(WOKEN, 0)
        elif not self.ws.closed:
            asyncio.ensure_future(self.ws.close(code=GOING_AWAY, message=ENDING))

    async def read(self):
        msg = await self.queue.read()  # type: ignore[union-attr]
        if self.counting and msg.type in (WSMsgType.TEXT, WSMsgType.BINARY) and msg is not WOKEN:
            self.seen(msg.data)
        return msg


def count_late(feed: Feed, data: str | bytes) -> None:
    """A page's message that came once the server was ending, none of it taken: counted
    in `feed.late` (a finger's message as one touch or melt; pings and lifted fingers not,
    nor what breaks the protocol)."""
    try:
        message = protocol.parse_input(data)
    except protocol.ProtocolError:
        return
    if message.kind == "ping" or message.kind in protocol.POINTER_KINDS and message.phase == "up":
        return
    feed.late[LATE_NAMES.get(message.kind, "changes")] += 1


def _handle_message(feed: Feed, page: ConnectedPage, queue: PageQueue,
                    msg) -> protocol.ProtocolError | None:
    """`_apply_message`, where a failure of the server's own (a bug met by one page's
    message) closes that page's socket alone (1011), in the one line its closing writes:
    aiohttp would log a traceback of 30 lines for each such message, a flood of them past
    any rate limit."""
    try:
        return _apply_message(feed, page, queue, msg)
    except Exception as err:
        log.debug("serve: page %s: handling its message failed", page.name, exc_info=True)
        return protocol.ProtocolError(f"the server failed on its message ({type(err).__name__}: "
                                      f"{str(err)[:60]})", protocol.INTERNAL_ERROR)


def _apply_message(feed: Feed, page: ConnectedPage, queue: PageQueue,
                   msg) -> protocol.ProtocolError | None:
    """Apply one message of a page; the error that closes its socket, if any."""
    if msg.type == WSMsgType.ERROR:
        return protocol.ProtocolError(f"socket error: {msg.data}"[:100], protocol.TOO_BIG)
    if msg.type not in (WSMsgType.TEXT, WSMsgType.BINARY):
        return None
    if feed.ending:  # nothing more is taken, and no pong says it was: counted for the warning
        count_late(feed, msg.data)
        return None
    if not page.bucket.take():
        return protocol.ProtocolError(f"over {protocol.RATE_TEXT} messages a second")
    try:
        message = protocol.parse_input(msg.data)
    except protocol.ProtocolError as err:
        return err
    if message.kind == "ping":
        page.text(protocol.text("pong", t=message.stamp, tick=feed.tick()))
    elif message.kind not in ("touch", "melt") and not page.changes.take():
        page.text(protocol.text("notice", text=f"{message.kind} refused: at most "
                                f"{CHANGE_RATE:g} changes a second"))
    else:
        feed.controls.handle(message, page.fingers,
                             lambda why: page.text(protocol.text("notice", text=why)), page.points,
                             queue)
    return None
