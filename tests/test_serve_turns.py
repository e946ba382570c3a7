"""Pages' input in turns (app/serve/turns.py), against a thread that only counts: the
commands each release sends, worked out by hand."""

from __future__ import annotations

from app.serve import turns
from app.serve.turns import Turns


class Counting:
    """A simulation thread's `send` and `handled`, and what it was sent."""

    def __init__(self) -> None:
        self.sent, self.handled, self.got = 0, 0, []

    def send(self, kind, arg=None) -> int:
        self.sent += 1
        self.got.append(arg)
        return self.sent


def test_each_command_goes_to_the_page_served_longest_ago():
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    a, b, c = t.open(), t.open(), t.open()
    for k in range(6):
        a.waiting.append(("touch", f"a{k}"))
    b.waiting.append(("touch", "b0"))
    t.release()  # the thread may hold MIN_AHEAD (4): a0, then b0 (never served), a1, a2
    assert turns.MIN_AHEAD == 4 and thread.got == ["a0", "b0", "a1", "a2"]
    t.release()  # nothing applied: nothing more
    assert thread.sent == 4 and t.waiting() == 3
    thread.handled = 2  # a0 and b0 applied: two in the thread, room for two
    c.waiting.append(("touch", "c0"))
    t.release(ticked=True)  # c never served: c0 first, then a3
    assert thread.got[4:] == ["c0", "a3"]
    thread.handled = 6
    t.put(c, "touch", "c1")  # c served before a's last: c1, then a4 and a5
    assert thread.got[6:] == ["c1", "a4", "a5"] and t.waiting() == 0


def test_the_thread_holds_twice_what_it_applied_in_its_last_tick():
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    q = t.open()
    for applied, ahead in ((0, turns.MIN_AHEAD), (1, turns.MIN_AHEAD), (20, 40),
                           (100, turns.AHEAD)):
        thread.handled += applied
        t.release(ticked=True)
        assert t.ahead == ahead, applied
    for k in range(100):
        q.waiting.append(("touch", k))
    t.release()
    assert thread.sent == turns.AHEAD  # (the thread holds nothing else)


def test_a_page_that_goes_leaves_its_waiting_commands_to_their_turns():
    """(It may have been told they were taken: a pong after them.) Its queue goes once
    they are all sent."""
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    a, b = t.open(), t.open()
    for k in range(6):
        a.waiting.append(("touch", f"a{k}"))
    t.release()
    assert thread.got == ["a0", "a1", "a2", "a3"]
    t.close(a)
    b.waiting.append(("touch", "b0"))
    thread.handled = 4
    t.release()  # b never served: b0 first, then a's last two
    assert thread.got[4:] == ["b0", "a4", "a5"] and t.waiting() == 0
    assert t.queues == [b]


def test_a_page_that_goes_with_nothing_waiting_goes_at_once():
    t = Turns(Counting())  # type: ignore[arg-type]
    a, b = t.open(), t.open()
    t.close(a)
    assert t.queues == [b]


def test_at_the_end_every_waiting_command_goes_to_the_thread_in_turns():
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    a, b = t.open(), t.open()
    for k in range(3):
        a.waiting.append(("touch", f"a{k}"))
        b.waiting.append(("touch", f"b{k}"))
    t.flush()  # (past `ahead`: nothing applies any more)
    assert thread.got == ["a0", "b0", "a1", "b1", "a2", "b2"] and t.waiting() == 0


def test_a_pages_queue_is_full_at_page_waiting(monkeypatch):
    monkeypatch.setattr(turns, "PAGE_WAITING", 3)
    t = Turns(Counting())  # type: ignore[arg-type]
    q = t.open()
    for k in range(3):
        assert not q.full()
        q.waiting.append(("touch", k))
    assert q.full()
