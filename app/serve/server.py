"""`frost serve`'s aiohttp app in front of one `Feed`: its routes (routes.py: HTTP,
sockets.py: a page's WebSocket), the feed started and stopped with it, its stats line.

Security (docs/phone-design.md): a token on every request when one is in force (403 without it),
the WebSocket's Origin must name the host asked, at most MAX_PAGES sockets, static files
only from their own folders, and a page's bad input closes its socket alone.
"""

from __future__ import annotations

import asyncio
import logging
import statistics
from pathlib import Path

from aiohttp import web

from app import photos
from app.resources import SHADER_DIR
from app.serve import install, photo, routes, sockets
from app.serve import weather as weather_route
from app.serve.appkeys import BACKDROP_PNGS, CA_DER, FEED, FILES, PAGE_LINES, PORTS, STATS, TOKEN
from app.serve.feed import Feed
from app.serve.logs import RateLimitedLog, quiet_bad_requests
from app.serve.session_files import SessionFiles

log = logging.getLogger("app.serve")

STATS_PERIOD = 10.0  # s between the log's stats lines


def make_app(feed: Feed, token: str | None = None, session_dir=None,
             web_dir: Path = routes.WEB_DIR, ca_der: bytes = b"",
             photo_dir: Path | None = None) -> web.Application:
    """The server's app: its routes, the token check, the feed started with it and stopped
    (the session written to `session_dir`, if given) when it is cleaned up; `ca_der`, the
    local authority's public certificate (served as /frost-ca.crt) where HTTPS uses it;
    `photo_dir`, the folder of the photos pages send (default `session_dir`'s backdrops/;
    neither: no photos taken)."""
    app = web.Application(middlewares=[routes.token_check])
    quiet_bad_requests()
    app[FEED], app[TOKEN] = feed, token or ""
    app[FILES] = SessionFiles(feed, session_dir)
    app[BACKDROP_PNGS] = {}
    app[PAGE_LINES] = RateLimitedLog()
    app[CA_DER], app[PORTS] = ca_der, {"http": None, "https": None}
    if photo_dir is None and session_dir is not None:
        photo_dir = Path(session_dir) / photos.FOLDER
    feed.controls.store = photo_dir
    photo.routes_for(app, photo_dir)  # POST /photo, GET /backdrops/<photo>.jpg
    weather_route.routes_for(app)  # POST /weather: moves the feed's weather
    install.routes_for(app, web_dir)  # the page, its manifest and its worker (/sw.js)
    app.router.add_get("/web/{path:.*}", routes.folder_files(web_dir))
    app.router.add_get("/shaders/{path:.*}", routes.folder_files(SHADER_DIR))
    app.router.add_get("/backdrops/{name}.png", routes.backdrop)
    app.router.add_get("/meta", routes.meta)
    app.router.add_get("/app.json", routes.app_info)
    app.router.add_get(routes.CA_PATH, routes.authority)
    app.router.add_get("/ws", sockets.socket)
    app.on_startup.append(_start)
    app.on_shutdown.append(_end)  # before aiohttp waits on the open handlers
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
    steps, since = feed.moment[0], loop.time()
    while True:
        await asyncio.sleep(period)
        now, ticks = loop.time(), feed.moment[0] - steps
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


async def close_pages(app: web.Application) -> None:
    """Every page's socket closed (1001, "frost serve is ending") by its own handler, which
    reads, and counts, what the page sent until the page answers the close (at most
    sockets.CLOSE_S, all pages at once); then the warning of the input that came once the
    server was ending, if any. Before the runner's cleanup: from its start aiohttp reads
    nothing more from a connection (what a page sent then could not be counted)."""
    pages = list(app[FEED].pages)
    for page in pages:
        page.end()
    if pages:
        await asyncio.wait([asyncio.ensure_future(p.gone.wait()) for p in pages],
                           timeout=sockets.CLOSE_S + 1.0)
    app[FEED].say_late()


async def _close_pages(app: web.Application) -> None:
    """The pages still connected closed at once (the runner's cleanup: what they send is
    no longer read), and the warning of the input that came once the server was ending."""
    for page in list(app[FEED].pages):
        page.close()
        await page.ws.close(code=sockets.GOING_AWAY, message=sockets.ENDING)
    app[FEED].say_late()


def finish(app: web.Application) -> None:
    """The frost ends (once): no more input taken, what the pages were told the server has
    applied, the session written. `frost serve` calls it at its signal, before the open
    requests are ended; the app's cleanup otherwise."""
    app[FEED].close()
    app[FILES].stop()


async def _end(app: web.Application) -> None:
    """The server's shutdown: the frost ends (its pages' input still waiting applied,
    before their sockets close and drop what waits in their turns), then the pages close."""
    finish(app)
    await _close_pages(app)


async def _stop(app: web.Application) -> None:
    if STATS in app:
        app[STATS].cancel()
    await _end(app)  # (a test client's cleanup comes without a shutdown)
