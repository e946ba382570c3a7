"""The phone screen every part of frost draws on: its size, and which points lie on it.

One place for both, so the simulation, the window, the offline tools and the command
line agree on what "on the screen" means (no GL here)."""

from __future__ import annotations

import math

WIDTH, HEIGHT = 760, 1280  # the phone screen, px (origin top-left, y down)
SIZE = (WIDTH, HEIGHT)


def touch_problem(x: float, y: float, size: tuple[int, int] = SIZE) -> str | None:
    """Why a touch at (x, y) px cannot land on a `size` screen, or None when it can.
    NaN and infinities are off every screen."""
    w, h = size
    if math.isfinite(x) and math.isfinite(y) and 0 <= x < w and 0 <= y < h:
        return None
    return f"touch ({x:g}, {y:g}) is off the {w}x{h} screen"


def check_touch(x: float, y: float, size: tuple[int, int] = SIZE) -> tuple[float, float]:
    """(x, y) as floats when the touch lands on the screen; ValueError naming it if not."""
    problem = touch_problem(float(x), float(y), size)
    if problem:
        raise ValueError(problem)
    return float(x), float(y)
