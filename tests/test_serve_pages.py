"""One page's outgoing queue and its input limits (app/serve/pages.py) by hand: a socket
that takes whatever it is sent, a clock the test moves. The oracles are the figures of
docs/phone-design.md (a page 50 ticks or 6 MB behind is resynced) and token counts worked out by
hand."""

from __future__ import annotations

import asyncio

from app.serve.pages import ConnectedPage as Page
from app.serve.pages import TokenBucket

MB = 1 << 20


class Wire:
    """A page's socket that takes every message at once."""

    def __init__(self):
        self.sent: list[str | bytes] = []
        self.closed = False  # (aiohttp's: True from the moment its close frame is sent)

    async def send_bytes(self, data):
        self.sent.append(data)

    send_str = send_bytes


def live_page(asks: list) -> tuple[Page, Wire]:
    wire = Wire()
    page = Page(wire, "p", lambda: asks.append("snapshot"))
    page.start([], '{"type":"state"}')  # a snapshot of nothing: live from here on
    return page, wire


def test_a_page_six_mb_behind_is_resynced_before_fifty_ticks():
    """A page whose socket takes nothing while big ticks come (a frosted pane's p99 is 29 kB,
    a snapshot's part 768 kB): 6 ticks of 1 MB are within the bound, the 7th finds 6 MB
    queued and drops the page to a resync, 43 ticks before the bound on ticks."""
    page, _wire = live_page([])
    megabyte = bytes(MB)
    for _ in range(6):
        page.tick([megabyte])
    assert not page.waiting and page.resyncs == 0
    page.tick([megabyte])
    assert page.waiting and page.resyncs == 1


class HeldWire(Wire):
    """A socket that holds one message (`hold`) until the test releases it."""

    def __init__(self, hold: bytes):
        super().__init__()
        self.hold, self.holding, self.release = hold, asyncio.Event(), asyncio.Event()

    async def send_bytes(self, data):
        if data == self.hold:
            self.holding.set()
            await self.release.wait()
        self.sent.append(data)

    send_str = send_bytes


def test_a_tick_counts_as_behind_until_its_last_message_is_sent():
    """The bound on ticks behind counts a tick of several messages as one until the last
    of them is out: with the first of two ticks' three messages sent and its second in the
    socket, the page is still two ticks behind; with all sent, none."""

    async def run():
        wire = HeldWire(b"0b")
        page = Page(wire, "p", lambda: None)
        page.start([], '{"type":"state"}')
        page.tick([b"0a", b"0b", b"0c"])
        page.tick([b"1a", b"1b"])
        writer = asyncio.create_task(page.write())
        await asyncio.wait_for(wire.holding.wait(), 30)
        during = page.behind_ticks
        wire.release.set()

        async def all_sent():
            while len(wire.sent) < 6:
                await asyncio.sleep(0)

        await asyncio.wait_for(all_sent(), 30)
        after = page.behind_ticks
        page.close()
        await writer
        return during, after, wire.sent

    during, after, sent = asyncio.run(run())
    assert sent == ['{"type":"state"}', b"0a", b"0b", b"0c", b"1a", b"1b"]
    assert (during, after) == (2, 0)


def test_a_resync_drops_what_was_queued_and_says_so_first():
    """A page 50 ticks behind is resynced: what it is sent next is the resync message
    alone (none of the stale ticks, which a snapshot replaces), then it asks for that
    snapshot."""
    asks: list[str] = []
    page, wire = live_page(asks)
    for i in range(51):  # the 51st finds 50 ticks queued
        page.tick([b"tick %d" % i])
    assert page.waiting

    async def write_out():
        writer = asyncio.create_task(page.write())
        for _ in range(1000):
            if asks:
                break
            await asyncio.sleep(0)
        page.close()
        await writer

    asyncio.run(write_out())
    assert asks and len(wire.sent) == 1, wire.sent[:3]
    assert wire.sent[0] == '{"type":"resync","reason":"fell behind"}'


def test_a_token_bucket_holds_no_more_than_its_burst():
    now = [0.0]
    bucket = TokenBucket(rate=8.0, burst=5.0, clock=lambda: now[0])
    now[0] = 100.0  # 800 tokens' worth of quiet
    assert [bucket.take() for _ in range(6)] == [True] * 5 + [False]
    now[0] += 0.125  # one token's worth (times exact in binary)
    assert [bucket.take() for _ in range(2)] == [True, False]


def test_a_token_bucket_grants_whole_tokens_only():
    now = [0.0]
    bucket = TokenBucket(rate=1.0, burst=3.0, clock=lambda: now[0])
    assert bucket.grant(3) == 3 and not bucket.take()
    now[0] = 0.625  # 0.625 of a token: none yet (rounded up or to nearest: one)
    assert not bucket.take()
    now[0] = 1.0  # 1.0
    assert bucket.take() and not bucket.take()
    now[0] = 3.5  # 2.5 tokens: two whole ones
    assert bucket.grant(3) == 2
    now[0] = 4.0  # the half left, and half a token more
    assert bucket.grant(3) == 1


def test_nothing_is_sent_after_the_socket_began_to_close():
    """aiohttp sends a close frame of its own on a frame too big or not UTF-8, while the
    page's writer may still have its snapshot queued: a frame after the close frame makes
    the browser see an abnormal closure (1006) instead of the code sent."""
    async def run():
        page, wire = live_page([])
        page.tick([b"one"])
        writer = asyncio.create_task(page.write())
        await asyncio.sleep(0.01)
        wire.closed = True
        page.tick([b"two"])
        await asyncio.sleep(0.01)
        assert page.closed and writer.done()
        return wire.sent

    assert asyncio.run(run()) == ['{"type":"state"}', b"one"]


def test_a_page_that_reads_every_tick_is_never_resynced_however_much_it_was_sent():
    """A page whose socket takes each tick as it comes holds nothing queued: 10 ticks of
    1 MB, each written out before the next, are 10 MB sent and never 6 MB behind."""
    async def run():
        page, wire = live_page([])
        writer = asyncio.create_task(page.write())
        megabyte = bytes(MB)
        for _ in range(10):
            page.tick([megabyte])
            for _ in range(100):
                if not page.queue:
                    break
                await asyncio.sleep(0)
        page.close()
        await writer
        return page, wire

    page, wire = asyncio.run(run())
    assert page.resyncs == 0 and not page.waiting
    assert len(wire.sent) == 11 and page.behind_bytes == 0 and page.behind_ticks == 0
