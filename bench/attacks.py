"""The hostile pages of `python -m bench serve` (its child process): pages that keep within
every limit a page has (app/serve/pages.py: RATE messages a second, in bursts of BURST;
POINT_RATE touches and melts a second) and still ask the shared frost for all the work
those limits let through. Each sender returns when its time is up or the server closed
its socket (which the reader notes).

- one-spot: a tap (down, up) at one point TAPS_PER_S times a second: every touch a seed in
  the same hash cell.
- all-over: one finger dragged over the whole pane, row after row of hash cells, each move
  leaving PER_MOVE touches: the page's whole POINT_RATE, every touch at a fresh spot.
- taps: a person's fast tapping, PERSON_TAPS_PER_S taps a second (down, up), each at a fresh
  spot (from fifteen pages with the person's: sixteen people tapping at once).
- sockets: no page of its own; a client opening sockets as fast as it can, each reading
  its hello and closing (a page needs the whole frost: a snapshot each).
"""

from __future__ import annotations

import asyncio
import itertools
import math
import time
from collections.abc import AsyncIterator, Iterator
from dataclasses import dataclass

from sim.io.gestures import DRAG_SPACING_HC
from sim.screen import HEIGHT, WIDTH

# The window bits of the permessage-deflate every browser's socket asks for: the bench's
# pages ask as browsers do (the server then deflates each page's messages on its own).
BROWSER_DEFLATE = 15
SPOT = (380.0, 640.0)  # the pane's centre
# 172 messages a second: under RATE (200) with room for the loop's jitter, which would
# otherwise have the server close the socket for a burst over its bucket.
TAPS_PER_S = 86.0
MESSAGES_PER_S = 2 * TAPS_PER_S
# A move message leaves a touch every DRAG_SPACING_HC * hc along the finger's path
# (app/serve/controls.py), so a page's touches are bounded by POINT_RATE (500), not by its
# messages: 3 touches a move at 172 moves a second would ask for 516, but a move across a
# turn of the path leaves fewer and the loop's jitter costs moves; 4 ask for 688, so the
# page's bound is always what limits it (the rest of a path is skipped, the finger going
# on from its end).
PER_MOVE = 4
PERSON_TAPS_PER_S = 12.0  # a person tapping as fast as they can, each tap a seed
MARGIN = 40.0  # px from the pane's edges
GOLDEN = 0.6180339887  # each pass over the pane is shifted by this much of a cell
LAG = 0.25  # s: a sender this far behind its schedule starts again from now (no burst)


@dataclass(frozen=True)
class Attacker:
    """Which of the attack's pages this is (`k` of `pages`), and the server's hc."""

    k: int
    pages: int
    hc: float


async def paced(rate: float, end: float) -> AsyncIterator[None]:
    """Yields `rate` times a second until `end` (time.monotonic())."""
    start, k = time.monotonic(), 0
    while (now := time.monotonic()) < end:
        due = start + k / rate
        if due > now:
            await asyncio.sleep(due - now)
        elif now - due > LAG:
            start, k = now, 0
        yield
        k += 1


async def _send(ws, got: dict, *messages: dict) -> bool:
    """Send `messages`; False once the socket is closed."""
    try:
        for m in messages:
            if ws.closed:
                return False
            await ws.send_json(m)
            got["sent"] += 1
    except (ConnectionError, RuntimeError):  # closed while sending
        return False
    return True


async def one_spot(ws, page: Attacker, got: dict, end: float) -> None:
    x, y = SPOT
    async for _ in paced(TAPS_PER_S, end):
        if not await _send(ws, got, {"type": "touch", "x": x, "y": y, "phase": "down"},
                           {"type": "touch", "phase": "up"}):
            return


async def all_over(ws, page: Attacker, got: dict, end: float) -> None:
    spots, phase = sweep(page), "down"
    async for _ in paced(MESSAGES_PER_S, end):
        x, y = next(spots)
        if not await _send(ws, got, {"type": "touch", "x": x, "y": y, "phase": phase}):
            return
        phase = "move"


async def taps(ws, page: Attacker, got: dict, end: float) -> None:
    n = 0
    async for _ in paced(PERSON_TAPS_PER_S, end):
        x, y = tap_spot(page, n)
        if not await _send(ws, got, {"type": "touch", "x": x, "y": y, "phase": "down"},
                           {"type": "touch", "phase": "up"}):
            return
        n += 1


def tap_spot(page: Attacker, n: int) -> tuple[float, float]:
    """Attacker `page`'s n-th tap: a fresh spot (golden-ratio steps over the pane, each page
    from its own start)."""
    u = (page.k / max(page.pages, 1) + n * GOLDEN) % 1.0
    v = (page.k * 0.37 + n * GOLDEN * GOLDEN) % 1.0
    return MARGIN + u * (WIDTH - 2 * MARGIN), MARGIN + v * (HEIGHT - 2 * MARGIN)


def sweep(page: Attacker) -> Iterator[tuple[float, float]]:
    """Without end, where `page`'s finger goes, a move PER_MOVE touch spacings along its
    path (and a hair, so that it leaves them all): a zigzag over the pane, across its width
    while it goes one hash cell (2 hc) down, so its touches land in every row of cells.
    Each pass over the pane is shifted down by a fraction of a cell (GOLDEN's multiples),
    so its touches land on fresh spots; page k of n starts k/n of the way down, so the
    pages sweep different rows."""
    cell, step = 2 * page.hc, PER_MOVE * DRAG_SPACING_HC * page.hc + 0.5
    width, height = WIDTH - 2 * MARGIN, HEIGHT - 2 * MARGIN
    rows = int(height // cell) - 1  # (a pass's shift takes up to one more)
    run = math.hypot(width, cell)  # the path's length across the pane
    for k in itertools.count():
        row, along = divmod(k * step / run + page.k * rows // page.pages, 1.0)
        turn, at = divmod(int(row), rows)
        across = along if int(row) % 2 == 0 else 1.0 - along
        yield MARGIN + across * width, MARGIN + (at + along + turn * GOLDEN % 1.0) * cell


async def sockets(http, url: str, got: dict, end: float) -> None:
    """Open a socket, read its hello, close it; again until `end` (each within the time
    left: a connection that hangs must not hold the bench past its end)."""
    while (left := end - time.monotonic()) > 0:
        try:
            await asyncio.wait_for(_open_once(http, url), left)
            got["sent"] += 1
        except (asyncio.TimeoutError, ConnectionError, OSError):
            await asyncio.sleep(0.01)


async def _open_once(http, url: str) -> None:
    ws = await http.ws_connect(url, max_msg_size=0, compress=BROWSER_DEFLATE)
    try:
        await ws.receive()
    finally:
        await ws.close()


SENDERS = {"one-spot": one_spot, "all-over": all_over, "taps": taps}
OPENERS = {"sockets": sockets}  # attacks by connections: (session, url, got, end)
