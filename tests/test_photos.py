"""Photos taken as backdrops (app/photos.py): crafted and hostile files refused with a
reason, good ones turned upright, covered to the pane, stripped of their metadata and
kept once under their hash."""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import threading
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support.photos import encoded, exif_photo, quadrants

from app import photos
from app.backdrops import load_backdrop
from sim.screen import HEIGHT, WIDTH

SIZE = (WIDTH, HEIGHT)


def colour_at(jpeg: bytes, fx: float, fy: float) -> tuple[int, ...]:
    with Image.open(io.BytesIO(jpeg)) as im:
        a = np.asarray(im.convert("RGB"))
    return tuple(int(v) for v in a[int(fy * a.shape[0]), int(fx * a.shape[1])])


def near(colour, want, tol=40) -> bool:
    return all(abs(int(c) - w) <= tol for c, w in zip(colour, want, strict=True))


@pytest.mark.parametrize("fmt", ["PNG", "JPEG", "WEBP"])
def test_each_taken_format_is_kept_as_a_jpeg_covering_the_pane(fmt):
    data = encoded(quadrants(600, 1000), fmt)
    jpeg = photos.prepare(data)
    with Image.open(io.BytesIO(jpeg)) as im:
        assert (im.format, im.size, im.mode) == ("JPEG", SIZE, "RGB")
    # 600x1000 covers 760x1280 scaled by 1.28 (1280/1000): 768 wide, 4 px cut each side
    assert near(colour_at(jpeg, 0.25, 0.25), (255, 0, 0))
    assert near(colour_at(jpeg, 0.75, 0.75), (255, 255, 255))


def test_the_format_comes_from_the_bytes_not_the_name():
    # A PNG sent as "photo.jpg" (image/jpeg) is read as the PNG it is...
    assert photos.sniff(encoded(quadrants(40, 40), "PNG")) == "PNG"
    photos.prepare(encoded(quadrants(40, 40), "PNG"))
    # ...and a page, a GIF or a script named like a photo is refused from its first bytes
    for data in (b"<html><script>alert(1)</script></html>", encoded(quadrants(40, 40), "GIF"),
                 b"RIFF\x00\x00\x00\x00WAVEfmt ", b"", b"\xff\xd8"):
        with pytest.raises(photos.PhotoError, match="not a PNG, JPEG or WebP"):
            photos.prepare(data)


def test_a_truncated_jpeg_is_refused_with_a_reason():
    data = encoded(quadrants(800, 800), "JPEG", quality=95)
    for cut in (len(data) // 2, 200, 20):
        with pytest.raises(photos.PhotoError, match="JPEG image cannot be decoded"):
            photos.prepare(data[:cut])


def test_a_png_bomb_is_refused_from_its_header_before_any_decoding(monkeypatch):
    # 20 000 x 20 000 one-bit pixels: 50 kB of PNG, 1.2 GB once decoded to RGB
    data = encoded(Image.new("1", (20_000, 20_000)), "PNG", optimize=True)
    assert len(data) < photos.MAX_BYTES
    alarm = encoded(Image.new("1", (8_000, 6_000)), "PNG", optimize=True)
    decoded = []
    monkeypatch.setattr(Image.Image, "load", lambda self: decoded.append(self) or None)
    with pytest.raises(photos.PhotoError, match="too many pixels; at most 40 million"):
        photos.prepare(data)
    assert decoded == []
    # under Pillow's own alarm, our limit still comes first, from the header
    with pytest.raises(photos.PhotoError, match="8000x6000 pixels; at most 40 million"):
        photos.prepare(alarm)
    assert decoded == []


def test_just_over_the_pixel_limit_is_refused_and_at_it_taken(monkeypatch):
    monkeypatch.setattr(photos, "MAX_PIXELS", 100 * 100)
    photos.prepare(encoded(quadrants(100, 100), "PNG"))
    with pytest.raises(photos.PhotoError, match="100x101 pixels"):
        photos.prepare(encoded(quadrants(100, 101), "PNG"))


def test_a_file_over_the_byte_limit_is_refused_unread(monkeypatch):
    monkeypatch.setattr(photos, "MAX_BYTES", 1000)
    with pytest.raises(photos.PhotoError, match="at most 0 MB"):
        photos.prepare(b"\x89PNG\r\n\x1a\n" + bytes(1000))


def fifo_fed(tmp_path: Path, data: bytes):
    """A FIFO (its size says 0) and the thread writing `data` into it in 64 KiB pieces
    until the reader is gone, and the count of bytes the reader took in (its one item)."""
    if not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs on this platform")
    fifo = tmp_path / "photo.fifo"
    os.mkfifo(fifo)

    def feed():
        with contextlib.suppress(BrokenPipeError), open(fifo, "wb", buffering=0) as f:
            for at in range(0, len(data), 65536):
                sent[0] += f.write(data[at:at + 65536])

    sent = [0]
    writer = threading.Thread(target=feed, daemon=True)
    writer.start()
    return fifo, writer, sent


def test_a_photo_read_from_a_fifo_is_read_whole(tmp_path):
    data = encoded(quadrants(64, 48), "PNG") + bytes(200_000)  # (over three pieces)
    fifo, writer, _ = fifo_fed(tmp_path, data)
    assert photos.read_file(fifo) == data
    writer.join(30)


def test_a_fifo_with_no_end_is_read_no_further_than_the_limit(tmp_path):
    """Its size says 0: the bytes read are bounded by the limit, not by the file's end
    (here three times the limit; /dev/zero has none)."""
    fifo, writer, sent = fifo_fed(tmp_path, bytes(3 * photos.MAX_BYTES))
    with pytest.raises(photos.PhotoError, match="the file holds more than 8 MB; at most 8 MB"):
        photos.read_file(fifo)
    writer.join(30)
    assert not writer.is_alive()
    # what the writer got in before the reader left: the limit and a pipe's buffer (64 KiB
    # on Linux, up to 1 MiB where raised)
    assert photos.MAX_BYTES < sent[0] < photos.MAX_BYTES + 2**21


def test_a_regular_file_over_the_limit_is_refused_from_its_size(tmp_path):
    big = tmp_path / "big.png"
    big.write_bytes(bytes(photos.MAX_BYTES + 1))
    with pytest.raises(photos.PhotoError, match=r"the file is 8\.0 MB; at most 8 MB"):
        photos.read_file(big)
    big.write_bytes(bytes(photos.MAX_BYTES))  # at the limit: read (and left to prepare)
    assert len(photos.read_file(big)) == photos.MAX_BYTES


@pytest.mark.parametrize("orientation, top_left", [
    (1, (255, 0, 0)),  # as stored: red top left
    (6, (0, 0, 255)),  # turned 90 degrees clockwise to be upright: blue comes to the top left
    (8, (0, 255, 0)),  # turned counter-clockwise: green comes to the top left
    (3, (255, 255, 255)),  # turned half way: white top left
])
def test_exif_orientation_is_applied(orientation, top_left):
    jpeg = photos.prepare(exif_photo(orientation))
    assert near(colour_at(jpeg, 0.1, 0.05), top_left)


def test_no_metadata_is_kept_gps_least_of_all(tmp_path):
    data = exif_photo(6, gps=True)
    with Image.open(io.BytesIO(data)) as im:  # (the crafted file does carry them)
        assert im.getexif().get_ifd(0x8825)
    name = photos.keep(data, tmp_path)
    stored = photos.photo_file(name, tmp_path).read_bytes()
    with Image.open(io.BytesIO(stored)) as im:
        assert not im.getexif()
        assert "exif" not in im.info and "icc_profile" not in im.info
    assert b"Exif" not in stored and b"PhoneMaker" not in stored


def test_transparency_is_laid_over_black():
    a = np.zeros((50, 50, 4), np.uint8)
    a[..., 0] = 255  # red, wholly transparent on the left half
    a[:, 25:, 3] = 255
    jpeg = photos.prepare(encoded(Image.fromarray(a, "RGBA"), "PNG"))
    assert near(colour_at(jpeg, 0.1, 0.5), (0, 0, 0))
    assert near(colour_at(jpeg, 0.9, 0.5), (255, 0, 0))


def test_a_photo_is_kept_once_under_the_hash_of_its_file(tmp_path):
    data = encoded(quadrants(300, 500), "PNG")
    name = photos.keep(data, tmp_path / "backdrops")
    path = photos.photo_file(name, tmp_path / "backdrops")
    assert photos.is_photo(name)
    assert name == "photo-" + hashlib.sha256(path.read_bytes()).hexdigest()[:32]
    assert [p.name for p in (tmp_path / "backdrops").iterdir()] == [path.name]
    # the same photo again (another session): the same name, the one file
    assert photos.keep(data, tmp_path / "backdrops") == name
    assert len(list((tmp_path / "backdrops").iterdir())) == 1
    # and the backdrop loads from it by name
    shown = load_backdrop(name, photos=tmp_path / "backdrops")
    assert shown.shape == (HEIGHT, WIDTH, 3)
    assert near(tuple(shown[10, 10]), (255, 0, 0))


def test_a_missing_photo_is_named_in_one_line(tmp_path):
    name = "photo-" + "0" * 32
    with pytest.raises(ValueError, match=f"backdrop {name}: its file .*{'0' * 32}.jpg is missing"):
        load_backdrop(name, photos=tmp_path)


@pytest.mark.parametrize("name", ["photo-" + "0" * 31, "photo-" + "G" * 32, "photo-../../etc",
                                  "photo-" + "0" * 32 + "/x", "dusk", "", None, 7])
def test_only_photo_names_name_photos(name):
    assert not photos.is_photo(name)
    with pytest.raises(ValueError):
        photos.photo_file(name, photos.Path("/tmp"))


# ---- found by a hostile user's probe -------------------------------------------------

def resized_then_cropped(image: Image.Image, size) -> Image.Image:
    """The obvious cover: the whole image scaled, then its middle cut out."""
    w, h = image.size
    scale = max(size[0] / w, size[1] / h)
    sw, sh = max(size[0], round(w * scale)), max(size[1], round(h * scale))
    whole = image.resize((sw, sh), Image.Resampling.LANCZOS)
    left, top = (sw - size[0]) // 2, (sh - size[1]) // 2
    return whole.crop((left, top, left + size[0], top + size[1]))


@pytest.mark.parametrize("w, h", [(600, 1000), (1600, 1200), (1280, 760), (761, 1281)])
def test_cover_resamples_only_what_shows_as_the_obvious_cover_would(w, h):
    from app.images import cover

    rng = np.random.default_rng(w)
    # (smooth: the obvious cover cuts at a whole px, a third of one off the exact middle)
    small = Image.fromarray((rng.random((h // 100 + 2, w // 100 + 2, 3)) * 255).astype(np.uint8))
    image = small.resize((w, h), Image.Resampling.BILINEAR)
    got = np.asarray(cover(image, SIZE)).astype(int)
    want = np.asarray(resized_then_cropped(image, SIZE)).astype(int)
    assert got.shape == want.shape == (HEIGHT, WIDTH, 3)
    assert np.abs(got - want).max() <= 8 and np.abs(got - want).mean() < 1


def test_a_picture_one_pixel_wide_is_taken_without_gigabytes():
    # 1 x 30 000 px, 200 bytes: scaled whole to cover the pane it was 760 x 22.8 million
    # (52 GB); only the 1 x 50 px that show are resampled now
    column = np.zeros((30_000, 1, 3), np.uint8)
    column[15_000 - 25:15_000 + 25] = (40, 200, 90)
    jpeg = photos.prepare(encoded(Image.fromarray(column), "PNG"))
    with Image.open(io.BytesIO(jpeg)) as im:
        shown = np.asarray(im.convert("RGB")).astype(int)
    assert shown.shape == (HEIGHT, WIDTH, 3)
    assert np.abs(shown[HEIGHT // 2] - (40, 200, 90)).max() < 20  # the middle of the column


def test_a_jpeg_whose_exif_breaks_the_decoder_is_refused_in_one_line(tmp_path):
    # (a phone photo's EXIF with bytes changed: Pillow's exif_transpose raises struct.error)
    data = (Path(__file__).parent / "data" / "corrupt-exif.jpg").read_bytes()
    with pytest.raises(photos.PhotoError, match="the JPEG image cannot be decoded: its EXIF "
                                                "data is corrupt") as err:
        photos.prepare(data)
    assert "\n" not in str(err.value)
    # the window's --background FILE: read with the same care (shown, one line if not)
    path = tmp_path / "corrupt.jpg"
    path.write_bytes(data)
    try:
        load_backdrop(str(path))
    except ValueError as refused:
        assert str(path) in str(refused) and "\n" not in str(refused)


def test_a_16_bit_grey_png_keeps_its_shades():
    ramp = np.repeat(np.linspace(0, 65535, 1280).astype(np.uint16)[:, None], 760, axis=1)
    image = Image.fromarray(ramp)
    assert image.mode == "I;16"
    data = encoded(image, "PNG")
    with Image.open(io.BytesIO(photos.prepare(data))) as im:
        shown = np.asarray(im.convert("L")).astype(int)
    for row in (100, 640, 1200):  # 16 bits to 8: the value over 257
        assert abs(shown[row].mean() - ramp[row, 0] / 257) < 4, row


def test_a_file_named_by_garbage_is_refused_without_pillows_object_in_the_line():
    with pytest.raises(photos.PhotoError) as err:
        photos.prepare(b"\xff\xd8\xff")
    assert "BytesIO" not in str(err.value) and "not a whole JPEG header" in str(err.value)


def test_a_background_file_is_shown_upright_as_its_exif_says(tmp_path):
    path = tmp_path / "turned.jpg"
    path.write_bytes(exif_photo(6))
    shown = load_backdrop(str(path))  # (frost render --background, the window's start)
    assert near(tuple(shown[40, 40]), (0, 0, 255))  # turned: blue at the top left
