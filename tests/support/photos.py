"""Photos made to order (encoded images, EXIF orientations) and sent to a server listening
as `frost serve` does, over raw HTTP."""

from __future__ import annotations

import asyncio
import io

import aiohttp
import numpy as np
from PIL import Image

from app import photos
from app.serve import photo
from app.serve.feed import Feed
from app.serve.listen import listen
from app.serve.server import make_app
from sim import Params
from support.page_model import PageModel, read_until


def encoded(image: Image.Image, fmt: str, **kwargs) -> bytes:
    out = io.BytesIO()
    image.save(out, fmt, **kwargs)
    return out.getvalue()


def quadrants(w: int, h: int) -> Image.Image:
    """Top-left red, top-right green, bottom-left blue, bottom-right white."""
    a = np.zeros((h, w, 3), np.uint8)
    a[: h // 2, : w // 2] = (255, 0, 0)
    a[: h // 2, w // 2:] = (0, 255, 0)
    a[h // 2:, : w // 2] = (0, 0, 255)
    a[h // 2:, w // 2:] = (255, 255, 255)
    return Image.fromarray(a)


def exif_photo(orientation: int, gps: bool = False) -> bytes:
    """A landscape JPEG of quadrants whose EXIF says `orientation` (and a GPS position)."""
    exif = Image.Exif()
    exif[0x0112] = orientation
    exif[0x010F] = "PhoneMaker"
    if gps:
        exif[0x8825] = {1: "N", 2: (51.0, 30.0, 0.0), 3: "W", 4: (0.0, 7.0, 0.0)}
    return encoded(quadrants(1600, 1200), "JPEG", exif=exif.tobytes(), quality=95)


def run(test, tmp_path, gap: float | None = None, token: str | None = None):
    """`test(port, runner, feed, store)` against a server listening as `frost serve` does,
    its photos kept in tmp_path/backdrops (`gap`: the seconds between two photos of one
    address, default the server's; `token`: the one in force, None for none)."""
    store = tmp_path / photos.FOLDER

    async def main():
        feed = Feed(Params.preset("c-2"), seed=1)
        app = make_app(feed, token, tmp_path)
        if gap is not None:
            app[photo.PHOTOS].gap = gap
        runner = await listen(app, "127.0.0.1", 0, token)
        assert runner is not None
        try:
            await test(runner.addresses[0][1], runner, feed, store)
        finally:
            await runner.cleanup()
    asyncio.run(main())


def post_head(port: int, length: int | None, origin: str | None = "same", path: str = "/photo",
              extra: str = "", host: str | None = None) -> bytes:
    """The head of a POST of `length` bytes (None: chunked) with Origin `origin` ("same":
    the server's own) and Host `host` (None: the server's own)."""
    lines = [f"POST {path} HTTP/1.1", f"Host: {host or f'127.0.0.1:{port}'}", "Content-Type: image/jpeg"]
    if origin == "same":
        origin = f"http://127.0.0.1:{port}"
    if origin is not None:
        lines.append(f"Origin: {origin}")
    lines.append("Transfer-Encoding: chunked" if length is None else f"Content-Length: {length}")
    return ("\r\n".join(lines) + "\r\n" + extra + "\r\n").encode()


async def answer(reader: asyncio.StreamReader, within: float = 30.0) -> tuple[int, dict, bytes]:
    """One answer read whole: (status, headers in lower case, body)."""
    head = await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), within)
    lines = head.decode("latin-1").split("\r\n")
    headers = {k.strip().lower(): v.strip() for k, v in
               (line.split(":", 1) for line in lines[1:] if ":" in line)}
    body = await asyncio.wait_for(reader.readexactly(int(headers.get("content-length", 0))), within)
    return int(lines[0].split()[1]), headers, body


async def upload(port: int, data: bytes, origin: str | None = "same", path: str = "/photo",
                 host: str | None = None) -> tuple[int, dict, bytes]:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        writer.write(post_head(port, len(data), origin, path, host=host) + data)
        return await answer(reader)
    finally:
        writer.close()


async def page(session: aiohttp.ClientSession, port: int):
    ws = await session.ws_connect(f"http://127.0.0.1:{port}/ws")
    model = PageModel()
    await read_until(ws, model, lambda: model.snapshots >= 1)
    return ws, model
