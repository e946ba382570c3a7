"""A photo from a page (app/serve/photo.py, the guard's body in app/serve/guard.py): the
server as `frost serve` listens (its guarded runner, a free port), real sockets as pages,
uploads as raw HTTP requests. Oracles: the state each socket receives, the folder of
photos (the stored file's own hash names it), the status line and JSON of each answer."""

from __future__ import annotations

import asyncio
import hashlib
import json

import aiohttp
import numpy as np
import pytest
from PIL import Image
from support.page_model import pause, read_quiet, read_until, until
from support.photos import answer, encoded, exif_photo, page, post_head, quadrants, run, upload

from app import photos
from app.serve import guard, photo
from app.serve.feed import Feed
from app.serve.listen import listen
from app.serve.server import make_app
from sim import Params
from sim.screen import HEIGHT, WIDTH


def error_line(body: bytes) -> str:
    """The answer's one-line error (AssertionError if it is not one)."""
    text = json.loads(body)["error"]
    assert isinstance(text, str) and text and "\n" not in text and len(text) < 200, text
    return text


def stored(store) -> list:
    return sorted(store.glob("*")) if store.exists() else []


def test_a_photo_becomes_every_pages_backdrop_and_is_kept(tmp_path):
    async def test(port, runner, feed, store):
        async with aiohttp.ClientSession() as session:
            (ws1, p1), (ws2, p2) = await page(session, port), await page(session, port)
            assert p1.state("backdrop") == "dusk"
            await pause(ws1, p1)  # (quiet sockets: what comes is about the photo)
            status, headers, body = await upload(port, encoded(quadrants(600, 1000), "PNG"))
            assert status == 200, body
            name = json.loads(body)["backdrop"]
            # kept once, under the hash of the file written
            [path] = stored(store)
            assert name == "photo-" + hashlib.sha256(path.read_bytes()).hexdigest()[:32]
            with Image.open(path) as im:
                assert (im.format, im.size) == ("JPEG", (WIDTH, HEIGHT))
                a = np.asarray(im.convert("RGB")).astype(int)
            assert np.abs(a[HEIGHT // 4, WIDTH // 4] - (255, 0, 0)).max() < 40
            for ws, p in ((ws1, p1), (ws2, p2)):  # every page is told
                await read_until(ws, p, lambda p=p: p.state("backdrop") == name)
                assert p.state("backdrops") == ["dusk", "lockscreen", name]
            # served to the pages as it is kept; named by /meta
            got = await session.get(f"http://127.0.0.1:{port}/backdrops/{name}.jpg")
            assert got.status == 200 and await got.read() == path.read_bytes()
            assert "immutable" in got.headers["Cache-Control"]
            meta = await (await session.get(f"http://127.0.0.1:{port}/meta")).json()
            assert meta["background"] == name
            # a page may go back to a built-in and to the photo again
            await ws1.send_json({"type": "backdrop", "name": "lockscreen"})
            await read_until(ws2, p2, lambda: p2.state("backdrop") == "lockscreen")
            await ws1.send_json({"type": "backdrop", "name": name})
            await read_until(ws2, p2, lambda: p2.state("backdrop") == name)
            # ...but not to a photo of the folder this run did not show
            other = photos.keep(encoded(quadrants(60, 60), "PNG"), store)
            asked = len(p1.texts)
            await ws1.send_json({"type": "backdrop", "name": other})

            def notices() -> list[str]:  # the page's since it asked (a state may follow)
                return [t["text"] for t in p1.texts[asked:] if t["type"] == "notice"]

            await read_until(ws1, p1, notices)
            assert any(f"backdrop {other[:40]!r} refused" in n for n in notices()), notices()
            assert feed.controls.backdrop == name
            for ws in (ws1, ws2):
                await ws.close()
    run(test, tmp_path)


def test_photos_served_are_only_those_kept_by_name(tmp_path):
    async def test(port, runner, feed, store):
        name = photos.keep(encoded(quadrants(60, 60), "PNG"), store)
        (tmp_path / "secret.jpg").write_bytes(b"not for pages")
        async with aiohttp.ClientSession() as session:
            base = f"http://127.0.0.1:{port}/backdrops/"
            assert (await session.get(base + name + ".jpg")).status == 200
            for wrong in ("photo-" + "0" * 32, name.upper(), "secret", "..%2Fsecret",
                          name[len("photo-"):], "dusk"):
                assert (await session.get(base + wrong + ".jpg")).status == 404, wrong
    run(test, tmp_path)


def exif_gps_jpeg() -> bytes:
    return exif_photo(6, gps=True)


HOSTILE = {
    "truncated JPEG": (lambda: encoded(quadrants(800, 800), "JPEG", quality=95)[:2000], 400,
                       "cannot be decoded"),
    "PNG bomb": (lambda: encoded(Image.new("1", (20_000, 20_000)), "PNG", optimize=True), 400,
                 "at most 40 million"),
    "HTML named .jpg": (lambda: b"<html><script>alert(1)</script></html>", 415,
                        "not a PNG, JPEG or WebP"),
}


@pytest.mark.parametrize("kind", list(HOSTILE))
def test_a_bad_file_is_told_to_its_sender_alone_and_changes_nothing(tmp_path, kind):
    make, want_status, want_text = HOSTILE[kind]

    async def test(port, runner, feed, store):
        async with aiohttp.ClientSession() as session:
            ws, p = await page(session, port)
            await pause(ws, p)  # (then quiet: all it receives is about the photo)
            status, _, body = await upload(port, make())
            assert status == want_status and want_text in error_line(body), body
            await read_quiet(ws, p)
            assert p.state("backdrop") == "dusk" and p.state("backdrops") == ["dusk", "lockscreen"]
            assert not [t for t in p.texts if t["type"] == "notice"]  # the sender alone
            assert feed.controls.backdrop == "dusk" and stored(store) == []
            await ws.close()
    run(test, tmp_path, gap=0)


def test_over_the_size_limit_or_without_a_length_is_refused_before_the_body(tmp_path):
    async def test(port, runner, feed, store):
        for head, want in ((post_head(port, photos.MAX_BYTES + 1), 413),
                           (post_head(port, None), 411)):
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(head)  # no body at all: the answer comes before it
            status, headers, body = await answer(reader, within=10)
            assert status == want and error_line(body)
            assert headers.get("connection", "").lower() == "close"
            writer.close()
        assert feed.controls.backdrop == "dusk" and stored(store) == []
    run(test, tmp_path, gap=0)


def test_a_photo_of_exactly_the_size_limit_is_taken(tmp_path):
    """The limit is a most (docs/phone.md: "up to 8 MB"): a JPEG padded after its
    end to exactly photos.MAX_BYTES is taken (200) and kept whole; one byte more is the
    413 above."""
    jpeg = encoded(quadrants(380, 640), "JPEG", quality=95)
    exact = jpeg + bytes(photos.MAX_BYTES - len(jpeg))  # (a decoder stops at its end marker)

    async def test(port, runner, feed, store):
        status, _, body = await upload(port, exact)
        assert status == 200, body
        assert feed.controls.backdrop == json.loads(body)["backdrop"] and len(stored(store)) == 1
    run(test, tmp_path, gap=0)


def test_an_empty_post_is_told_it_holds_no_photo(tmp_path):
    async def test(port, runner, feed, store):
        status, _, body = await upload(port, b"")
        assert status == 400 and error_line(body) == "the request holds no photo (Content-Length: 0)"
        assert feed.controls.backdrop == "dusk" and stored(store) == []
    run(test, tmp_path, gap=0)


@pytest.mark.parametrize("origin", [None, "http://evil.example", "https://127.0.0.1:{port}",
                                    "http://127.0.0.1:{other}", "null"])
def test_a_post_from_another_origin_or_none_is_refused(tmp_path, origin):
    async def test(port, runner, feed, store):
        given = None if origin is None else origin.format(port=port, other=port + 1)
        status, _, body = await upload(port, encoded(quadrants(60, 60), "PNG"), origin=given)
        assert status == 403 and error_line(body)
        assert feed.controls.backdrop == "dusk" and stored(store) == []
        # (the same file from the page's own origin is taken: the Origin alone refused it)
        assert (await upload(port, encoded(quadrants(60, 60), "PNG")))[0] == 200
    run(test, tmp_path, gap=0)


@pytest.mark.parametrize(("token", "path", "host", "says"), [
    ("t0ken", "/photo", None, "needs the token"), ("t0ken", "/photo?token=t0ke", None, "needs the token"),
    (None, "/photo", "rebound.example", "only to this machine's names")])
def test_a_post_without_the_token_or_to_another_host_is_refused_in_json(tmp_path, token, path, host,
                                                                         says):
    """The token's (and, on loopback, the Host's) 403 is JSON too, as every refusal of POST
    /photo is (docs/protocol.md); other paths keep their line of text."""
    async def test(port, runner, feed, store):
        status, headers, body = await upload(port, encoded(quadrants(60, 60), "PNG"), path=path,
                                             host=host)
        assert status == 403 and headers["content-type"].startswith("application/json")
        assert says in error_line(body)
        assert feed.controls.backdrop == "dusk" and stored(store) == []
        async with aiohttp.ClientSession() as session:
            meta = await session.get(f"http://127.0.0.1:{port}/meta",
                                     headers={"Host": host} if host else {})
            assert meta.status == 403 and (await meta.text()).startswith("frost: this server")
        if token:  # with the token the same post is taken: the token alone refused it
            assert (await upload(port, encoded(quadrants(60, 60), "PNG"),
                                 path=f"/photo?token={token}"))[0] == 200
    run(test, tmp_path, gap=0, token=token)


def test_a_flood_of_photos_gets_one_taken_the_rest_told_to_wait_and_the_frost_ticks_on(tmp_path):
    async def test(port, runner, feed, store):
        data = [encoded(quadrants(300 + i, 500), "PNG") for i in range(12)]
        answers = await asyncio.gather(*(upload(port, d) for d in data))
        statuses = sorted(a[0] for a in answers)
        assert statuses == [200] + [429] * 11
        for status, headers, body in answers:
            if status == 429:
                assert 1 <= int(headers["retry-after"]) <= 5 and "one photo every 5 s" in error_line(body)
        assert len(stored(store)) == 1
        tick = feed.tick()
        await until(lambda: feed.tick() > tick, "a tick after the flood")
    run(test, tmp_path)


def tinted(image: Image.Image, i: int) -> Image.Image:
    """`image` with a square of its own colour in the middle: photos that differ once kept."""
    w, h = image.size
    image.paste((40 * i, 90, 200 - 40 * i), (w // 2 - 200, h // 2 - 200, w // 2 + 200, h // 2 + 200))
    return image


def test_photos_are_checked_one_at_a_time(tmp_path, monkeypatch):
    running, most = [0], [0]
    keep = photos.keep

    def counted(data, store):
        running[0] += 1
        most[0] = max(most[0], running[0])
        try:
            return keep(data, store)
        finally:
            running[0] -= 1
    monkeypatch.setattr(photos, "keep", counted)

    async def test(port, runner, feed, store):
        data = [encoded(tinted(quadrants(1500, 2000), i), "PNG") for i in range(photo.MAX_WAITING)]
        answers = await asyncio.gather(*(upload(port, d) for d in data))
        assert [a[0] for a in answers] == [200] * photo.MAX_WAITING
        assert most == [1] and len(stored(store)) == photo.MAX_WAITING
    run(test, tmp_path, gap=0)


def noisy_png() -> bytes:
    """A PNG larger than any head may be (its bytes, read as a head, would close the
    connection)."""
    rng = np.random.default_rng(3)
    data = encoded(Image.fromarray(rng.integers(0, 256, (300, 300, 3), np.uint8)), "PNG")
    assert len(data) > 2 * guard.MAX_HEAD_BYTES
    return data


def test_a_request_after_a_photos_body_on_one_connection_is_served(tmp_path):
    async def test(port, runner, feed, store):
        data = noisy_png()
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        meta = f"GET /meta HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode()
        writer.write(post_head(port, len(data)) + data + meta)  # pipelined
        status, _, body = await answer(reader)
        assert status == 200, body
        status, _, body = await answer(reader)
        assert status == 200 and json.loads(body)["background"] == feed.controls.backdrop
        assert feed.controls.backdrop.startswith("photo-")
        assert runner.too_long == 0 and runner.timed_out == 0
        writer.close()
    run(test, tmp_path, gap=0)


def test_a_body_has_its_own_deadline(tmp_path, monkeypatch):
    monkeypatch.setattr(guard, "HEAD_S", 0.4)
    monkeypatch.setattr(guard, "BODY_S", 3.0)
    data = encoded(quadrants(60, 60), "PNG")

    async def test(port, runner, feed, store):
        # in two parts, further apart than a head may take but within the body's time: taken
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(post_head(port, len(data)) + data[:100])
        await writer.drain()
        await asyncio.sleep(1.0)
        writer.write(data[100:])
        assert (await answer(reader))[0] == 200
        writer.close()
        # stopped halfway: closed at the body's deadline, nothing kept
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        loop = asyncio.get_running_loop()
        t0 = loop.time()
        writer.write(post_head(port, len(data) + 1) + data)
        with pytest.raises((asyncio.IncompleteReadError, ConnectionError)):
            await answer(reader, within=60)  # (a bound on a failure: nothing else ends it)
        # the body's deadline, not the head's (0.4 s): a loaded machine only adds time
        assert loop.time() - t0 > 2.5 and runner.timed_out == 1
        assert len(stored(store)) == 1
        writer.close()
    run(test, tmp_path, gap=0)


def test_an_exif_photo_with_gps_is_kept_upright_and_without_it(tmp_path):
    async def test(port, runner, feed, store):
        status, _, body = await upload(port, exif_gps_jpeg())
        assert status == 200, body
        [path] = stored(store)
        with Image.open(path) as im:
            assert not im.getexif() and "exif" not in im.info
        assert b"GPS" not in path.read_bytes()
    run(test, tmp_path)


def test_a_server_without_a_folder_takes_no_photo(tmp_path):
    async def main():
        feed = Feed(Params.preset("c-2"), seed=1)
        runner = await listen(make_app(feed), "127.0.0.1", 0, None)
        try:
            port = runner.addresses[0][1]
            status, _, body = await upload(port, encoded(quadrants(60, 60), "PNG"))
            assert status == 503 and "no photos" in error_line(body)
        finally:
            await runner.cleanup()
    asyncio.run(main())


def test_the_offline_shell_never_holds_a_photo(tmp_path):
    # the worker answers only its shell's paths: the built-ins, never backdrops/<photo>.jpg
    async def test(port, runner, feed, store):
        photos.keep(encoded(quadrants(60, 60), "PNG"), store)
        async with aiohttp.ClientSession() as session:
            worker = await (await session.get(f"http://127.0.0.1:{port}/sw.js")).text()
        shell = json.loads(worker.split("\n", 1)[0].removeprefix("const SHELL = ").rstrip(";"))
        kept = [f for f in shell["files"] if f.startswith("backdrops/")]
        assert kept == ["backdrops/dusk.png", "backdrops/lockscreen.png"]
        assert not [f for f in shell["files"] if f.startswith("backdrops/photo") or f.endswith(".jpg")]
    run(test, tmp_path)
