"""The lock screen's live clock: the time and the date drawn over the `lockscreen`
backdrop's clock box, each minute, by the window, `frost render`, `frost replay` and
`frost serve` alike. No GL here.

`assets/lockscreen.png` (drawn by `assets/make_lockscreen.py`) holds the lock screen's
static parts, with the box left as bare wallpaper; `clock_patch` draws a minute over the
box's own pixels, and `with_clock` gives the whole backdrop at that minute. A minute is
named as session files record it: local time, "YYYY-MM-DDTHH:MM" (`minute_name`). With the
weather outside (--weather), the temperature outside is drawn under the clock, in the box
too (`outside_line`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from datetime import datetime, timedelta

import numpy as np
from PIL import Image, ImageDraw, ImageFilter, ImageFont

from sim.io.session import MINUTE_FORMAT
from sim.screen import HEIGHT, WIDTH

# The clock's rectangle on the 760x1280 backdrop: x0, y0, x1, y1 (px, y down). The
# minute's change is these pixels only; nothing static is drawn inside it.
CLOCK_BOX = (40, 150, 720, 470)
# Each line of the box: its centre (px from the box's top, centred across it) and its size
# (px): the date, the time, and the temperature outside (the time's figures end 56 px above
# it; the box 26 px below). The page draws its own box with these too (app/web/lockclock.js).
CLOCK_LINES = {"date": (52, 40), "time": (188, 196), "outside": (294, 36)}
# The minute `frost render` and a session with no minute of its own show (a render is
# the same every time): a Thursday morning, 09:41.
DEFAULT_MINUTE = "2026-11-26T09:41"
TEXT = (248, 249, 252)
SHADOW = (8, 14, 34)


def font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """Pillow's built-in scalable font (Aileron Regular, in Pillow since 10.1) at `size` px."""
    return ImageFont.load_default(size=size)


def minute_name(when: datetime) -> str:
    """`when` to the minute, as session files and the protocol name it."""
    return when.strftime(MINUTE_FORMAT)


def parse_minute(text: str) -> datetime:
    """The minute named by `text` ("YYYY-MM-DDTHH:MM"); ValueError in one line if not one."""
    try:
        return datetime.strptime(text, MINUTE_FORMAT)
    except (TypeError, ValueError):
        raise ValueError(f"minute {str(text)[:40]!r} is not YYYY-MM-DDTHH:MM") from None


def parse_clock(text: str) -> datetime:
    """A clock given on the command line: "HH:MM" or "HH:MM:SS" (on DEFAULT_MINUTE's day),
    "YYYY-MM-DDTHH:MM" or "YYYY-MM-DDTHH:MM:SS"; ValueError in one line if not one."""
    day = DEFAULT_MINUTE[:10]
    for full in (f"{day}T{text}", text):
        for fmt in (MINUTE_FORMAT, MINUTE_FORMAT + ":%S"):
            try:
                return datetime.strptime(full, fmt)
            except ValueError:
                continue
    raise ValueError(f"clock {text[:40]!r}: give HH:MM[:SS] or YYYY-MM-DDTHH:MM[:SS]")


def clock_from(start: datetime | None) -> Callable[[], datetime]:
    """The time now, local (None), or a clock that reads `start` now and runs on in real
    time from there (--clock-start: demos and tests see a minute turn when they choose)."""
    if start is None:
        return datetime.now
    began = time.monotonic()
    return lambda: start + timedelta(seconds=time.monotonic() - began)


def outside_line(weather: dict | None) -> str:
    """What the lock screen says under its clock of the weather event `weather` (a
    snapshot's or an applied event's {"reading": ..., "glass": ...}): the temperature
    outside in whole degrees, e.g. "-25 °C outside" (the font has no typographic minus);
    "" without a reading."""
    if not weather:
        return ""
    return f"{round(weather['reading']['temperature_c']):d} °C outside"  # (an int: never "-0")


def clock_patch(static: np.ndarray, minute: str, outside: str = "") -> np.ndarray:
    """The clock box of the backdrop at `minute`: `static`'s (the whole 760x1280 static
    backdrop, H x W x 3 uint8) box pixels with the date and the time drawn over them, and
    `outside` (`outside_line`'s) under the time."""
    x0, y0, x1, y1 = CLOCK_BOX
    when = parse_minute(minute)
    box = Image.fromarray(np.ascontiguousarray(static[y0:y1, x0:x1]))
    w, h = box.size
    date = f"{when:%A} {when.day} {when:%B}"
    clock = f"{when:%H:%M}"
    # A soft shadow under the white figures keeps them legible on a bright sky.
    mask = Image.new("L", (w, h), 0)
    shadow = ImageDraw.Draw(mask)
    _text(shadow, date, clock, outside, 255)
    mask = mask.filter(ImageFilter.GaussianBlur(7)).point(lambda v: v * 0.55)
    box.paste(Image.new("RGB", (w, h), SHADOW), (0, 0), mask)
    _text(ImageDraw.Draw(box), date, clock, outside, TEXT)
    return np.asarray(box)


def _text(draw: ImageDraw.ImageDraw, date: str, clock: str, outside: str, fill) -> None:
    w = CLOCK_BOX[2] - CLOCK_BOX[0]
    for name, text in (("date", date), ("time", clock), ("outside", outside)):
        if text:
            y, size = CLOCK_LINES[name]
            draw.text((w / 2, y), text, font=font(size), fill=fill, anchor="mm")


def with_clock(static: np.ndarray, minute: str, outside: str = "") -> np.ndarray:
    """The whole lock screen at `minute`: `static` with its clock box drawn (`outside`
    under the time)."""
    if static.shape[:2] != (HEIGHT, WIDTH):
        raise ValueError(f"the lock screen is {WIDTH}x{HEIGHT}, not "
                         f"{static.shape[1]}x{static.shape[0]}")
    out = np.array(static, np.uint8)
    x0, y0, x1, y1 = CLOCK_BOX
    out[y0:y1, x0:x1] = clock_patch(static, minute, outside)
    return out
