"""Photos people bring as backdrops (uploaded from a page, dropped on the window): checked
from their bytes, decoded only when their header's size is within the limit, turned as
their EXIF orientation says, covered to the pane and re-encoded by us, without any of
their metadata (a phone photo's GPS position is never kept or passed on). Each is kept in
a folder of backdrops (a session folder's `backdrops/`) under the hash of the file we
wrote, so the sessions that show one photo share its file, and its name, `photo-` and the
hash, is what sessions and the pages' protocol carry (docs/protocol.md, docs/sessions.md).
No name from the sender reaches a path."""

from __future__ import annotations

import hashlib
import io
import os
import re
import struct
import warnings
from pathlib import Path

import numpy as np
from PIL import Image, ImageOps, UnidentifiedImageError

from app.images import cover
from sim.io.files import one_line, write_atomic
from sim.screen import HEIGHT, WIDTH

PREFIX = "photo-"
DIGITS = 32  # hex digits of the SHA-256 of the stored file kept in the name
NAME = re.compile(rf"{PREFIX}[0-9a-f]{{{DIGITS}}}\Z")
FOLDER = "backdrops"  # the photos' folder in a session folder
MAX_BYTES = 8 * 1024 * 1024  # a file larger is refused unread (a page sends about 1 MB)
MAX_PIXELS = 40_000_000  # width x height in the header; more is refused before decoding
QUALITY = 90  # of the JPEG we store


class PhotoError(ValueError):
    """A file that is not taken as a photo; its message is one line, naming why."""

    def __init__(self, message: str):
        super().__init__(one_line(message))


def store_of(session_dir) -> Path:
    """The folder of photos of a session folder (the folder a session file is in)."""
    return Path(session_dir) / FOLDER


def is_photo(name: object) -> bool:
    """Whether `name` is a photo's backdrop name (`photo-` and 32 hex digits)."""
    return isinstance(name, str) and NAME.match(name) is not None


def photo_file(name: str, store: Path) -> Path:
    """Where photo `name` is kept in the folder `store` (which may not hold it)."""
    if not is_photo(name):
        raise ValueError(f"{one_line(name)[:80]!r} is not a photo's name")
    return Path(store) / f"{name[len(PREFIX):]}.jpg"


def sniff(data: bytes) -> str | None:
    """The image format `data` begins as (Pillow's name), from its bytes alone: PNG,
    JPEG or WEBP; None for anything else."""
    if data.startswith(b"\x89PNG\r\n\x1a\n"):
        return "PNG"
    if data.startswith(b"\xff\xd8\xff"):
        return "JPEG"
    if len(data) >= 12 and data[:4] == b"RIFF" and data[8:12] == b"WEBP":
        return "WEBP"
    return None


def prepare(data: bytes, size: tuple[int, int] = (WIDTH, HEIGHT)) -> bytes:
    """The JPEG we keep of the image file `data`: upright, covering `size` (centre-cropped),
    RGB (any transparency over black), with no metadata. PhotoError saying why if it is
    not a PNG, JPEG or WebP, is larger than MAX_BYTES or MAX_PIXELS, or cannot be decoded."""
    if len(data) > MAX_BYTES:
        raise PhotoError(f"the file is {len(data) / 2**20:.1f} MB; at most "
                         f"{MAX_BYTES // 2**20} MB is taken")
    kind = sniff(data)
    if kind is None:
        raise PhotoError("not a PNG, JPEG or WebP image (whatever its name or type says)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            warnings.simplefilter("ignore", UserWarning)  # (Pillow's "Corrupt EXIF data")
            image = Image.open(io.BytesIO(data), formats=[kind])  # reads the header only
            return _prepared(image, kind, size)
    except PhotoError:
        raise
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as err:
        raise PhotoError(f"the {kind} image has too many pixels; at most "
                         f"{MAX_PIXELS / 1e6:g} million are taken ({err})") from None
    except struct.error:  # (Pillow's EXIF reader on bytes that are not what they say)
        raise PhotoError(f"the {kind} image cannot be decoded: its EXIF data is corrupt") from None
    except UnidentifiedImageError:
        raise PhotoError(f"the {kind} image cannot be decoded: its data is not a whole "
                         f"{kind} header") from None
    except Exception as err:  # noqa: BLE001 (a hostile file may break a decoder anywhere:
        # struct.error in corrupt EXIF, OSError when truncated...; each is a refusal)
        raise PhotoError(f"the {kind} image cannot be decoded: {err}") from None


def _prepared(image: Image.Image, kind: str, size: tuple[int, int]) -> bytes:
    """`prepare`'s work once the header is read: the size checked, then decoded."""
    with image:
        w, h = image.size
        if w < 1 or h < 1 or w * h > MAX_PIXELS:
            raise PhotoError(f"the {kind} image is {w}x{h} pixels; at most "
                             f"{MAX_PIXELS / 1e6:g} million are taken")
        if kind == "JPEG":  # decoded at a fraction of its size where that still covers
            side = max(size)
            image.draft("RGB", (side, side))
        image.load()
        rgb = upright_rgb(image)
    out = io.BytesIO()
    cover(rgb, size).save(out, "JPEG", quality=QUALITY)  # (no exif, no icc: nothing kept)
    return out.getvalue()


def upright_rgb(image: Image.Image) -> Image.Image:
    """A decoded `image` turned upright as its EXIF says, as 8-bit RGB: 16-bit grey taken
    to 8 bits (Pillow's own conversion clips it to white), any transparency laid over
    black."""
    image = ImageOps.exif_transpose(image)
    if image.mode in ("I", "I;16", "I;16B", "I;16L", "I;16N"):  # (a 16-bit grey PNG)
        image = Image.fromarray((np.asarray(image).astype(np.uint32) >> 8).astype(np.uint8), "L")
    if image.mode in ("RGBA", "LA", "PA") or "transparency" in image.info:
        rgba = image.convert("RGBA")
        black = Image.new("RGBA", rgba.size, (0, 0, 0, 255))
        return Image.alpha_composite(black, rgba).convert("RGB")
    return image.convert("RGB")


def keep(data: bytes, store: Path, size: tuple[int, int] = (WIDTH, HEIGHT)) -> str:
    """`data` checked and prepared (see `prepare`), kept in `store` (made if missing;
    a photo kept already is not written again); its backdrop name. PhotoError as
    `prepare`; OSError naming the file if it cannot be written."""
    jpeg = prepare(data, size)
    name = PREFIX + hashlib.sha256(jpeg).hexdigest()[:DIGITS]
    path = photo_file(name, store)
    if not path.is_file():
        write_atomic(path, lambda f: f.write(jpeg))
    return name


def copy_photos(names, source: Path, target: Path) -> None:
    """The photos among `names` kept in `source` copied to `target` where it lacks them
    (a replayed session's, to the folder of the session the window keeps)."""
    if Path(source).resolve() == Path(target).resolve():
        return
    for name in dict.fromkeys(n for n in names if is_photo(n)):
        there, here = photo_file(name, source), photo_file(name, target)
        if there.is_file() and not here.is_file():
            write_atomic(here, _writer(there.read_bytes()))


def _writer(data: bytes):
    return lambda f: f.write(data)


def read_file(path: Path) -> bytes:
    """The bytes of the image file `path` if it is at most MAX_BYTES (a file dropped on
    the window, given with --background); PhotoError saying why not. A regular file
    larger is refused unread; of any other (a pipe, a FIFO, /dev/zero: their size says
    0) at most MAX_BYTES + 1 bytes are read."""
    try:
        with open(path, "rb") as f:
            size = os.fstat(f.fileno()).st_size
            data = f.read(MAX_BYTES + 1) if size <= MAX_BYTES else b""
    except OSError as err:
        raise PhotoError(f"{path}: cannot read it ({err.strerror or err})") from None
    if size > MAX_BYTES or len(data) > MAX_BYTES:
        held = f"is {size / 2**20:.1f} MB" if size > MAX_BYTES else \
            f"holds more than {MAX_BYTES / 2**20:g} MB"
        raise PhotoError(f"{path}: the file {held}; at most {MAX_BYTES // 2**20} MB is taken")
    return data
