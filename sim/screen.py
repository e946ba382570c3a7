"""The phone screen every part of frost draws on: its size, which points lie on it, its
tick rate and the warm finger's default radius.

One place for both, so the simulation, the window, the offline tools and the command
line agree on what "on the screen" means (no GL here)."""

from __future__ import annotations

import math

WIDTH, HEIGHT = 760, 1280  # the phone screen, px (origin top-left, y down)
SIZE = (WIDTH, HEIGHT)
# The warm finger's largest radius, px: several times the screen's diagonal (1 489 px),
# so one melt can clear it all; the window's --melt-radius, a --melt's R and a session's
# melts all keep to it.
MAX_MELT_RADIUS = 10_000.0
# The warm finger's radius when none is given (the window's right button), px.
MELT_RADIUS = 24.0
# The simulation's fixed rate: ticks a second, live and in every scripted run.
TICKS_PER_SECOND = 25


def touch_problem(x: float, y: float, size: tuple[int, int] = SIZE, what: str = "touch") -> str | None:
    """Why a touch (or `what`) at (x, y) px cannot land on a `size` screen, or None when it
    can. NaN and infinities are off every screen."""
    w, h = size
    if math.isfinite(x) and math.isfinite(y) and 0 <= x < w and 0 <= y < h:
        return None
    return f"{what} ({x:g}, {y:g}) is off the {w}x{h} screen"


def radius_problem(r: float) -> str | None:
    """Why `r` px cannot be a melt's radius, or None when it can (NaN cannot)."""
    if 0 < r <= MAX_MELT_RADIUS:
        return None
    return f"melt radius {r:g} must be in (0, {MAX_MELT_RADIUS:g}] px"


def melt_problem(x: float, y: float, r: float, size: tuple[int, int] = SIZE) -> str | None:
    """Why a melt of radius `r` at (x, y) cannot be made, or None when it can: its centre
    is on the screen (where a finger can be) and its radius in range."""
    return radius_problem(r) or touch_problem(x, y, size, "melt")

