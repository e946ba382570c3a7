"""Pages' input in turns: each page's commands wait in a queue of its own and go to the
simulation thread one at a time, each to the page served longest ago, while fewer wait
there than the thread lately applies in two ticks (at least MIN_AHEAD, at most AHEAD).

The thread applies what a tick's budget takes (app/simthread/backlog.py), oldest first. Sent
to it as they came, one page sweeping the pane at its full rate kept 2 000 commands
waiting there, so a person's tap on another page waited behind all of them (or was
dropped with them) while the frost ticked on time. In turns, pages that send without end
share the thread's input in rotation, and a person's tap (their page served less lately
than any of those) goes to the thread at the next command's turn and waits behind about
two ticks' worth; a page's own queue holds at most PAGE_WAITING, more is dropped (its
finger goes on from where it is). A page that goes leaves its waiting commands to their
turns: it may have been told they were taken."""

from __future__ import annotations

from collections import deque
from typing import Any

from app.simthread.thread import SimThread

# Pages' commands the thread may hold at once: twice what it applied in its last tick,
# within these bounds (a touch costs 0.2-10 ms of a tick's 3-10 ms of input: 1 to 40 a
# tick), so the thread has its next tick's input and a person's tap waits behind little.
MIN_AHEAD, AHEAD = 4, 64
# A page's own commands waiting for their turn: half a second of its fingers' most
# (POINT_RATE, app/serve/pages.py).
PAGE_WAITING = 250


class PageQueue:
    """One page's commands: waiting for their turn, and sent to the thread (their numbers,
    `SimThread.send`'s) and not applied yet."""

    def __init__(self) -> None:
        self.waiting: deque[tuple[str, Any]] = deque()
        self.sent: deque[int] = deque()
        self.served = -1  # the number of the page's command sent last (-1: none yet)
        self.closed = False  # its page went (`Turns.close`)
        self.dropped_here = 0  # its touches and melts dropped: too much waited (controls.py)

    def full(self) -> bool:
        return len(self.waiting) >= PAGE_WAITING


class Turns:
    """The pages' queues of one simulation thread, sent to it in turns (`release`)."""

    def __init__(self, thread: SimThread):
        self.thread = thread
        self.queues: list[PageQueue] = []
        self._handled = 0  # the thread's `handled` at the last tick
        self.ahead = MIN_AHEAD  # pages' commands the thread may hold now

    def open(self) -> PageQueue:
        queue = PageQueue()
        self.queues.append(queue)
        return queue

    def close(self, queue: PageQueue) -> None:
        """A page went: its commands still waiting go on to the thread in their turns (the
        page may have been told they were taken: a pong after them); then its queue goes."""
        queue.closed = True
        if not queue.waiting:
            self.queues.remove(queue)

    def put(self, queue: PageQueue, kind: str, arg: Any = None) -> None:
        """A page's command, sent now if its turn comes at once."""
        queue.waiting.append((kind, arg))
        self.release()

    def waiting(self) -> int:
        """Commands waiting for their turn, all pages'."""
        return sum(len(q.waiting) for q in self.queues)

    def release(self, ticked: bool = False) -> None:
        """Send waiting commands to the thread while it holds fewer than `ahead` of the
        pages', each of the page served longest ago (pages that never were first, in the
        order they came). `ticked`: the thread ticked since the last such call, so `ahead`
        follows what it applied."""
        handled = self.thread.handled
        if ticked:
            self.ahead = min(AHEAD, max(MIN_AHEAD, 2 * (handled - self._handled)))
            self._handled = handled
        there = 0
        for q in self.queues:
            while q.sent and q.sent[0] <= handled:
                q.sent.popleft()
            there += len(q.sent)
        while there < self.ahead and self._send_next():
            there += 1

    def flush(self) -> None:
        """Every page's waiting commands sent to the thread now, in turns: the server is
        ending, and what a page was told the server has must reach the session."""
        while self._send_next():
            pass

    def _send_next(self) -> bool:
        """The next command of the page served longest ago sent; False: none waits."""
        waiting = [q for q in self.queues if q.waiting]
        if not waiting:
            return False
        q = min(waiting, key=lambda q: q.served)
        q.served = self.thread.send(*q.waiting.popleft())
        q.sent.append(q.served)
        if q.closed and not q.waiting:
            self.queues.remove(q)
        return True
