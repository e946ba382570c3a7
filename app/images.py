"""Screenshots: read a framebuffer, write a PNG that carries how the frost was made."""

from __future__ import annotations

import json
import logging
import time
from pathlib import Path

import numpy as np
from PIL import Image, PngImagePlugin

from sim.files import write_atomic

log = logging.getLogger(__name__)


def read_image(fbo) -> np.ndarray:
    """The framebuffer's colour as H x W x 3 uint8, top row first (GL reads bottom-up)."""
    w, h = fbo.size
    data = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8)
    return data.reshape(h, w, 3)[::-1].copy()


def png_writer(image: np.ndarray, meta: dict):
    """A writer (see sim.files) of `image` as PNG; each meta entry becomes a text chunk
    (JSON unless a str)."""
    info = PngImagePlugin.PngInfo()
    for key, value in meta.items():
        info.add_text(key, value if isinstance(value, str) else json.dumps(value))
    return lambda f: Image.fromarray(image).save(f, format="PNG", pnginfo=info)


def save_png(image: np.ndarray, path, meta: dict) -> Path:
    """Write `image` to `path` atomically (never a half-written PNG) with `meta`."""
    path = write_atomic(path, png_writer(image, meta))
    log.info("screenshot written to %s", path)
    return path


def timestamped_path(folder, prefix: str = "frost", suffix: str = ".png", also=(),
                     taken=()) -> Path:
    """A new file name in `folder` named by the time, never one that already exists, nor
    one whose stem exists with any (folder, suffix) of `also` or is in `taken` (names
    handed out before whose files may not be written yet, or never were)."""
    folder = Path(folder)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    path, n = folder / f"{prefix}-{stamp}{suffix}", 1
    while path.exists() or path.stem in taken or any(
            (Path(other) / f"{path.stem}{ext}").exists() for other, ext in also):
        path, n = folder / f"{prefix}-{stamp}-{n}{suffix}", n + 1
    return path
