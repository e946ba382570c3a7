"""The server's HTTP side (docs/protocol.md, HTTP): the token or the Host checked on every
request, static files from their own folders only, the backdrops, /meta."""

from __future__ import annotations

import asyncio
import html
import io
import ipaddress
import secrets
from pathlib import Path, PurePosixPath
from urllib.parse import urlsplit

from aiohttp import web

from app.backdrops import BACKDROPS, load_backdrop
from app.images import frost_meta
from app.serve import photo, posts, weather
from app.serve.appkeys import BACKDROP_PNGS, CA_DER, FEED, PORTS, TOKEN
from app.serve.feed import Feed

WEB_DIR = Path(__file__).resolve().parent.parent / "web"
TYPES = {".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript",
         ".css": "text/css", ".json": "application/json", ".png": "image/png",
         ".svg": "image/svg+xml", ".vert": "text/plain", ".frag": "text/plain",
         ".glsl": "text/plain", ".webmanifest": "application/manifest+json"}
CA_PATH = "/frost-ca.crt"  # the local authority's public certificate: served without the token


@web.middleware
async def token_check(request: web.Request, handler):
    """The token, where one is in force; else (a server on loopback) a Host naming this
    machine: a page of another site whose name its DNS turns to 127.0.0.1 (DNS rebinding)
    sends its own name as Host and as Origin, and would pass the Origin check. The local
    authority's public certificate alone is served to anyone: a phone installs it before
    it opens the page."""
    if request.path == CA_PATH:
        return await handler(request)
    token = request.app[TOKEN]
    given = request.query.get("token", "")
    if token and not secrets.compare_digest(given.encode(), token.encode()):
        return refused(request, "this server needs the token of the URL frost serve printed",
                       REPLACED if given else NO_TOKEN)
    host = request.headers.get("Host")
    if not token and host is not None and not loopback_name(host):
        return refused(request, "this server answers only to this machine's names "
                                "(127.0.0.1, localhost)", NOT_THIS_NAME)
    return await handler(request)


# What a person is told of a refusal, on the page's own paths (below).
REPLACED = "This page's link (its token) was replaced: scan the new QR code that frost serve prints."
NO_TOKEN = "This address needs its token: open the link frost serve printed, or scan its QR code."
NOT_THIS_NAME = ("frost serve answers only to this machine's own names: open "
                 "http://127.0.0.1 or http://localhost, with its port.")
# The page's own paths: a browser, or the installed app at its start_url, shows what they
# answer to a person. The API's answers stay one line of text for programs (and the page).
PAGE_PATHS = frozenset({"/", "/index.html"})
API_PATHS = frozenset({"/ws", "/meta", "/photo", "/weather", "/app.json", "/sw.js",
                       "/manifest.webmanifest"})
POST_PATHS = frozenset({photo.PATH, weather.PATH})  # their every refusal is JSON
REFUSAL_PAGE = """<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="theme-color" content="#000000">
<title>frost</title>
<style>
html {{ background: #000; color: #dde6f5; font: 18px/1.45 system-ui, sans-serif; }}
body {{ margin: 0; padding: max(24px, env(safe-area-inset-top)) 20px 24px; }}
h1 {{ font-size: 22px; margin: 0 0 12px; }}
p {{ margin: 0; max-width: 30em; }}
</style>
</head>
<body>
<h1>frost</h1>
<p id="refused">{text}</p>
</body>
</html>
"""


def refused(request: web.Request, line: str, told: str) -> web.Response:
    """The 403 for `request`: on the page's own paths, or a browser's navigation to any
    path but the API's, a page sized for a phone that says `told` (the installed app opened
    at its start_url showed the one line below, in a desktop's tiny type); to POST /photo
    and /weather JSON, as their every refusal is (the page shows the error it holds); else
    `line`."""
    navigation = request.headers.get("Sec-Fetch-Mode") == "navigate"
    if request.path in PAGE_PATHS or (navigation and request.path not in API_PATHS):
        return web.Response(status=403, text=REFUSAL_PAGE.format(text=html.escape(told, quote=False)),
                            content_type="text/html", headers={"Cache-Control": "no-store"})
    if request.path in POST_PATHS:
        return posts.refusal(403, line)
    return web.Response(status=403, text=f"frost: {line}\n")


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


def folder_files(folder: Path, name: str | None = None):
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


async def meta(request: web.Request) -> web.Response:
    """What a page's screenshot states beside its own view (app.images.frost_meta's keys):
    the parameters, seed, tick and touches of the frame published last (not of the
    simulation, which may have ticked on since), and the backdrop shown (`background`)."""
    feed: Feed = request.app[FEED]
    snap, thread = feed.latest, feed.thread
    about = frost_meta("page", snap.params if snap else feed.controls.params, thread.seed,
                       snap.stats.tick if snap else 0, thread.touch_ticks(snap),
                       background=feed.controls.backdrop)
    return web.json_response(about, headers={"Cache-Control": "no-cache"})


async def backdrop(request: web.Request) -> web.Response:
    name, cache = request.match_info["name"], request.app[BACKDROP_PNGS]
    if name not in BACKDROPS:
        raise web.HTTPNotFound(text=f"frost: no backdrop {name[:40]!r}\n")
    if name not in cache:
        cache[name] = await asyncio.to_thread(backdrop_png, name)
    return web.Response(body=cache[name], content_type="image/png")


def backdrop_png(name: str) -> bytes:
    """Built-in backdrop `name` as the pages get it (the static site's file too)."""
    from PIL import Image
    out = io.BytesIO()
    # (the lock screen's static parts: each page gets its clock box as a clock message)
    Image.fromarray(load_backdrop(name, minute=None)).save(out, "PNG")
    return out.getvalue()


async def authority(request: web.Request) -> web.Response:
    """GET /frost-ca.crt: the local authority's certificate (DER), to install on a phone
    (its private key never leaves its file); 404 where there is none (no HTTPS, or a
    certificate of the user's own)."""
    der = request.app[CA_DER]
    if not der:
        raise web.HTTPNotFound(text="frost: this server has no local authority to trust\n")
    return web.Response(body=der, content_type="application/x-x509-ca-cert", headers={
        "Content-Disposition": 'attachment; filename="frost-ca.crt"', "Cache-Control": "no-cache"})


async def app_info(request: web.Request) -> web.Response:
    """GET /app.json: the ports this server listens on ({"http": N, "https": N or null})
    and whether it serves a local authority to trust ("ca": "frost-ca.crt" or null)."""
    ports: dict = request.app[PORTS]
    info = {**ports, "ca": CA_PATH.lstrip("/") if request.app[CA_DER] else None}
    return web.json_response(info, headers={"Cache-Control": "no-store"})
