"""The feed (app/serve/feed.py) ticked by hand: the simulation thread runs on its own
thread, as when it serves (a snapshot's drawing happens on it, between two ticks), but
each tick waits for the test, and the test publishes what the thread made (`Feed.pump`)
when it chooses, so that orders the loop meets only now and then are met every time.

The oracle is the simulation itself: a page (what it holds after the messages it was
queued) must hold the thread's height grid (as half floats) and the live ice drawn anew."""

from __future__ import annotations

import queue
import threading

import numpy as np
from test_serve import CENTRE, PAPER, PageModel

from app.serve import feed as feed_module
from app.serve.feed import Feed
from app.serve.pages import Page
from app.serve.protocol import Encoder, Input
from app.simthread.schedule import Schedule
from app.simthread.thread import SimThread
from sim.look.geometry import FrostGeometry


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


def fed(touches=(CENTRE,)) -> tuple[Feed, ByHand, Page]:
    thread = SimThread(PAPER, 1, touches)
    feed = Feed(PAPER, 1, thread=thread)
    page = Page(Wire(), "page", feed.ask_redraw)
    feed.pages.add(page)
    return feed, ByHand(thread), page


def held(page: Page) -> PageModel:
    """What the page holds once it has applied every message it was queued."""
    model = PageModel()
    for message, _ends_tick in page.queue:
        if isinstance(message, bytes):
            model.apply(message)
    return model


def assert_holds_the_frost(model: PageModel, feed: Feed) -> None:
    thread = feed.thread
    geometry = thread.geometry
    assert model.snapshots == 1 and model.heights is not None
    assert (model.heights == geometry.heights.ravel().astype(np.float16)).all()
    live = FrostGeometry(thread.params, *thread.size).redraw(thread.sim)
    truth = PageModel()
    for part in Encoder(geometry.cols, geometry.rows).snapshot(live.tick, live.features, live.look,
                                                               live.height_scale):
        truth.apply(part)
    assert len(truth.tris) > 100
    assert np.array_equal(model.sorted_tris(), truth.sorted_tris())


def test_melts_of_a_tick_reach_the_pages_before_its_growth():
    """A warm finger on the growing edge of the frost, a tick at a time: each tick melts,
    then grows (its step). Sent in that order, the page ends with the thread's frost; sent
    the other way, a step's heights and ridges near the melt are wiped by the older melt."""
    feed, ticks, page = fed()
    try:
        feed.ask_redraw()  # (what the page's writer does, waiting with nothing to write)
        ticks.tick(feed)
        assert not page.waiting  # its snapshot: the seed
        ticks.tick(feed, 30)
        fingers: dict = {}
        for _ in range(20):
            x, y = (float(v) for v in feed.thread.sim.crystals[-1])  # the newest crystal
            feed.controls.handle(Input("melt", x, y, "down", 0), fingers)
            feed.controls.handle(Input("melt", phase="up"), fingers)
            ticks.tick(feed)
        kinds = [e["kind"] for e in feed.thread.session().events]
        assert kinds.count("melt") == 20
        assert_holds_the_frost(held(page), feed)
    finally:
        ticks.stop()


def test_a_snapshot_drawn_before_the_frost_moved_on_is_drawn_again(monkeypatch):
    """The snapshot of a page that connects is drawn on the thread right after a tick; the
    loop may have published that tick's frost before the drawing is done, and the next
    tick's too before it serves the drawing: the drawing is then of a frost older than the
    last one published, whose ticks the page would miss. It is drawn again."""
    feed, ticks, page = fed()
    entered, go = threading.Event(), threading.Event()

    class Slow(FrostGeometry):
        """The drawing, held until the loop has published its tick."""

        def redraw(self, sim):
            entered.set()
            assert go.wait(30)
            return super().redraw(sim)

    try:
        ticks.tick(feed, 40)  # a frost growing every tick
        monkeypatch.setattr(feed_module, "FrostGeometry", Slow)
        feed.ask_redraw()
        ticks.order()
        assert entered.wait(30)
        feed.pump()  # publishes that tick while its snapshot is being drawn
        go.set()
        ticks.done()
        monkeypatch.setattr(feed_module, "FrostGeometry", FrostGeometry)
        ticks.tick(feed)  # a tick more published, then the drawing found: one tick old
        ticks.tick(feed, 5)
        assert not page.waiting and feed.redraws == 1
        assert_holds_the_frost(held(page), feed)
    finally:
        go.set()
        ticks.stop()
