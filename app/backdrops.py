"""The view behind the glass: the built-in backdrops by name, a photo kept in a folder of
backdrops by its name (app/photos.py), or any PNG or JPEG file, scaled to cover the
screen and centre-cropped. Shared by the window, every offline
command and the command line's check of --background. The lock screen's clock box is
drawn at a minute (app/lockscreen.py): DEFAULT_MINUTE unless one is given."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from PIL import Image

from app.images import cover
from app.lockscreen import DEFAULT_MINUTE, with_clock
from app.photos import MAX_PIXELS, is_photo, photo_file, upright_rgb
from app.resources import ASSET_DIR
from sim.io.files import one_line
from sim.io.session import DEFAULT_BACKDROP  # noqa: F401 (the default, named here too)
from sim.screen import HEIGHT, WIDTH

# Name -> file in assets/ and the script that draws it.
BACKDROPS = {"dusk": ("background.png", "make_background.py"),
             "lockscreen": ("lockscreen.png", "make_lockscreen.py")}
LIVE = "lockscreen"  # the backdrop with a live clock (its static parts in its PNG)


def load_backdrop(name: str, size: tuple[int, int] = (WIDTH, HEIGHT),
                  minute: str | None = DEFAULT_MINUTE, photos: Path | None = None,
                  outside: str = "") -> np.ndarray:
    """Backdrop `name` (built-in, a photo kept in the folder `photos`, or a file) as
    H x W x 3 uint8, top row first, covering `size` (width, height); the lock screen with
    its clock at `minute` and `outside` under it (None: its static parts only, the clock
    box bare). ValueError in one line if it cannot be read."""
    image = read_backdrop(name, photos)
    if name == LIVE and minute is not None:
        image = Image.fromarray(with_clock(np.asarray(image), minute, outside))
    return np.asarray(cover(image, size))


def read_backdrop(name: str, photos: Path | None = None) -> Image.Image:
    """The image of backdrop `name` as it is stored (RGB); ValueError in one line if it
    cannot be read."""
    path = backdrop_path(name, photos)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # (Pillow's "Corrupt EXIF data")
            with Image.open(path) as im:
                w, h = im.size
                if name not in BACKDROPS and w * h > MAX_PIXELS:
                    raise ValueError(f"{w}x{h} pixels; at most {MAX_PIXELS / 1e6:g} million "
                                     "are taken")
                im.load()
                image = upright_rgb(im)  # (as its EXIF says, as a photo sent is)
    except Exception as err:  # noqa: BLE001 (any decoder's failure on a file: one line)
        raise ValueError(f"background {one_line(name)}: cannot read it as an image "
                         f"({one_line(str(err))})") from err
    if name == LIVE and image.size != (WIDTH, HEIGHT):
        raise ValueError(f"background image {path} is {image.size[0]}x{image.size[1]}, not "
                         f"{WIDTH}x{HEIGHT}; make it with: python3 assets/make_lockscreen.py")
    return image


def backdrop_path(name: str, photos: Path | None = None) -> Path:
    """The file of backdrop `name`: a built-in's PNG in assets/, a photo's in the folder
    `photos` (a session folder's backdrops/), else `name` as a path."""
    if is_photo(name):
        if photos is None:
            raise ValueError(f"backdrop {name}: a photo, and no folder of photos to find it in")
        path = photo_file(name, photos)
        if not path.is_file():
            raise ValueError(f"backdrop {name}: its file {path} is missing")
        return path
    if name in BACKDROPS:
        file, script = BACKDROPS[name]
        path = ASSET_DIR / file
        if not path.is_file():
            raise ValueError(f"background image {path} is missing; make it with: "
                             f"python3 assets/{script}")
        return path
    path = Path(name)
    if not path.is_file():
        raise ValueError(f"background {one_line(name)}: no such file (built-in: "
                         f"{', '.join(BACKDROPS)})")
    return path


def next_backdrop(current: str, extra: str | None = None) -> str:
    """The backdrop after `current` in the key's cycle: the built-ins, then `extra` (a
    file given with --background) if any."""
    cycle = [*BACKDROPS, *([extra] if extra and extra not in BACKDROPS else [])]
    i = cycle.index(current) if current in cycle else -1
    return cycle[(i + 1) % len(cycle)]


def view_from(args, view: dict | None = None) -> dict | None:
    """`view` (a session's, or None) with the command line's --background on top."""
    background = getattr(args, "background", None)
    return view if background is None else {**(view or {}), "background": background}
