"""Who the simulation thread tells of its snapshots and notices, and the work it runs
between two ticks for them."""

from __future__ import annotations

import queue
from collections.abc import Callable
from typing import Generic, TypeVar

from app.simthread.commands import take_all

S = TypeVar("S")  # a snapshot


class Readers(Generic[S]):
    """The maker (its `wake`, its `outbox`), then each reader that subscribed, with a
    queue of snapshots of its own; the notices for the HUD and the log."""

    def __init__(self, wake: Callable[[], None] | None):
        self.outbox: queue.Queue[S] = queue.Queue()  # the maker's snapshots (drain)
        # (logging level, text) from the thread's workers, for the HUD and the log.
        self.notices: queue.Queue[tuple[int, str]] = queue.Queue()
        self._wakes: list[Callable[[], None]] = [wake] if wake is not None else []
        self._readers: list[queue.Queue[S]] = []
        self._between: queue.Queue[Callable[[], None]] = queue.Queue()

    def drain(self) -> list[S]:
        """Every snapshot produced since the last call, oldest first (the maker's)."""
        return take_all(self.outbox)

    def subscribe(self, wake: Callable[[], None]) -> Callable[[], list[S]]:
        """Another reader of the snapshots: each one published from now on goes to a queue
        of its own too, and `wake()` is called after it (on the thread) and after each
        notice (on the thread that made it). Returns the reader's drain."""
        mine: queue.Queue[S] = queue.Queue()
        self._readers.append(mine)
        self._wakes.append(wake)
        return lambda: take_all(mine)

    def between_ticks(self, work: Callable[[], None]) -> None:
        """`work()` once, on the thread that ticks, right after the tick under way (or the
        next) has published its snapshot and before the next tick begins: the simulation
        holds still while it runs (a page's snapshot is drawn from it there)."""
        self._between.put(work)

    def wake(self) -> None:
        """Tell every reader that a snapshot or a notice is waiting."""
        for wake in self._wakes:
            wake()

    def notify(self, level: int, text: str) -> None:
        """A message for the main thread (any thread may call it)."""
        self.notices.put((level, text))
        self.wake()

    def publish(self, snapshot: S) -> None:
        """`snapshot` to every reader, the work asked between ticks, then the wake-ups."""
        self.outbox.put(snapshot)
        for reader in self._readers:
            reader.put(snapshot)
        for work in take_all(self._between):
            work()
        self.wake()
