"""Work drawn off the asyncio loop: the feed's snapshots and the lock screen's minutes."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any


class Workers:
    """The loop's default executor while the loop runs; the caller's own thread otherwise
    (a test's pump, or the last pump at the end), so the work is never left undone."""

    def __init__(self) -> None:
        self.loop: asyncio.AbstractEventLoop | None = None  # set when the server starts

    def run(self, work: Callable[[Any], Any], arg: Any, done: Callable[[Any], None]) -> None:
        """`done(work(arg))`: `work` on a worker and `done` back on the loop while it runs
        (not at all if the loop cancels it), both here otherwise."""
        loop = self.loop
        if loop is None or not loop.is_running():
            done(work(arg))
            return
        future = loop.run_in_executor(None, work, arg)
        future.add_done_callback(lambda f: None if f.cancelled() else done(f.result()))
