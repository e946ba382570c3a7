"""The page model: what a page holds after the messages `frost serve` sent it (the height
grid, the feature triangles, the texts), the oracle the server's state is checked against;
and reading a socket into it, and an in-process server to read from."""

from __future__ import annotations

import asyncio
import json

import numpy as np
from aiohttp import WSMsgType
from aiohttp.test_utils import TestClient, TestServer

from app.serve.feed import Feed
from app.serve.protocol import (
    CLOCK,
    LAST_PART,
    RESET,
    SNAPSHOT,
    apply_geometry,
    decode_clock,
    decode_geometry,
    message_type,
)
from app.serve.server import make_app
from sim import Params

PAPER = Params.preset("c-2")
CENTRE = (380.0, 640.0)


class PageModel:
    """What a page holds after the messages it got."""

    def __init__(self):
        self.heights: np.ndarray | None = None
        self.tris = np.empty((0, 3, 6), np.float32)
        self.texts: list[dict] = []
        self.tick, self.snapshots, self.messages, self.resets = -1, 0, 0, 0

    def apply(self, data: bytes) -> dict:
        if message_type(data) == CLOCK:  # the lock screen's minute: no geometry
            return decode_clock(data)
        m = decode_geometry(data)
        cols, rows = m["grid"]
        if self.heights is None:
            self.heights = np.zeros(cols * rows, np.float32)
        if m["flags"] & RESET:
            self.tris = self.tris[:0]
            self.resets += not m["flags"] & SNAPSHOT
        if m["clear_box"] is not None:
            x0, y0, x1, y1 = m["clear_box"]
            lo, hi = self.tris[:, :, :2].min(axis=1), self.tris[:, :, :2].max(axis=1)
            meets = (hi[:, 0] >= x0) & (lo[:, 0] <= x1) & (hi[:, 1] >= y0) & (lo[:, 1] <= y1)
            self.tris = self.tris[~meets]
        apply_geometry(self.heights, m)
        self.tris = np.concatenate((self.tris, m["vertices"].reshape(-1, 3, 6)))
        self.tick, self.messages = m["tick"], self.messages + 1
        if m["flags"] & SNAPSHOT and m["flags"] & LAST_PART:
            self.snapshots += 1
        return m

    def sorted_tris(self) -> np.ndarray:
        """The distinct triangles, sorted (a survivor of a melt whose box its bounds meet
        but not its triangles is sent again: drawn twice, it draws the same)."""
        return np.unique(self.tris.reshape(-1, 18), axis=0)

    def state(self, key):
        for t in reversed(self.texts):
            if t["type"] in ("state", "hello") and key in t:
                return t[key]
        return None

    def answered(self, t, since: int = 0) -> bool:
        """Whether the pong to ping `t` is among the texts from `since` on (whatever came
        after it)."""
        return any(m["type"] == "pong" and m.get("t") == t for m in self.texts[since:])

    def take(self, msg) -> None:
        """A message the socket received; AssertionError if the socket ended."""
        if msg.type == WSMsgType.BINARY:
            self.apply(msg.data)
        elif msg.type == WSMsgType.TEXT:
            self.texts.append(json.loads(msg.data))
        else:
            raise AssertionError(f"socket ended: {msg.type} {msg.data} {msg.extra}")


async def read_until(ws, page: PageModel, done, timeout: float = 60.0):
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while not done():
        page.take(await asyncio.wait_for(ws.receive(), max(0.01, end - loop.time())))


async def until(done, what: str = "", timeout: float = 30.0) -> None:
    """Wait for `done()` (polled), however loaded the machine; AssertionError naming
    `what` if it is still not so after `timeout` s (a bound on a failure, not a claim)."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while not done():
        if loop.time() > end:
            raise AssertionError(f"not within {timeout:g} s: {what}")
        await asyncio.sleep(0.02)


async def read_quiet(ws, page: PageModel, quiet: float = 0.4):
    """Read until nothing comes for `quiet` s (a paused simulation sends nothing)."""
    while True:
        try:
            msg = await asyncio.wait_for(ws.receive(), quiet)
        except asyncio.TimeoutError:
            return
        page.take(msg)


def near(page: PageModel, spot, reach: float = 40.0) -> bool:
    xy = page.tris[:, :, :2].reshape(-1, 2)
    return bool(len(xy)) and bool((np.hypot(*(xy - spot).T) < reach).any())


def serve(test, params=PAPER, **app_kw):
    """Run `test(client, feed)` against a fresh server."""
    async def main():
        feed = Feed(params, seed=1)
        async with TestClient(TestServer(make_app(feed, **app_kw))) as client:
            await test(client, feed)
        return feed
    return asyncio.run(main())


async def pause(ws, page):
    await ws.send_json({"type": "pause"})
    await read_until(ws, page, lambda: page.state("paused") is True)
    await read_quiet(ws, page)
