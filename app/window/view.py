"""Where the phone sits in the window: letterboxing and cursor mapping (no GL, no GLFW)."""

from __future__ import annotations

from dataclasses import dataclass

from sim.screen import SIZE as PHONE
from sim.screen import touch_problem

# Room left for window decorations and panels when fitting the monitor's work area.
WORKAREA_MARGIN = 0.95
# The window's sizes, as a fraction of the phone's 760x1280: from a 38x64 thumbnail to
# 3040x5120 (four 4K monitors stacked). --scale and the window both take this range.
SCALES = (0.05, 4.0)


def scale_problem(scale: float) -> str | None:
    """Why the window cannot be `scale` times the phone (NaN too), or None when it can."""
    lo, hi = SCALES
    return None if lo <= scale <= hi else f"scale {scale:g} must be in [{lo:g}, {hi:g}]"


def fit_scale(workarea: tuple[int, int], phone: tuple[int, int] = PHONE,
              most: float = 1.0) -> float:
    """The largest scale <= `most` at which the phone fits the work area (screen
    coordinates), aspect kept."""
    (ww, wh), (pw, ph) = workarea, phone
    if ww <= 0 or wh <= 0:
        return most
    return min(most, WORKAREA_MARGIN * ww / pw, WORKAREA_MARGIN * wh / ph)


def screen_scale(content_scale: float, points: bool) -> float:
    """Screen coordinates a phone px takes at a monitor's content scale: as many as the
    scale where screen coordinates are pixels (Windows, X11: 1.5 at 150 %), one where they
    are points the system scales itself (a Mac: its Retina framebuffer is twice the
    window)."""
    return 1.0 if points or not content_scale > 0 else float(content_scale)


def letterbox(framebuffer_size: tuple[int, int],
              phone: tuple[int, int] = PHONE) -> tuple[int, int, int, int]:
    """The viewport (x, y, w, h), y from the bottom, of the phone centred in the framebuffer."""
    (fw, fh), (pw, ph) = framebuffer_size, phone
    scale = min(fw / pw, fh / ph)
    w, h = max(1, round(pw * scale)), max(1, round(ph * scale))
    return (fw - w) // 2, (fh - h) // 2, w, h


def cursor_to_phone(cursor: tuple[float, float], window_size: tuple[int, int],
                    framebuffer_size: tuple[int, int], phone: tuple[int, int] = PHONE):
    """Phone px (x, y from the top) under a cursor given in window coordinates (y from
    the top, as GLFW reports it), or None outside the phone. Window and framebuffer
    sizes differ on HiDPI screens."""
    (cx, cy), (ww, wh), (fw, fh) = cursor, window_size, framebuffer_size
    if min(ww, wh, fw, fh) <= 0:
        return None
    fx, fy = cx * fw / ww, cy * fh / wh
    vx, vy, vw, vh = letterbox(framebuffer_size, phone)
    top = fh - vy - vh
    px, py = (fx - vx) * phone[0] / vw, (fy - top) * phone[1] / vh
    if touch_problem(px, py, phone):  # the rule sessions and the command line keep too
        return None
    return px, py


@dataclass
class Sizes:
    """The window's size and its framebuffer's (they differ on HiDPI screens), as the
    resize callbacks last reported them."""

    window: tuple[int, int]
    framebuffer: tuple[int, int]

    def phone_at(self, cursor: tuple[float, float]):
        """Phone px under a cursor in window coordinates, or None outside the phone."""
        return cursor_to_phone(cursor, self.window, self.framebuffer)
