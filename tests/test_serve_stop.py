"""`frost serve` stopped (docs/phone.md, Stopping; docs/phone-design.md, With the window,
and stopping): whatever a page was told the server has
(a photo answered 200, a touch answered by the pong after it) is in the session written,
input left unapplied is counted in the warning, and a request still open (a photo half
sent) cannot hold the exit. Oracles: the spots and photo names each page was answered for,
against the session file; the counts of commands sent, against the warning."""

from __future__ import annotations

import asyncio
import json
import os
import random
import signal
import subprocess
import time
from pathlib import Path

import pytest
from aiohttp import WSMsgType
from aiohttp.test_utils import TestClient, TestServer
from support.photos import answer, encoded, post_head, quadrants
from support.serve import session_serve

from app.serve import guard
from app.serve.feed import Feed
from app.serve.server import make_app
from app.simthread import thread as thread_module
from app.simthread.thread import SimThread
from sim import Params
from sim.io.session import SessionLog

PAPER = Params.preset("c-2")
WINDOWS_LIKE = Path(__file__).resolve().parent / "windows_like.py"
# s a request open at the stop may add to it, beside the same stop with none open at the
# same moment: a third of what tells a stop that works (guard.SHUTDOWN_S, twice) from one
# held by the request (aiohttp's own 60 s). A difference of two stops under the same load,
# not a claim on the machine's speed.
HELD_BOUND_S = 20.0
PHOTO = encoded(quadrants(380, 640), "JPEG", quality=95)


def spot(n: int) -> tuple[float, float]:
    """The n-th tap's spot: each its own, on the pane (760 x 1280)."""
    return 40.0 + (n % 60) * 11.0, 100.0 + (n // 60) * 13.0


def session_of(folder: Path) -> SessionLog:
    [path] = folder.glob("session-*.json")
    return SessionLog.load(path)


def touches(session: SessionLog) -> list[tuple[float, float]]:
    return [(e["x"], e["y"]) for e in session.events if e["kind"] == "touch"]


# ---- the simulation thread's end ---------------------------------------------------------

def test_input_waiting_at_the_end_applies_after_the_last_step_and_replays():
    thread = SimThread(PAPER, 1)  # (never started: every command waits)
    thread.send("touch", (spot(0), None))
    thread.tick()  # one step, with the first touch
    sent = [spot(n) for n in range(1, 9)]
    for xy in sent:
        thread.send("touch", (xy, None))
    thread.stop(apply_s=30.0)
    session = thread.session()
    assert touches(session) == [spot(0), *sent] and session.steps == 1
    assert thread.handled == thread.sent == 9
    assert thread.notices.empty()  # nothing left to warn of
    from sim.io.timeline import replay
    assert replay(session).events == session.events  # (due after the last step: applied)


def test_input_left_at_the_end_for_want_of_time_is_all_counted_in_the_warning(monkeypatch):
    """A clock that moves one second a look: three touches fit in 3.5 s, the other nine
    are counted in the warning (and not in the session)."""
    looks = iter(range(1000))
    monkeypatch.setattr(thread_module.time, "perf_counter", lambda: float(next(looks)))
    thread = SimThread(PAPER, 1)
    for n in range(12):
        thread.send("touch", (spot(n), None))
    thread.stop(apply_s=3.5)
    assert touches(thread.session()) == [spot(n) for n in range(3)]
    level, text = thread.notices.get_nowait()
    assert "never applied" in text and text.endswith(": 9 touches")


# ---- the server's end (its app's cleanup, as a test client ends it) ---------------------

def ended_with(test, tmp_path) -> Feed:
    """Run `test(client, feed)` against a server whose simulation thread never ticks (all
    input waits for the end), then end it (its session written in tmp_path)."""
    async def main():
        feed = Feed(PAPER, seed=1)
        feed.thread.start = lambda: None  # type: ignore[method-assign]
        async with TestClient(TestServer(make_app(feed, None, tmp_path))) as client:
            await test(client, feed)
        return feed
    return asyncio.run(main())


async def post_photo(client):
    return await client.post("/photo", data=PHOTO, headers={
        "Origin": f"http://{client.host}:{client.port}", "Content-Type": "image/jpeg"})


def test_a_photo_answered_is_in_the_session_however_soon_the_server_ends(tmp_path):
    """(After a touch the thread applied: without one, backdrops alone are no session.)"""
    names = []

    async def test(client, feed):
        feed.thread.send("touch", (spot(0), None))
        feed.thread.tick()
        answered = await post_photo(client)
        assert answered.status == 200, await answered.text()
        names.append((await answered.json())["backdrop"])
    ended_with(test, tmp_path)
    session = session_of(tmp_path)
    assert [e["name"] for e in session.events if e["kind"] == "backdrop"] == names


def test_touches_answered_by_a_pong_are_in_the_session(tmp_path):
    """Twenty taps, then a ping: the pong says the server has them; they wait in the page's
    turn and the thread's inbox when the server ends, and are all in its session."""
    sent = [spot(n) for n in range(20)]

    async def test(client, feed):
        ws = await client.ws_connect("/ws")
        for x, y in sent:
            await ws.send_json({"type": "touch", "x": x, "y": y})
        await ws.send_json({"type": "ping", "t": 7})
        async for msg in ws:
            if msg.type == WSMsgType.TEXT and json.loads(msg.data)["type"] == "pong":
                break
        assert feed.controls.turns.waiting() > 0  # (some had not reached the thread)
    ended_with(test, tmp_path)
    assert touches(session_of(tmp_path)) == sent


def test_nothing_is_taken_once_the_server_ends(tmp_path):
    """Input after the end is not answered (no pong: the page is not told it was taken),
    and a photo is answered 503 with the reason."""
    async def test(client, feed):
        ws = await client.ws_connect("/ws")
        feed.close()
        await ws.send_json({"type": "touch", "x": 100, "y": 100})
        await ws.send_json({"type": "ping", "t": 1})
        answered = await post_photo(client)
        assert answered.status == 503 and "ending" in (await answered.json())["error"]
        await ws.send_json({"type": "ping", "t": 2})
        texts = []
        with pytest.raises(asyncio.TimeoutError):  # (no more messages come)
            while True:
                msg = await asyncio.wait_for(ws.receive(), 2.0)
                texts += [json.loads(msg.data)["type"]] if msg.type == WSMsgType.TEXT else []
        assert "pong" not in texts
    feed = ended_with(test, tmp_path)
    assert touches(feed.thread.session()) == [] and not list(tmp_path.glob("session-*"))


# ---- `frost serve` stopped by a signal --------------------------------------------------

FROSTS = {"here": ["-m", "app"], "as-on-windows": [str(WINDOWS_LIKE)]}


def start(folder: Path, frost=FROSTS["here"]) -> tuple[subprocess.Popen, str, int]:
    """`frost serve` on a free port writing its session in `folder`: the process, its URL
    and its port."""
    served = session_serve(folder, frost)
    return served.proc, served.url, served.port


async def tapped(ws, spots, t: int) -> None:
    """`spots` tapped, then a ping: returns at its pong (the server has them all)."""
    for x, y in spots:
        await ws.send_json({"type": "touch", "x": x, "y": y})
    await ws.send_json({"type": "ping", "t": t})
    async for msg in ws:
        data = json.loads(msg.data) if msg.type == WSMsgType.TEXT else {}
        if data.get("type") == "pong" and data.get("t") == t:
            return
    raise ConnectionError("the socket closed before the pong")


async def half_sent(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    """A photo upload whose body stops half way, its handler reading it: a second upload
    from this address is refused for the one in flight (429). The first's connection (its
    writer must be kept: collected, it closes the connection)."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    writer.write(post_head(port, len(PHOTO)) + PHOTO[:len(PHOTO) // 2])
    await writer.drain()
    other, sender = await asyncio.open_connection("127.0.0.1", port)
    sender.write(post_head(port, len(PHOTO)) + PHOTO)
    status, _headers, _body = await answer(other)
    sender.close()
    assert status == 429, status  # (the first is in flight: one photo every 5 s)
    return reader, writer


async def nothing_or_503(connection: tuple[asyncio.StreamReader, asyncio.StreamWriter]) -> None:
    """What a request open at the stop gets: its connection closed, or a 503."""
    got = await asyncio.wait_for(connection[0].read(), 30)
    assert got == b"" or got.startswith(b"HTTP/1.1 503 "), got[:60]


def stopped(proc: subprocess.Popen) -> tuple[float, str]:
    """SIGINT to `proc`; the seconds until it exited (asserted 130, saying so) and what
    it wrote on stderr."""
    at = time.monotonic()
    proc.send_signal(signal.SIGINT)
    assert proc.wait(60) == 130
    took = time.monotonic() - at
    said = proc.stderr.read()  # type: ignore[union-attr]
    assert "\nfrost: interrupted (Ctrl-C)\n" in said, said
    return took, said


@pytest.mark.parametrize("frost", FROSTS.values(), ids=FROSTS.keys())
@pytest.mark.usefixtures("subprocesses")
def test_ctrl_c_with_a_photo_half_sent_ends_at_once_with_the_session_written(tmp_path, frost):
    """The photo's handler waits for the rest of its body when Ctrl-C comes (after a touch
    the pong answered): the upload gets nothing or a 503, the session holds the touch, and
    the process exits no later than HELD_BOUND_S after a second server stopped at the same
    moment with no request open (aiohttp waited 60 s for such a request)."""
    from aiohttp import ClientSession

    (tmp_path / "held").mkdir()
    (tmp_path / "bare").mkdir()
    proc, url, port = start(tmp_path / "held", frost)
    bare, bare_url, _ = start(tmp_path / "bare", frost)
    try:
        async def main():
            async with ClientSession() as http, \
                    http.ws_connect(url + "ws", heartbeat=None) as ws, \
                    http.ws_connect(bare_url + "ws", heartbeat=None) as bare_ws:
                await tapped(ws, [spot(0)], 1)
                await tapped(bare_ws, [spot(0)], 1)
                upload = await half_sent(port)
                took, bare_took = await asyncio.gather(asyncio.to_thread(stopped, proc),
                                                       asyncio.to_thread(stopped, bare))
                await nothing_or_503(upload)
                return took[0], bare_took[0]
        took, bare_took = asyncio.run(main())
    finally:
        for p in (proc, bare):
            p.kill()
            p.wait()
    print(f"benchmark: Ctrl-C to exit {took:.2f} s with a photo half sent, "
          f"{bare_took:.2f} s with none")
    assert took < bare_took + HELD_BOUND_S, (took, bare_took)
    assert touches(session_of(tmp_path / "held")) == [spot(0)]
    assert touches(session_of(tmp_path / "bare")) == [spot(0)]


def test_a_second_ctrl_c_ends_the_wait_for_open_requests_at_once(tmp_path, monkeypatch):
    """With 120 s for the requests still open (a photo half sent; aiohttp's own is 60 s),
    the second Ctrl-C, once the session is written, ends the wait: `frost serve` returns
    130 (the test waits up to 60 s for it: half the wait it cuts short, a bound on a
    failure and no claim on the machine's speed)."""
    from app.serve.appkeys import PORTS
    from app.serve.command import _serve

    monkeypatch.setattr(guard, "SHUTDOWN_S", 120.0)
    feed = Feed(PAPER, seed=1)
    app = make_app(feed, None, tmp_path)

    async def main():
        serving = asyncio.ensure_future(_serve(app, "127.0.0.1", 0, None, None))
        while app[PORTS]["http"] is None:
            await asyncio.sleep(0.02)
        feed.thread.send("touch", (spot(0), None))
        upload = await half_sent(app[PORTS]["http"])
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1500):  # (30 s at most) until the first signal's session is written
            if list(tmp_path.glob("session-*.json")):
                break
            await asyncio.sleep(0.02)
        os.kill(os.getpid(), signal.SIGINT)
        status = await asyncio.wait_for(serving, 60)
        upload[1].close()  # (the process would exit here, and its connections with it)
        return status
    assert asyncio.run(main()) == 130
    assert touches(session_of(tmp_path)) == [spot(0)]


def stop_at_random(folder: Path, rng: random.Random) -> float:
    """One stop of `frost serve` at a moment `rng` picks while a page taps in bursts (each
    answered by a pong) and uploads a photo slowly: right after the photo's answer, while
    its body is on its way, or at any moment of the first 1.5 s. Asserts that every touch
    and photo answered is in the session; the seconds the stop took."""
    from aiohttp import ClientSession

    proc, url, port = start(folder)
    acked: list[tuple[float, float]] = []
    photo: list[str] = []
    when = rng.choice(("after the photo", "during the upload", "any time"))
    try:
        async def taps(ws):
            n = 0
            with_ok = (ConnectionError, asyncio.CancelledError, RuntimeError)
            try:
                while True:
                    burst = [spot(n + k) for k in range(rng.randint(1, 8))]
                    await tapped(ws, burst, n)
                    acked.extend(burst)
                    n += len(burst)
                    # (within a page's rates, messages and touches: over them a page is
                    # told that input was skipped, or its socket is closed)
                    await asyncio.sleep(0.06)
            except with_ok:
                return

        async def upload(sent_half: asyncio.Event):
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(post_head(port, len(PHOTO)))
            chunks = [PHOTO[i:i + len(PHOTO) // 8 + 1] for i in range(0, len(PHOTO),
                                                                     len(PHOTO) // 8 + 1)]
            for k, chunk in enumerate(chunks):
                writer.write(chunk)
                await writer.drain()
                if k == len(chunks) // 2:
                    sent_half.set()
                await asyncio.sleep(0.05)  # (a slow link: the body takes 0.4 s)
            try:
                status, _h, body = await answer(reader)
            except (asyncio.IncompleteReadError, ConnectionError):
                return
            if status == 200:
                photo.append(json.loads(body)["backdrop"])
            else:
                assert status == 503, (status, body)

        async def main():
            async with ClientSession() as http, http.ws_connect(url + "ws",
                                                                 heartbeat=None) as ws:
                tapping = asyncio.ensure_future(taps(ws))
                half = asyncio.Event()
                uploading = asyncio.ensure_future(upload(half))
                if when == "after the photo":
                    await uploading
                elif when == "during the upload":
                    await half.wait()
                else:
                    await asyncio.sleep(rng.uniform(0.0, 1.5))
                ended = await asyncio.to_thread(stopped, proc)
                await asyncio.wait_for(asyncio.gather(tapping, uploading), 30)
                return ended
        took, said = asyncio.run(main())
    finally:
        proc.kill()
        proc.wait()
    session = session_of(folder)
    missing = set(acked) - set(touches(session))
    assert not missing, (when, len(missing), len(acked), said[-600:])
    assert set(photo) <= {e["name"] for e in session.events if e["kind"] == "backdrop"}, \
        (when, said[-600:])
    return took


@pytest.mark.usefixtures("subprocesses")
def test_stops_at_random_moments_keep_all_that_was_answered(tmp_path):
    """Three stops (the validation run below does twenty). What is kept is the subject; a
    request open at the stop holding the exit is the half-sent photo's test above, and a
    stop that never ends fails `stopped`'s wait. The times are printed, not held."""
    rng = random.Random(46)
    took = [stop_at_random(tmp_path / str(k), rng) for k in range(3)]
    print(f"benchmark: Ctrl-C to exit at random moments {[round(t, 2) for t in took]} s")


@pytest.mark.validation
def test_twenty_stops_at_random_moments_keep_all_that_was_answered(tmp_path):
    rng = random.Random(4646)
    took = [stop_at_random(tmp_path / str(k), rng) for k in range(20)]
    print(f"benchmark: Ctrl-C to exit at random moments, max {max(took):.2f} s of "
          f"{[round(t, 2) for t in took]}")
