"""The feed's simulation thread ticked by hand, and a page's socket that is never written."""

from __future__ import annotations

import queue

from app.serve.feed import Feed
from app.simthread.schedule import Schedule
from app.simthread.thread import SimThread


class ByHand:
    """A schedule for `thread` that ticks when `tick` says; it starts the thread."""

    def __init__(self, thread: SimThread):
        self.orders: queue.Queue[bool] = queue.Queue()
        self.idle: queue.Queue[None] = queue.Queue()
        thread.schedule = Schedule(1.0, self._wait)
        thread.start()
        self.idle.get(timeout=30)

    def _wait(self, _seconds: float) -> bool:
        self.idle.put(None)
        return self.orders.get()  # True: stop

    def order(self) -> None:
        """One tick, begun; `done` waits for its end."""
        self.orders.put(False)

    def done(self) -> None:
        self.idle.get(timeout=60)

    def tick(self, feed: Feed, count: int = 1) -> None:
        """`count` ticks, each published at once."""
        for _ in range(count):
            self.order()
            self.done()
            feed.pump()

    def stop(self) -> None:
        self.orders.put(True)


class Wire:
    """A socket that is never written to: the page's queue is what it was sent."""

    async def send_bytes(self, data):  # pragma: no cover - the writer never runs here
        raise AssertionError("not written")

    send_str = send_bytes
