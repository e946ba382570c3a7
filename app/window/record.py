"""Recording: phone frames, downscaled and thinned, written as an animated WebP on stop.

Each frame lasts in the file as long as it did on the screen (the time to the next frame
kept), so a recording plays at the speed it was made, whatever the frame rate was.
Encoding runs on a writer thread so the window keeps drawing; `close` waits for it.
"""

from __future__ import annotations

import logging
import threading
import time
from pathlib import Path

import numpy as np
from PIL import Image

from app.images import timestamped_path
from sim.io.files import why, write_atomic

log = logging.getLogger("app.window")

# 380x640 and at most 12.5 frames a second: about 0.7 MB a frame.
FRAME_SIZE = (380, 640)
FRAME_GAP = 0.08  # s: a frame offered sooner after the last one kept is skipped
# At most 30 s at the full rate (about 270 MB); recording stops and writes itself at the cap.
MAX_FRAMES = 375


def recording_path(folder: str | Path, taken=()) -> Path:
    """frost-<time>.webp in `folder`, never an existing name nor one in `taken` (the
    recordings of this run, whose writers may not have finished)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return timestamped_path(folder, suffix=".webp", taken=taken)


def frame_durations(times: list[float], end: float) -> list[int]:
    """Milliseconds each frame shows: from its time to the next frame's, the last until
    `end` (at least FRAME_GAP). Rounded on the running total, so they add up to the
    whole recording's length to the millisecond."""
    ends = [*times[1:], max(end, times[-1] + FRAME_GAP)]
    marks = [round((t - times[0]) * 1000.0) for t in (times[0], *ends)]
    return [b - a for a, b in zip(marks, marks[1:], strict=False)]


def write_animation(frames: list[Image.Image], durations: list[int], path: Path) -> Path:
    """Encode `frames` (each shown its duration, ms) to `path` atomically (a half-written
    WebP never appears)."""
    write_atomic(path, lambda f: frames[0].save(
        f, format="WEBP", save_all=True, append_images=frames[1:], duration=durations,
        loop=0, quality=80, method=0))
    log.info("recording: %d frames (%.1f s) written to %s", len(frames), sum(durations) / 1000,
             path)
    return path


def _write_or_report(frames: list[Image.Image], durations: list[int], path: Path,
                     report) -> None:
    """The writer thread: a failure goes to `report`, never kills the app."""
    try:
        write_animation(frames, durations, path)
    except OSError as err:
        report(f"recording NOT written: {why(err, path)}")


class Recorder:
    def __init__(self, folder: str | Path, report=None, clock=time.monotonic):
        self.folder, self.clock = folder, clock
        # Where a failed write is told (from any thread): the window's HUD; else the log.
        self.report = report or (lambda text: log.warning("%s", text))
        self.frames: list[Image.Image] | None = None
        self.times: list[float] = []  # when each frame kept was offered (clock's seconds)
        self.names: set[str] = set()  # stems of this run's recordings
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
        self.frames, self.times = [], []
        log.info("recording: started")

    def offer(self, read) -> None:
        """A new phone frame is on the screen now; `read()` returns it (HxWx3 uint8,
        top-down)."""
        now = self.clock()
        if self.frames is None or (self.times and now - self.times[-1] < FRAME_GAP):
            return
        image: np.ndarray = read()
        self.frames.append(Image.fromarray(image).resize(FRAME_SIZE, Image.Resampling.BILINEAR))
        self.times.append(now)
        if len(self.frames) >= MAX_FRAMES:
            log.info("recording: %d frames is the cap", MAX_FRAMES)
            self.stop()

    def stop(self) -> None:
        frames, self.frames = self.frames, None
        if not frames:
            log.info("recording: stopped with no frames")
            return
        durations = frame_durations(self.times, self.clock())
        try:
            path = recording_path(self.folder, self.names)
        except OSError as err:
            self.report(f"recording: {len(frames)} frames lost: {why(err, self.folder)}")
            return
        self.names.add(path.stem)
        writer = threading.Thread(target=_write_or_report, name="frost-rec",
                                  args=(frames, durations, path, self.report))
        writer.start()
        self._writers.append(writer)

    def close(self) -> None:
        """Write a recording still running and wait for every writer."""
        if self.active:
            self.stop()
        for writer in self._writers:
            writer.join()
