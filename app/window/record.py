"""Recording: phone frames, downscaled and thinned, written as an animated WebP on stop.

Each frame lasts in the file as long as it did on the screen (the time to the next frame
kept, the last one's until R stopped it), so a recording plays at the speed it was made,
whatever the frame rate was. A frame the same as the last one kept is not kept again: the
last one lasts longer, so a still scene holds one frame however long it is recorded.
Frames wait in memory until the stop: a recording is written when it reaches MAX_FRAMES
distinct frames and then keeps no more until R ends it (R always starts or stops).
Encoding runs on a writer thread so the window keeps drawing; `close` waits.
"""

from __future__ import annotations

import io
import logging
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from PIL import Image, ImageChops

from app.images import timestamped_path
from sim.io.files import why, write_atomic

log = logging.getLogger("app.window")

# 380x640 and at most 12.5 frames a second: about 1 MB a frame in memory (Pillow holds an
# RGB pixel in 4 bytes).
FRAME_SIZE = (380, 640)
FRAME_GAP = 0.08  # s: a frame offered sooner after the last one looked at is skipped
# The distinct frames held in memory: 30 s of a scene changing at the full rate, about
# 365 MB. At the cap the recording is written and keeps no more frames; the next R ends it.
MAX_FRAMES = 375
QUALITY = 80  # WebP's lossy quality

Tell = Callable[[int, str], None]  # (logging level, text): to the HUD and the log


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
    if len(frames) == 1:  # a still scene (no two frames kept in a row are the same)
        data = still_animation(frames[0], sum(durations))
        write_atomic(path, lambda f: f.write(data))
    else:
        write_atomic(path, lambda f: frames[0].save(
            f, format="WEBP", save_all=True, append_images=frames[1:], duration=durations,
            loop=0, quality=QUALITY, method=0))
    log.debug("recording: %d frames encoded into %s", len(frames), path)
    return path


def still_animation(frame: Image.Image, duration: int) -> bytes:
    """An animated WebP of one RGB frame shown `duration` ms. (libwebp merges identical
    frames and writes a lone frame as a still image, which has no duration.) The frame's
    bitstream in the container's animation chunks: VP8X, ANIM, then one ANMF."""
    still = io.BytesIO()
    frame.save(still, format="WEBP", quality=QUALITY, method=0)
    bitstream = still.getvalue()[12:]  # after "RIFF", its size, "WEBP": the VP8 chunk
    w, h = (_u24(n - 1) for n in frame.size)
    body = (b"WEBP" + _chunk(b"VP8X", b"\x02\0\0\0" + w + h)  # flag: animation
            + _chunk(b"ANIM", bytes(6))  # background 0, loop forever
            + _chunk(b"ANMF", _u24(0) + _u24(0) + w + h + _u24(duration) + b"\x02" + bitstream))
    return b"RIFF" + len(body).to_bytes(4, "little") + body


def same(a: Image.Image, b: Image.Image) -> bool:
    """Exactly the same pixels (frames of one size and mode). One pass in C over a
    difference image: a third of comparing their tobytes() (171 vs 497 us at 380x640)."""
    return ImageChops.difference(a, b).getbbox() is None


def _chunk(tag: bytes, payload: bytes) -> bytes:
    return tag + len(payload).to_bytes(4, "little") + payload + b"\0" * (len(payload) % 2)


def _u24(n: int) -> bytes:
    return n.to_bytes(3, "little")


def _write_or_report(frames: list[Image.Image], durations: list[int], path: Path,
                     tell: Tell) -> None:
    """The writer thread: done or failed, `tell` says so; nothing kills the app."""
    try:
        write_animation(frames, durations, path)
    except OSError as err:
        tell(logging.WARNING, f"recording NOT written: {why(err, path)}")
        return
    tell(logging.INFO, f"recording: {len(frames)} frames ({sum(durations) / 1000:.1f} s) "
         f"written to {path}")


class Recorder:
    """R's recording: off, recording, or full (written at MAX_FRAMES, until R ends it)."""

    def __init__(self, folder: str | Path, tell: Tell | None = None, clock=time.monotonic):
        self.folder, self.clock = folder, clock
        # What it says, from any thread: the window's HUD and log; else the log.
        self.tell = tell or log.log
        self.frames: list[Image.Image] | None = None
        self.times: list[float] = []  # when each frame kept was offered (clock's seconds)
        # The last frame looked at: when (clock's seconds), and its render count (`offer`).
        self.looked: tuple[float, int | None] | None = None
        self.full = False  # written at the cap; R ends it
        self.names: set[str] = set()  # stems of this run's recordings
        self._writers: list[threading.Thread] = []

    @property
    def active(self) -> bool:
        """Keeping frames."""
        return self.frames is not None

    @property
    def count(self) -> int:
        return len(self.frames) if self.frames is not None else 0

    def readout(self) -> str | None:
        """The HUD's word for it: None while off."""
        if self.full:
            return f"REC full ({MAX_FRAMES} frames written, R ends)"
        return f"REC {self.count} frames" if self.active else None

    def toggle(self) -> None:
        self.stop() if self.active or self.full else self.start()

    def start(self) -> None:
        self.frames, self.times, self.looked = [], [], None
        self.tell(logging.INFO, "recording: started")

    def offer(self, read, drawn: int | None = None) -> None:
        """A new phone frame is on the screen now; `read()` returns it (HxWx3 uint8,
        top-down). `drawn`, if given, counts the phone's renders: the same count as the
        frame last looked at is the same frame, not read again (a read and its downscale
        cost ~15 ms on llvmpipe; a still scene would pay them 12.5 times a second)."""
        now = self.clock()
        if self.frames is None or (self.looked and now - self.looked[0] < FRAME_GAP):
            return
        if self.looked and drawn is not None and drawn == self.looked[1]:
            return
        self.looked = (now, drawn)
        image: np.ndarray = read()
        frame = Image.fromarray(image).resize(FRAME_SIZE, Image.Resampling.BILINEAR)
        if self.frames and same(frame, self.frames[-1]):
            return  # the last frame kept lasts on: its time runs to the next one kept
        self.frames.append(frame)
        self.times.append(now)
        if len(self.frames) >= MAX_FRAMES:
            self.tell(logging.WARNING, f"recording: {MAX_FRAMES} frames is the cap: written, "
                      "no more kept (R ends it)")
            self._write(now + FRAME_GAP)
            self.full = True

    def stop(self) -> None:
        if self.full:
            self.full = False
            self.tell(logging.INFO, "recording: ended (written at the cap)")
        elif not self.frames:
            self.frames = None
            self.tell(logging.INFO, "recording: stopped with no frames")
        else:
            self._write(self.clock())

    def _write(self, end: float) -> None:
        """The frames kept, the last one lasting until `end`, to a new file by a writer."""
        frames, self.frames = self.frames, None
        assert frames  # (stop and offer call it with frames kept)
        durations = frame_durations(self.times, end)
        try:
            path = recording_path(self.folder, self.names)
        except OSError as err:
            self.tell(logging.WARNING,
                      f"recording: {len(frames)} frames lost: {why(err, self.folder)}")
            return
        self.names.add(path.stem)
        writer = threading.Thread(target=_write_or_report, name="frost-rec",
                                  args=(frames, durations, path, self.tell))
        writer.start()
        self._writers.append(writer)

    def close(self) -> None:
        """Write a recording still running and wait for every writer."""
        if self.active:
            self.stop()
        for writer in self._writers:
            writer.join()
