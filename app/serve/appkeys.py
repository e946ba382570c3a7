"""What the server's aiohttp app holds (its keys), apart from the modules that fill and read
them: the app (server.py) registers the routes (routes.py) and the socket (sockets.py),
which read what it holds."""

from __future__ import annotations

import asyncio

from aiohttp import web

from app.serve.feed import Feed
from app.serve.logs import RateLimitedLog
from app.serve.session_files import SessionFiles

FEED = web.AppKey("feed", Feed)
TOKEN = web.AppKey("token", str)  # "" when none is in force
FILES = web.AppKey("files", SessionFiles)
BACKDROP_PNGS = web.AppKey("backdrops", dict)  # name: PNG bytes, made at the first ask
STATS = web.AppKey("stats", asyncio.Task)
PAGE_LINES = web.AppKey("page_lines", RateLimitedLog)  # pages connected and closed
CA_DER = web.AppKey("ca_der", bytes)  # the local authority's public certificate; b"": none
PORTS = web.AppKey("ports", dict)  # {"http": N, "https": N or None}, filled once listening
