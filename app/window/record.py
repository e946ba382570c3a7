"""Recording: phone frames, downscaled and thinned, written as an animated WebP on stop.

Encoding runs on a writer thread so the window keeps drawing; `close` waits for it.
"""

from __future__ import annotations

import logging
import threading
from datetime import datetime
from pathlib import Path

import numpy as np
from PIL import Image

from sim.files import why, write_atomic

log = logging.getLogger("app.window")

# 380x640 and every 2nd phone frame: about 0.7 MB a frame, 12.5 frames a second.
FRAME_SIZE = (380, 640)
KEEP_EVERY = 2
FRAME_MS = 80  # two ticks at 25 ticks/s
# At most 30 s (about 270 MB); recording stops and writes itself at the cap.
MAX_FRAMES = 375


def recording_path(folder: str | Path) -> Path:
    """frost-<time>.webp in `folder`, never an existing name."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    stem = "frost-" + datetime.now().strftime("%Y%m%d-%H%M%S")
    path, n = folder / f"{stem}.webp", 1
    while path.exists():
        path, n = folder / f"{stem}-{n}.webp", n + 1
    return path


def write_animation(frames: list[Image.Image], path: Path) -> Path:
    """Encode `frames` to `path` atomically (a half-written WebP never appears)."""
    write_atomic(path, lambda f: frames[0].save(
        f, format="WEBP", save_all=True, append_images=frames[1:], duration=FRAME_MS,
        loop=0, quality=80, method=0))
    log.info("recording: %d frames written to %s", len(frames), path)
    return path


def _write_or_report(frames: list[Image.Image], path: Path, report) -> None:
    """The writer thread: a failure goes to `report`, never kills the app."""
    try:
        write_animation(frames, path)
    except OSError as err:
        report(f"recording NOT written: {why(err, path)}")


class Recorder:
    def __init__(self, folder: str | Path, report=None):
        self.folder = folder
        # Where a failed write is told (from any thread): the window's HUD; else the log.
        self.report = report or (lambda text: log.warning("%s", text))
        self.frames: list[Image.Image] | None = None
        self._offered = 0
        self._writers: list[threading.Thread] = []

    @property
    def active(self) -> bool:
        return self.frames is not None

    @property
    def count(self) -> int:
        return len(self.frames) if self.frames is not None else 0

    def toggle(self) -> None:
        self.stop() if self.active else self.start()

    def start(self) -> None:
        self.frames, self._offered = [], 0
        log.info("recording: started")

    def offer(self, read) -> None:
        """A new phone frame exists; `read()` returns it (HxWx3 uint8, top-down)."""
        if self.frames is None:
            return
        self._offered += 1
        if (self._offered - 1) % KEEP_EVERY:
            return
        image: np.ndarray = read()
        self.frames.append(Image.fromarray(image).resize(FRAME_SIZE, Image.Resampling.BILINEAR))
        if len(self.frames) >= MAX_FRAMES:
            log.info("recording: %d frames is the cap", MAX_FRAMES)
            self.stop()

    def stop(self) -> None:
        frames, self.frames = self.frames, None
        if not frames:
            log.info("recording: stopped with no frames")
            return
        try:
            path = recording_path(self.folder)
        except OSError as err:
            self.report(f"recording: {len(frames)} frames lost: {why(err, self.folder)}")
            return
        writer = threading.Thread(target=_write_or_report, args=(frames, path, self.report),
                                  name="frost-rec")
        writer.start()
        self._writers.append(writer)

    def close(self) -> None:
        """Write a recording still running and wait for every writer."""
        if self.active:
            self.stop()
        for writer in self._writers:
            writer.join()
