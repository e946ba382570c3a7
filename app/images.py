"""Images that carry how the frost was made: screenshots and renders (read from a
framebuffer, PNG or JPEG by the file's suffix) and the height / normal / alpha maps
(computed by sim.look.maps). PIL and numpy only, no GL, so the simulation thread can write
maps and the GL tools can write screenshots alike."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np
from PIL import Image, PngImagePlugin

from sim.io.files import write_all_atomic, write_atomic
from sim.look.maps import MAP_NAMES, MEANING, compute_maps, encode
from sim.params import Params
from sim.screen import HEIGHT, WIDTH

DEFAULT_FOLDER = Path("frost-out")  # where headless PNGs go without --out
# What a picture's file name ends with (any case) and the format written under it.
IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG"}
JPEG_QUALITY = 95
JPEG_COMMENT_MAX = 65533  # bytes in a JPEG's one comment segment (its length is 16 bits)


def read_image(fbo) -> np.ndarray:
    """The framebuffer's colour as H x W x 3 uint8, top row first (GL reads bottom-up)."""
    w, h = fbo.size
    data = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8)
    return data.reshape(h, w, 3)[::-1].copy()


def frost_meta(software: str, params: Params | None, seed: int, tick: int, touches,
               **more) -> dict:
    """The text every PNG frost writes (screenshots, renders, maps, sheets), one schema:
    `parameters` (as session files encode them; None for a sheet of several presets, whose
    own keys say which), `seed`, `tick`, `touches` as [tick, x, y] each, `Software`
    naming the command that wrote it, `Creation Time`; then `more` (view, session, map,
    encoding, ...)."""
    meta = {"parameters": params.as_dict() if params is not None else None, "seed": int(seed),
            "tick": int(tick), "touches": [[int(t), float(x), float(y)] for t, x, y in touches],
            "Software": f"frost ({software})", "Creation Time": time.strftime("%Y-%m-%dT%H:%M:%S")}
    if params is None:
        del meta["parameters"]
    return {**meta, **more}


def png_writer(image: np.ndarray, meta: dict):
    """A writer (see sim.io.files) of `image` as PNG; each meta entry becomes a text chunk
    (JSON unless a str)."""
    info = PngImagePlugin.PngInfo()
    for key, value in meta.items():
        info.add_text(key, value if isinstance(value, str) else json.dumps(value))
    return lambda f: Image.fromarray(image).save(f, format="PNG", pnginfo=info)


def jpeg_writer(image: np.ndarray, meta: dict):
    """A writer of `image` as JPEG. A JPEG has no text chunks: `meta` goes into its
    comment segment as one JSON object, left without its largest entries (named under
    `left_out`) where the whole would not fit in the segment's 64 KB."""
    comment = jpeg_comment(meta)
    return lambda f: Image.fromarray(image).save(f, format="JPEG", quality=JPEG_QUALITY,
                                                 comment=comment)


def jpeg_comment(meta: dict) -> bytes:
    """`meta` as JSON bytes of at most JPEG_COMMENT_MAX, the largest entries left out
    (and named) until it fits."""
    kept, left_out = dict(meta), []
    text = json.dumps(kept).encode()
    while len(text) > JPEG_COMMENT_MAX:
        largest = max(kept, key=lambda key: len(json.dumps(kept[key])))
        del kept[largest]
        left_out.append(largest)
        text = json.dumps({**kept, "left_out": left_out}).encode()
    return text


def image_format(path) -> str | None:
    """The format a picture at `path` is written in, by its suffix; None for a suffix
    frost does not write."""
    return IMAGE_FORMATS.get(Path(path).suffix.lower())


def suffix_problem(path) -> str | None:
    """Why frost cannot write a picture under the name `path` (None: it can)."""
    if image_format(path):
        return None
    shown = Path(path).suffix or "no suffix"
    return f"frost writes {', '.join(IMAGE_FORMATS)} pictures; this name has {shown}"


def save_image(image: np.ndarray, path, meta: dict) -> Path:
    """Write `image` to `path` atomically with `meta`, as PNG or JPEG by the suffix of
    `path` (ValueError for another). Silent: the caller says what it wrote, once."""
    problem = suffix_problem(path)
    if problem:
        raise ValueError(problem)
    writer = png_writer if image_format(path) == "PNG" else jpeg_writer
    return write_atomic(path, writer(image, meta))


def save_png(image: np.ndarray, path, meta: dict) -> Path:
    """Write `image` to `path` atomically (never a half-written PNG) with `meta`. Silent:
    the caller says what it wrote, once."""
    return write_atomic(path, png_writer(image, meta))


def timestamped_path(folder, prefix: str = "frost", suffix: str = ".png", also=(),
                     taken=()) -> Path:
    """A new file name in `folder` named by the time and this process (two runs started in
    the same second choose before either writes, so the time alone would name both files
    the same): never one that already exists, nor one whose stem exists with any
    (folder, suffix) of `also` or is in `taken` (names this run handed out before whose
    files may not be written yet, or never were)."""
    folder = Path(folder)
    stamp = f"{time.strftime('%Y%m%d-%H%M%S')}-p{os.getpid()}"
    path, n = folder / f"{prefix}-{stamp}{suffix}", 1
    while path.exists() or path.stem in taken or any(
            (Path(other) / f"{path.stem}{ext}").exists() for other, ext in also):
        path, n = folder / f"{prefix}-{stamp}-{n}{suffix}", n + 1
    return path


def export_maps(folder, grid: np.ndarray, segments: np.ndarray, params: Params,
                meta: dict, width: int = WIDTH, height: int = HEIGHT,
                triangles: np.ndarray | None = None) -> dict[str, Path]:
    """Write height.png, normal.png and alpha.png into `folder`; returns name -> path.

    `grid` is the geometry's height grid (FrostGeometry.heights, or the renderer's
    mirror of it) and `segments` the live skeleton (`sim.look.maps.live_segments`), both copied
    by the caller if another thread may change them. Each PNG carries `meta`
    (`frost_meta`) and what its values mean as text chunks."""
    images, top = encode(compute_maps(grid, segments, params, width, height, triangles))
    common = {**meta, "height_max_px": top}
    folder = Path(folder)
    paths = {name: folder / f"{name}.png" for name in MAP_NAMES}
    # All three or none: a full disk or an unwritable folder leaves no half set.
    write_all_atomic({paths[name]: png_writer(images[name], {**common, "map": name,
                                                             "encoding": MEANING[name]})
                      for name in MAP_NAMES})
    return paths


def cover(image: Image.Image, size: tuple[int, int]) -> Image.Image:
    """`image` scaled (keeping its aspect) to cover `size`, centre-cropped to it. Only the
    part that shows is resampled, straight to `size`: a picture 1 px wide is never first
    made 760 px wide and a million tall."""
    w, h = image.size
    if (w, h) == size:
        return image
    scale = max(size[0] / w, size[1] / h)
    bw, bh = size[0] / scale, size[1] / scale  # the part shown, in the image's px
    left, top = (w - bw) / 2, (h - bh) / 2
    return image.resize(size, Image.Resampling.LANCZOS, box=(left, top, left + bw, top + bh))
