"""A page's WebSocket (docs/protocol.md): its Origin checked, a place among MAX_PAGES, the
hello, its messages applied one by one; a malformed one, or one over its limits, closes
that socket alone, in one line of the log."""

from __future__ import annotations

import asyncio
import logging
from urllib.parse import urlsplit

from aiohttp import WSMsgType, web

from app.serve import MAX_PAGES, guard, protocol
from app.serve.appkeys import FEED, PAGE_LINES
from app.serve.feed import Feed
from app.serve.pages import CHANGE_RATE, ConnectedPage
from app.serve.turns import PageQueue

log = logging.getLogger("app.serve")

HEARTBEAT = 20.0  # s: a socket that answers no ping within half of it is closed


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
                               compress=True)
    if len(feed.pages) >= MAX_PAGES:  # closed at once, with words the page can show (a 503
        await ws.prepare(request)      # reaches a browser's page as "connection lost")
        await ws.close(code=protocol.TRY_AGAIN_LATER,
                       message=f"{MAX_PAGES} pages are connected already".encode())
        return ws
    await ws.prepare(request)
    guard.untimed(request.transport)  # frames from now on, not request heads
    page = ConnectedPage(ws, f"{request.remote}:{id(ws) & 0xFFFF:04x}", feed.ask_redraw)
    feed.pages.add(page)
    page.text(feed.hello())
    writer = asyncio.create_task(page.write())
    queue = feed.controls.turns.open()  # its commands, sent to the thread in turns
    lines = request.app[PAGE_LINES]
    lines.info("serve: page %s connected (%d pages)", page.name, len(feed.pages))
    try:
        async for msg in ws:
            problem = _handle_message(feed, page, queue, msg)
            if problem is not None:
                lines.info("serve: page %s closed: %s", page.name, problem.reason)
                await ws.close(code=problem.code, message=problem.reason.encode()[:120])
                break
    finally:
        page.close()
        feed.pages.discard(page)
        feed.controls.turns.close(queue)
        writer.cancel()
    return ws


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
    if msg.type not in (WSMsgType.TEXT, WSMsgType.BINARY) or feed.ending:
        return None  # (ending: nothing more is taken, and no pong says it was)
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
