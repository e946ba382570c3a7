"""A photo from a page (docs/phone-design.md, Photos: what the server checks;
docs/protocol.md): `POST /photo`, its checks, and `GET /backdrops/<photo>.jpg`, the photos kept.

Its Origin is checked and its refusals are JSON as every POST's (app/serve/posts.py). Each
remote address may send one photo every MIN_GAP_S; the request is refused before its body
is read. The body is read to its Content-Length, at most photos.MAX_BYTES (the connection guard
times it: guard.BODY_S). Checking and re-encoding it (app/photos.py) runs on a worker, one
photo at a time; at most MAX_WAITING wait their turn, the rest are told to try again. A
photo kept becomes every page's backdrop, as a page's backdrop command makes one; a bad
file is told to its sender alone and changes nothing.
"""

from __future__ import annotations

import asyncio
import logging
from dataclasses import dataclass
from pathlib import Path

from aiohttp import web

from app import photos
from app.serve.appkeys import FEED
from app.serve.posts import Gaps, head_refusal, refusal, unread

log = logging.getLogger("app.serve")

MIN_GAP_S = 5.0  # s between two photos of one remote address
MAX_WAITING = 4  # photos read and waiting for the worker; more are refused (503)
PATH = "/photo"
ENDING = "frost serve is ending: the photo was not taken"


@dataclass
class PhotoDesk(Gaps):
    """What the photo route keeps between requests: the folder of photos (None: this server
    keeps none), when each remote address last sent one, the worker's turn."""

    store: Path | None = None
    gap: float = MIN_GAP_S
    waiting: int = 0
    turn: asyncio.Semaphore | None = None  # made on the server's loop
    kept: int = 0  # photos taken
    refused: int = 0  # files refused (not a photo, too large...)


async def upload(request: web.Request) -> web.Response:
    """POST /photo: the body, a PNG, JPEG or WebP file; 200 {"backdrop": name} when it is
    every page's backdrop, else a 4xx/5xx {"error": one line}."""
    desk: PhotoDesk = request.app[PHOTOS]
    refused = head_refusal(request, "a photo", photos.MAX_BYTES, lambda n: (
        f"the file is {n:,} bytes; at most {photos.MAX_BYTES // 2**20} MB "
        f"({photos.MAX_BYTES:,} bytes) is taken"))
    if refused is not None:
        return refused
    length = request.content_length or 0
    if length == 0:
        return refusal(400, "the request holds no photo (Content-Length: 0)")
    if desk.store is None:
        return refusal(503, "this server keeps no photos (it has no session folder)")
    feed = request.app[FEED]
    if feed.ending:
        return unread(503, ENDING)
    loop = asyncio.get_running_loop()
    remote = request.remote or "?"
    soon = desk.too_soon(remote, loop.time(), "photo")
    if soon is not None:
        return soon
    if desk.waiting >= MAX_WAITING:
        return refusal(503, "other photos are being checked: try again in a few seconds",
                       retry=max(1, int(desk.gap)))
    desk.last[remote] = loop.time()
    desk.waiting += 1
    try:
        try:
            data = await request.content.readexactly(length)
        except (asyncio.IncompleteReadError, ConnectionError):
            return refusal(400, "the photo's bytes stopped before its Content-Length")
        if desk.turn is None:
            desk.turn = asyncio.Semaphore(1)
        async with desk.turn:
            name = await asyncio.to_thread(photos.keep, data, desk.store)
    except photos.PhotoError as err:
        desk.refused += 1
        status = 415 if photos.sniff(data) is None else 400  # (not an image; or a bad one)
        return refusal(status, str(err))
    except OSError as err:
        log.error("serve: a photo cannot be kept in %s: %s", desk.store, err)
        return refusal(500, "the server cannot keep the photo (see its log)")
    finally:
        desk.waiting -= 1
    if feed.ending:  # (its session is written: a photo taken now would not be in it)
        return refusal(503, ENDING)
    desk.kept += 1
    feed.controls.show_photo(name)
    feed.send_state()
    return web.json_response({"backdrop": name}, headers={"Cache-Control": "no-store"})


async def kept_photo(request: web.Request) -> web.StreamResponse:
    """GET /backdrops/<photo>.jpg: a photo of the folder of photos, by its name alone (its
    content's hash: the same name is always the same bytes)."""
    name, store = request.match_info["name"], request.app[PHOTOS].store
    if store is None or not photos.is_photo(name) or not photos.photo_file(name, store).is_file():
        raise web.HTTPNotFound(text=f"frost: no photo {name[:40]!r}\n")
    return web.FileResponse(photos.photo_file(name, store), headers={
        "Content-Type": "image/jpeg", "Cache-Control": "private, max-age=31536000, immutable"})


PHOTOS = web.AppKey("photos", PhotoDesk)


def routes_for(app: web.Application, store: Path | None) -> None:
    """POST /photo and GET /backdrops/<photo>.jpg on `app`, photos kept in `store`."""
    app[PHOTOS] = PhotoDesk(store=store)
    app.router.add_post(PATH, upload)
    app.router.add_get("/backdrops/{name}.jpg", kept_photo)
