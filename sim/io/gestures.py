"""What a finger's drag becomes: touches (left button) and melts (right button, the warm
finger) spaced along its path. The window, headless --melt-path and the scribble
benchmark share these, so a scripted scribble sends what a hand would."""

from __future__ import annotations

import math

# A drag plants a touch every DRAG_SPACING_HC * hc px along the cursor's path.
DRAG_SPACING_HC = 4.0
# A right-button drag melts every MELT_SPACING * melt radius px along the cursor's path.
MELT_SPACING = 0.5


def path_points(start: tuple[float, float], end: tuple[float, float], spacing: float):
    """Points every `spacing` px from `start` (excluded) towards `end`; the last one
    reached becomes the new start of a drag."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    n = int(math.hypot(dx, dy) // spacing)
    length = math.hypot(dx, dy)
    return [(start[0] + dx * k * spacing / length, start[1] + dy * k * spacing / length)
            for k in range(1, n + 1)]
