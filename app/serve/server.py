"""`frost serve`: the HTTP + WebSocket server (aiohttp) in front of one `Feed`.

Security (docs/phone.md): a token on every request when one is in force (403 without it),
the WebSocket's Origin must name the host asked, at most MAX_PAGES sockets, static files
only from their own folders, and a page's bad input closes its socket alone.
"""

from __future__ import annotations

import asyncio
import io
import ipaddress
import logging
import secrets
import statistics
import time
from pathlib import Path, PurePosixPath
from urllib.parse import urlsplit

from aiohttp import WSMsgType, web
from aiohttp.http_exceptions import HttpProcessingError

from app.backdrops import BACKDROPS, load_backdrop
from app.images import frost_meta
from app.resources import SHADER_DIR
from app.serve import MAX_PAGES, guard, protocol
from app.serve.feed import Feed
from app.serve.pages import CHANGE_RATE, Page, TokenBucket
from app.serve.session import SessionFiles

log = logging.getLogger("app.serve")

WEB_DIR = Path(__file__).resolve().parent.parent / "web"
HEARTBEAT = 20.0  # s: a socket that answers no ping within half of it is closed
TYPES = {".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript",
         ".css": "text/css", ".json": "application/json", ".png": "image/png",
         ".svg": "image/svg+xml", ".vert": "text/plain", ".frag": "text/plain",
         ".glsl": "text/plain", ".webmanifest": "application/manifest+json"}
FULL = 1013  # a socket's close code: try again later (every page's place is taken)
FEED = web.AppKey("feed", Feed)
TOKEN = web.AppKey("token", str)  # "" when none is in force
FILES = web.AppKey("files", SessionFiles)
BACKDROP_PNGS = web.AppKey("backdrops", dict)
STATS = web.AppKey("stats", asyncio.Task)
STATS_PERIOD = 10.0  # s between the log's stats lines
BAD_LOG_S = 10.0  # s: at most one line a while on requests refused as malformed
# Lines on pages connected and closed: a house of them at once, then one a PAGE_LOG_S.
PAGE_LOG_BURST, PAGE_LOG_S = 16, 10.0


class _BadRequestsInOneLine(logging.Filter):
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


BAD_REQUESTS = _BadRequestsInOneLine()


class Sparing:
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


PAGE_LINES = web.AppKey("page_lines", Sparing)


def make_app(feed: Feed, token: str | None = None, session_dir=None,
             web_dir: Path = WEB_DIR) -> web.Application:
    """The server's app: its routes, the token check, the feed started with it and stopped
    (the session written to `session_dir`, if given) when it is cleaned up."""
    app = web.Application(middlewares=[_token_check])
    if BAD_REQUESTS not in logging.getLogger("aiohttp.server").filters:
        logging.getLogger("aiohttp.server").addFilter(BAD_REQUESTS)
    BAD_REQUESTS.said_at, BAD_REQUESTS.unsaid = None, 0  # a new server says its first
    app[FEED], app[TOKEN] = feed, token or ""
    app[FILES] = SessionFiles(feed, session_dir)
    app[BACKDROP_PNGS] = {}
    app[PAGE_LINES] = Sparing()
    app.router.add_get("/", _folder(web_dir, "index.html"))
    app.router.add_get("/web/{path:.*}", _folder(web_dir))
    app.router.add_get("/shaders/{path:.*}", _folder(SHADER_DIR))
    app.router.add_get("/backdrops/{name}.png", _backdrop)
    app.router.add_get("/meta", _meta)
    app.router.add_get("/ws", _socket)
    app.on_startup.append(_start)
    app.on_shutdown.append(_close_pages)  # before aiohttp waits on the open handlers
    app.on_cleanup.append(_stop)
    return app


async def _start(app: web.Application) -> None:
    app[FEED].start(asyncio.get_running_loop())
    app[FILES].start()
    app[STATS] = asyncio.create_task(_log_stats(app[FEED], STATS_PERIOD))


async def _log_stats(feed: Feed, period: float) -> None:
    """A stats line in the log every `period` s, as the window logs one. Its rate counts
    the session's steps: a rebuild (a new preset) sets the tick back to 0."""
    loop = asyncio.get_running_loop()
    steps, since = feed.key[0], loop.time()
    while True:
        await asyncio.sleep(period)
        now, ticks = loop.time(), feed.key[0] - steps
        n = max(0, min(ticks, len(feed.tick_ms)))
        log.info("serve: %s", stats_line(now - since, ticks, list(feed.tick_ms)[-n:] if n else [],
                                         list(feed.sizes)[-n:] if n else [], len(feed.pages),
                                         bool(feed.latest and feed.latest.stats.paused)))
        steps, since = steps + ticks, now


def stats_line(seconds: float, ticks: int, tick_ms: list[float], sizes: list[int], pages: int,
               paused: bool) -> str:
    """`seconds` of serving in words: the simulation's rate (`ticks` advanced) and median
    tick (`tick_ms`), the pages connected and the median bytes a tick sent each (`sizes`)."""
    rate = "sim paused" if paused else f"sim {ticks / seconds:.1f} ticks/s"
    tick = f"tick median {statistics.median(tick_ms):.1f} ms" if tick_ms else "no tick"
    sent = f", {statistics.median(sizes) / 1000:.1f} kB a tick each" if sizes and pages else ""
    return f"stats ({seconds:.1f} s): {rate}, {tick}, {pages} page{'s' * (pages != 1)}{sent}"


async def _close_pages(app: web.Application) -> None:
    for page in list(app[FEED].pages):
        page.close()
        await page.ws.close(code=1001, message=b"frost serve is ending")


async def _stop(app: web.Application) -> None:
    feed: Feed = app[FEED]
    if STATS in app:
        app[STATS].cancel()
    await _close_pages(app)  # (a test client's cleanup comes without a shutdown)
    feed.thread.stop()
    feed.pump()  # the last ticks, for the session's file
    app[FILES].stop()


@web.middleware
async def _token_check(request: web.Request, handler):
    """The token, where one is in force; else (a server on loopback) a Host naming this
    machine: a page of another site whose name its DNS turns to 127.0.0.1 (DNS rebinding)
    sends its own name as Host and as Origin, and would pass the Origin check."""
    token = request.app[TOKEN]
    given = request.query.get("token", "")
    if token and not secrets.compare_digest(given.encode(), token.encode()):
        raise web.HTTPForbidden(text="frost: this server needs the token of the URL "
                                     "frost serve printed\n")
    host = request.headers.get("Host")
    if not token and host is not None and not loopback_name(host):
        raise web.HTTPForbidden(text="frost: this server answers only to this machine's "
                                     "names (127.0.0.1, localhost)\n")
    return await handler(request)


def loopback_name(host: str) -> bool:
    """Whether a request's Host header names this machine: localhost or a loopback
    address, any port."""
    try:
        name = urlsplit("//" + host).hostname
    except ValueError:  # an unclosed bracket
        return False
    if name == "localhost":
        return True
    try:
        return name is not None and ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


def inside(folder: Path, rel: str) -> Path | None:
    """The file `rel` names under `folder`, or None if it is not a file there (a path that
    climbs out with '..', is absolute, or is a link leading out)."""
    if not rel or "\\" in rel or "\0" in rel or rel.startswith("/"):
        return None
    if any(part in ("..", ".") for part in PurePosixPath(rel).parts):
        return None
    root = folder.resolve()
    try:
        path = (root / rel).resolve()
        return path if path.is_relative_to(root) and path.is_file() else None
    except OSError:  # a name too long for the file system, a loop of links
        return None


def _folder(folder: Path, name: str | None = None):
    """A handler serving the files of `folder` (the path's {path}, or always `name`)."""
    async def handler(request: web.Request) -> web.StreamResponse:
        rel = name or request.match_info["path"]
        path = inside(folder, rel)
        if path is None:
            raise web.HTTPNotFound(text=f"frost: no file {rel[:80]!r}\n")
        headers = {"Cache-Control": "no-cache"}
        if path.suffix in TYPES:
            headers["Content-Type"] = TYPES[path.suffix]
        return web.FileResponse(path, headers=headers)
    return handler


async def _meta(request: web.Request) -> web.Response:
    """What a page's screenshot states beside its own view (app.images.frost_meta's keys):
    the parameters, seed and touches of the frame published last."""
    feed: Feed = request.app[FEED]
    snap, thread = feed.latest, feed.thread
    meta = frost_meta("page", snap.params if snap else feed.controls.params, thread.seed,
                      snap.stats.tick if snap else 0, thread.touch_ticks(snap))
    return web.json_response(meta, headers={"Cache-Control": "no-cache"})


async def _backdrop(request: web.Request) -> web.Response:
    name, cache = request.match_info["name"], request.app[BACKDROP_PNGS]
    if name not in BACKDROPS:
        raise web.HTTPNotFound(text=f"frost: no backdrop {name[:40]!r}\n")
    if name not in cache:
        cache[name] = await asyncio.to_thread(_png, name)
    return web.Response(body=cache[name], content_type="image/png")


def _png(name: str) -> bytes:
    from PIL import Image
    out = io.BytesIO()
    Image.fromarray(load_backdrop(name)).save(out, "PNG")
    return out.getvalue()


def same_origin(origin: str, host: str) -> bool:
    """A WebSocket's Origin header names the host (and port) the request was made to."""
    parts = urlsplit(origin)
    return parts.scheme in ("http", "https") and parts.netloc.lower() == host.lower()


async def _socket(request: web.Request) -> web.WebSocketResponse:
    feed: Feed = request.app[FEED]
    origin = request.headers.get("Origin")
    if origin is not None and not same_origin(origin, request.host):
        raise web.HTTPForbidden(text="frost: the page's origin is not this server\n")
    ws = web.WebSocketResponse(max_msg_size=protocol.MAX_INPUT_BYTES, heartbeat=HEARTBEAT)
    if len(feed.pages) >= MAX_PAGES:  # closed at once, with words the page can show (a 503
        await ws.prepare(request)      # reaches a browser's page as "connection lost")
        await ws.close(code=FULL, message=f"{MAX_PAGES} pages are connected already".encode())
        return ws
    await ws.prepare(request)
    guard.untimed(request.transport)  # frames from now on, not request heads
    page = Page(ws, f"{request.remote}:{id(ws) & 0xFFFF:04x}", feed.ask_redraw)
    feed.pages.add(page)
    page.text(feed.hello())
    writer = asyncio.create_task(page.write())
    lines = request.app[PAGE_LINES]
    lines.info("serve: page %s connected (%d pages)", page.name, len(feed.pages))
    try:
        async for msg in ws:
            problem = _guarded_take(feed, page, msg)
            if problem is not None:
                lines.info("serve: page %s closed: %s", page.name, problem.reason)
                await ws.close(code=problem.code, message=problem.reason.encode()[:120])
                break
    finally:
        page.close()
        feed.pages.discard(page)
        writer.cancel()
    return ws


def _guarded_take(feed: Feed, page: Page, msg) -> protocol.ProtocolError | None:
    """`_take`, where a failure of the server's own (a bug met by one page's message) closes
    that page's socket alone (1011), in the one line its closing writes: aiohttp would log
    a traceback of 30 lines for each such message, a flood of them past any rate limit."""
    try:
        return _take(feed, page, msg)
    except Exception as err:
        log.debug("serve: page %s: handling its message failed", page.name, exc_info=True)
        return protocol.ProtocolError(f"the server failed on its message ({type(err).__name__}: "
                                      f"{str(err)[:60]})", protocol.INTERNAL_ERROR)


def _take(feed: Feed, page: Page, msg) -> protocol.ProtocolError | None:
    """Apply one message of a page; the error that closes its socket, if any."""
    if msg.type == WSMsgType.ERROR:
        return protocol.ProtocolError(f"socket error: {msg.data}"[:100], protocol.TOO_BIG)
    if msg.type not in (WSMsgType.TEXT, WSMsgType.BINARY):
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
                             lambda why: page.text(protocol.text("notice", text=why)), page.points)
    return None
