"""The lock screen's new minute drawn off the frame loop: its clock box takes 18 ms to
draw on a quiet 2-core machine (the text and its blurred shadow, app/lockscreen.py) and
40-75 ms under load, a dropped frame each minute if the loop drew it. One worker draws it;
the loop uploads the box when it is ready (a texture write, well under a millisecond)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np


class ClockDrawer:
    """`draw(minute, outside)` (app.gl.Renderer.clock_box) on one worker; `wake()` after each."""

    def __init__(self, draw: Callable[[str, str], np.ndarray], wake: Callable[[], None]):
        self.draw, self.wake = draw, wake
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="frost-clock")
        self.asked: tuple[str, str] | None = None  # the newest (minute, outside) asked for
        self._future: Future | None = None

    def ask(self, minute: str, outside: str = "") -> None:
        """Draw `minute` with `outside` under it (once: asking again for what was asked
        last does nothing)."""
        if (minute, outside) == self.asked:
            return
        self.asked = (minute, outside)
        self._future = self._pool.submit(self.draw, minute, outside)
        self._future.add_done_callback(lambda _f: self.wake())

    def ready(self) -> tuple[str, str, np.ndarray] | None:
        """(minute, outside, box) of the newest asked once it is drawn, then None until the
        next; a drawing that failed raises its error here, on the loop's thread."""
        future = self._future
        if future is None or not future.done() or self.asked is None:
            return None
        self._future = None
        return (*self.asked, future.result())

    def follow(self, renderer, minute: str | None, outside: str) -> bool:
        """The renderer's clock to show `minute` (None: the one it shows) with `outside`
        under it: asked of the worker where the renderer patches its clock box, else set
        at once. True when that changes what is shown."""
        minute = minute or renderer.minute
        if (minute, outside) == (renderer.minute, renderer.outside):
            return False
        if renderer.patches_clock():  # (its clock box alone, drawn on the worker)
            self.ask(minute, outside)
        else:
            renderer.set_minute(minute, outside=outside)
        return True

    def upload(self, renderer) -> bool:
        """The newest drawing, once ready, given to the renderer (unless it shows that
        already); True when it did."""
        drawn = self.ready()
        if drawn is None or drawn[:2] == (renderer.minute, renderer.outside):
            return False
        renderer.set_minute(drawn[0], drawn[2], outside=drawn[1])
        return True

    def close(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)
