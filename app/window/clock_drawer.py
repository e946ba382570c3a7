"""The lock screen's new minute drawn off the frame loop: its clock box takes 18 ms to
draw on a quiet 2-core machine (the text and its blurred shadow, app/lockscreen.py) and
40-75 ms under load, a dropped frame each minute if the loop drew it. One worker draws it;
the loop uploads the box when it is ready (a texture write, well under a millisecond)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np


class ClockDrawer:
    """`draw(minute)` (app.gl.Renderer.clock_box) on one worker; `wake()` after each."""

    def __init__(self, draw: Callable[[str], np.ndarray], wake: Callable[[], None]):
        self.draw, self.wake = draw, wake
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="frost-clock")
        self.asked: str | None = None  # the newest minute asked for
        self._future: Future | None = None

    def ask(self, minute: str) -> None:
        """Draw `minute` (once: asking again for the minute asked last does nothing)."""
        if minute == self.asked:
            return
        self.asked = minute
        self._future = self._pool.submit(self.draw, minute)
        self._future.add_done_callback(lambda _f: self.wake())

    def ready(self) -> tuple[str, np.ndarray] | None:
        """(minute, box) of the newest minute asked once it is drawn, then None until the
        next; a drawing that failed raises its error here, on the loop's thread."""
        future = self._future
        if future is None or not future.done():
            return None
        self._future = None
        return self.asked or "", future.result()

    def close(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)
