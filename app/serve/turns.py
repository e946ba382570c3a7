"""Pages' input in turns: each page's commands wait in a queue of its own and go to the
simulation thread a page at a time, while fewer than AHEAD of them wait there.

The thread applies what a tick's budget takes (app/simthread/backlog.py), oldest first. Sent
to it as they came, one page sweeping the pane at its full rate kept 2 000 commands
waiting there, so a person's tap on another page waited behind all of them (or was
dropped with them) while the frost ticked on time: in `frost bench serve`, 2 of 5 taps of
a person's page beside 15 such pages showed within the run. In turns, a command waits
behind at most AHEAD others and one of each other page's; a page's own queue holds at most
PAGE_WAITING, more is dropped (its finger goes on from where it is)."""

from __future__ import annotations

from collections import deque
from typing import Any

from app.simthread.thread import SimThread

# Pages' commands the thread may hold at once: a tick's worth of cheap touches and more (a
# touch costs 0.2-3 ms of a tick's 10 ms of input), so the thread never waits for the loop.
AHEAD = 32
# A page's own commands waiting for their turn: half a second of its fingers' most
# (POINT_RATE, app/serve/pages.py).
PAGE_WAITING = 250


class PageQueue:
    """One page's commands: waiting for their turn, and sent to the thread (their numbers,
    `SimThread.send`'s) and not applied yet."""

    def __init__(self) -> None:
        self.waiting: deque[tuple[str, Any]] = deque()
        self.sent: deque[int] = deque()

    def full(self) -> bool:
        return len(self.waiting) >= PAGE_WAITING


class Turns:
    """The pages' queues of one simulation thread, sent to it in turns (`release`)."""

    def __init__(self, thread: SimThread):
        self.thread = thread
        self.queues: list[PageQueue] = []
        self._first = 0  # the page whose turn comes first at the next release

    def open(self) -> PageQueue:
        queue = PageQueue()
        self.queues.append(queue)
        return queue

    def close(self, queue: PageQueue) -> int:
        """A page went: its commands still waiting are dropped; how many."""
        self.queues.remove(queue)
        return len(queue.waiting)

    def put(self, queue: PageQueue, kind: str, arg: Any = None) -> None:
        """A page's command, sent now if its turn comes at once."""
        queue.waiting.append((kind, arg))
        self.release()

    def waiting(self) -> int:
        """Commands waiting for their turn, all pages'."""
        return sum(len(q.waiting) for q in self.queues)

    def release(self) -> None:
        """Send waiting commands to the thread, one of each page in turn (the first page
        moving on by one each time), while fewer than AHEAD of the pages' wait there."""
        handled = self.thread.handled
        ahead = 0
        for q in self.queues:
            while q.sent and q.sent[0] <= handled:
                q.sent.popleft()
            ahead += len(q.sent)
        n = len(self.queues)
        order = [self.queues[(self._first + k) % n] for k in range(n)]
        self._first = (self._first + 1) % n if n else 0
        while ahead < AHEAD and any(q.waiting for q in order):
            for q in order:
                if q.waiting and ahead < AHEAD:
                    q.sent.append(self.thread.send(*q.waiting.popleft()))
                    ahead += 1
