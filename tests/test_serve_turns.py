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


def test_pages_take_turns_and_the_thread_holds_at_most_ahead(monkeypatch):
    monkeypatch.setattr(turns, "AHEAD", 4)
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    a, b, c = t.open(), t.open(), t.open()
    for k in range(6):
        a.waiting.append(("touch", f"a{k}"))
    b.waiting.append(("touch", "b0"))
    t.release()  # a first: a0 b0 a1 a2 (c has none)
    assert thread.got == ["a0", "b0", "a1", "a2"] and t.waiting() == 3
    t.release()  # nothing applied: nothing more (b first this time)
    assert thread.sent == 4
    thread.handled = 2  # a0 and b0 applied: room for two
    c.waiting.append(("touch", "c0"))
    t.release()  # c first now: c0, then a3
    assert thread.got[4:] == ["c0", "a3"]
    thread.handled = 6
    t.put(c, "touch", "c1")  # a first again: a4, (b none), c1, then a5
    assert thread.got[6:] == ["a4", "c1", "a5"] and t.waiting() == 0


def test_a_page_that_goes_takes_its_waiting_commands_with_it(monkeypatch):
    monkeypatch.setattr(turns, "AHEAD", 1)
    thread = Counting()
    t = Turns(thread)  # type: ignore[arg-type]
    a, b = t.open(), t.open()
    for k in range(3):
        a.waiting.append(("touch", f"a{k}"))
    b.waiting.append(("touch", "b0"))
    t.release()
    assert thread.got == ["a0"]
    assert t.close(a) == 2
    thread.handled = 1
    t.release()
    assert thread.got == ["a0", "b0"] and t.waiting() == 0


def test_a_pages_queue_is_full_at_page_waiting(monkeypatch):
    monkeypatch.setattr(turns, "PAGE_WAITING", 3)
    t = Turns(Counting())  # type: ignore[arg-type]
    q = t.open()
    for k in range(3):
        assert not q.full()
        q.waiting.append(("touch", k))
    assert q.full()
