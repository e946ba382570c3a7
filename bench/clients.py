"""The pages of `python -m bench serve`, run in a child process (aiohttp clients) so that they do
not share the server's interpreter lock: the house's pages (one scribbling, one tapping
clear glass to time touch-to-first-delta, the others only reading) or the hostile pages of
an attack (bench/attacks.py) with a person's page beside them, tapping clear glass as
the house's does: what the attack costs a person. Every page reads what the server sends
it."""

from __future__ import annotations

import asyncio
import math
import time
from collections.abc import Coroutine
from dataclasses import dataclass

import numpy as np

from app.serve import protocol
from bench import attacks
from sim.screen import HEIGHT, WIDTH

SCRIBBLE_HZ = 50.0  # pointer events a second of the scribbling finger
TAP_PERIOD = 0.6  # s between the latency page's taps
NEAR = 40.0  # px: a delta's vertex this near a tap shows its growth


@dataclass(frozen=True)
class Plan:
    """What the child's pages do: "house" (one scribbling, one tapping, the others reading)
    or an attack of attacks.SENDERS; `hc` is the server's, which spaces a drag's touches."""

    kind: str
    pages: int
    hc: float = 7.0


def scribble_point(t: float) -> tuple[float, float]:
    """Where the scribbling finger is at time t (s): a slow Lissajous over the screen."""
    return (WIDTH / 2 + 0.4 * WIDTH * math.sin(0.9 * t),
            HEIGHT / 2 + 0.4 * HEIGHT * math.sin(0.55 * t + 0.3))


def tap_point(k: int) -> tuple[float, float]:
    """The latency page's k-th tap: a grid of spots away from the scribble's path."""
    return (60.0 + (k * 97) % (WIDTH - 120), 60.0 + (k * 211) % (HEIGHT - 120))


def pages_main(url: str, plan: Plan, seconds: float, out) -> None:
    out.put(asyncio.run(_pages(url, plan, seconds)))


async def _pages(url: str, plan: Plan, seconds: float) -> dict:
    from aiohttp import ClientSession
    got: dict = {"bytes": 0, "latency": [], "taps": 0, "sent": 0, "closed": [],
                 "sending_s": seconds + 0.5, "tapped": [], "tick_at": {}}
    async with ClientSession() as http:
        # Each asks for permessage-deflate, as every browser's page does: the server then
        # compresses each page's messages on its own (aiohttp's default, compress 15).
        sockets = [await http.ws_connect(url, max_msg_size=0, compress=attacks.BROWSER_DEFLATE)
                   for _ in range(plan_pages(plan))]
        end = time.monotonic() + seconds + 0.5  # the server times `seconds` from here
        if plan.kind == "house":
            jobs = _house(sockets, got, end)
        else:
            jobs = [*_attack(plan, sockets[1:], got, end), _taps(sockets[0], got, end, True)]
            if plan.kind in attacks.OPENERS:
                jobs.append(attacks.OPENERS[plan.kind](http, url, got, end))
        await asyncio.gather(*(asyncio.create_task(job) for job in jobs))
        for ws in sockets:
            await ws.close()
    return got


def plan_pages(plan: Plan) -> int:
    """The pages `plan` keeps connected: its own, and with an attack a person's."""
    return plan.pages + (plan.kind != "house")


def _house(sockets: list, got: dict, end: float) -> list[Coroutine]:
    jobs = [_read(ws, got, end, None) for ws in sockets[2:]]
    jobs.append(_scribble(sockets[0], got, end))
    if len(sockets) > 1:
        jobs.append(_taps(sockets[1], got, end))
    return jobs


def _attack(plan: Plan, sockets: list, got: dict, end: float) -> list[Coroutine]:
    send = attacks.SENDERS.get(plan.kind)
    if send is None:  # (an attack by connections, not by a page's messages)
        return [_read(ws, got, end, None) for ws in sockets]
    return [*(_read(ws, got, end, None) for ws in sockets),
            *(send(ws, attacks.Attacker(k, plan.pages, plan.hc), got, end)
              for k, ws in enumerate(sockets))]


async def _read(ws, got: dict, end: float, on_binary) -> None:
    while time.monotonic() < end:
        try:
            msg = await asyncio.wait_for(ws.receive(), max(0.01, end - time.monotonic()))
        except asyncio.TimeoutError:
            return
        if msg.type.name != "BINARY" and msg.type.name != "TEXT":
            if ws.close_code is not None:  # the server closed it (a limit broken?)
                got["closed"].append(f"{ws.close_code} {msg.extra or ''}".strip())
            return
        got["bytes"] += len(msg.data)
        if on_binary is not None and msg.type.name == "BINARY":
            on_binary(msg.data)


async def _scribble(ws, got: dict, end: float) -> None:
    reader = asyncio.create_task(_read(ws, got, end, None))
    t0, phase = time.monotonic(), "down"
    while time.monotonic() < end:
        x, y = scribble_point(time.monotonic() - t0)
        await ws.send_json({"type": "touch", "x": x, "y": y, "phase": phase})
        phase = "move"
        await asyncio.sleep(1.0 / SCRIBBLE_HZ)
    await reader


async def _taps(ws, got: dict, end: float, ticks: bool = False) -> None:
    """Tap clear glass; the time until the first message with a vertex near the tap. With
    `ticks`, also each tap's spot and time, and when each tick's first message came
    (`got`'s "tapped" and "tick_at"), for the server's session to tell when each showed."""
    pending: dict = {}

    def seen(data: bytes) -> None:
        if protocol.message_type(data) != protocol.GEOMETRY:  # (the lock screen's clock)
            return
        if ticks:
            got["tick_at"].setdefault(protocol.HEADER.unpack_from(data)[4], time.monotonic())
        if not pending:
            return
        xy = protocol.decode_geometry(data)["vertices"][:, :2]
        (x, y), t = pending["spot"], pending["t"]
        if len(xy) and (np.hypot(xy[:, 0] - x, xy[:, 1] - y) < NEAR).any():
            got["latency"].append(time.monotonic() - t)
            pending.clear()

    reader = asyncio.create_task(_read(ws, got, end, seen))
    k = 0
    while time.monotonic() < end - 1.0:
        spot = tap_point(k)
        pending.update(spot=spot, t=time.monotonic())
        got["taps"] += 1
        got["tapped"].append((*spot, pending["t"]))
        await ws.send_json({"type": "touch", "x": spot[0], "y": spot[1], "id": 1})
        await ws.send_json({"type": "touch", "phase": "up", "id": 1})
        k += 1
        await asyncio.sleep(TAP_PERIOD)
    await reader
