"""`frost serve` through aiohttp's test client: the shared frost, snapshots, the security
rules, bad input, a stalled page, and the session it writes. Each page here keeps what a
page holds (the height grid and the feature triangles) from the messages it gets, as the
oracle the server's state is checked against."""

import asyncio
import json
import logging
import re
import socket
import threading
from pathlib import Path

import numpy as np
import pytest
from aiohttp import WSMsgType
from support.page_model import CENTRE, PAPER, PageModel, near, pause, read_quiet, read_until, serve, until
from support.serve import session_serve

from app import session_keeper
from app.serve import MAX_PAGES
from app.serve import pages as pages_module
from app.serve import session_files as session_module
from app.serve.feed import Feed
from app.serve.routes import inside
from app.serve.server import make_app
from app.serve.session_files import SessionFiles
from app.serve.sockets import same_origin
from sim import Params
from sim.io.session import SessionLog
from sim.io.timeline import replay

WINDOWS_LIKE = Path(__file__).resolve().parent / "windows_like.py"


async def closing(ws, timeout: float = 10.0):
    """The close message the server sends `ws` within `timeout` s (what it sends before
    is read and dropped); AssertionError if the socket stays open."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while loop.time() < end:
        try:
            msg = await asyncio.wait_for(ws.receive(), end - loop.time())
        except asyncio.TimeoutError:
            break
        if msg.type in (WSMsgType.CLOSE, WSMsgType.CLOSING, WSMsgType.CLOSED):
            return msg
    raise AssertionError("the server left the socket open")


async def connect(client, token=None):
    ws = await client.ws_connect("/ws" + (f"?token={token}" if token else ""))
    page = PageModel()
    await read_until(ws, page, lambda: page.snapshots >= 1)
    assert page.texts[0]["type"] == "hello" and page.texts[0]["protocol"] == 1
    return ws, page


def test_a_touch_grows_frost_on_the_page():
    async def test(client, feed):
        ws, page = await connect(client)
        assert not near(page, CENTRE)
        await ws.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
        await read_until(ws, page, lambda: near(page, CENTRE))
        assert page.heights.reshape(feed.encoder.grid[::-1]).any()
    serve(test)


def test_two_pages_see_the_same_frost_and_a_late_one_gets_it_whole():
    async def test(client, feed):
        (a, pa), (b, pb) = await connect(client), await connect(client)
        await b.send_json({"type": "touch", "x": 300.0, "y": 500.0})
        await a.send_json({"type": "touch", "x": 450.0, "y": 800.0, "phase": "down", "id": 2})
        await a.send_json({"type": "touch", "x": 470.0, "y": 840.0, "phase": "move", "id": 2})
        await a.send_json({"type": "touch", "x": 490.0, "y": 880.0, "phase": "move", "id": 2})
        await read_until(a, pa, lambda: near(pa, (300, 500)) and near(pa, (450, 800))
                         and pa.tick > 40)
        await pause(a, pa)
        await read_quiet(b, pb)
        assert pa.tick == pb.tick and pa.heights.any()
        assert (pa.heights == pb.heights).all()
        assert np.array_equal(pa.sorted_tris(), pb.sorted_tris())
        # the late page: one snapshot (and the ticks since it), equal to the sum of the early
        # page's deltas
        c, pc = await connect(client)
        await read_quiet(c, pc)
        assert pc.snapshots == 1 and pc.tick == pa.tick
        assert (pc.heights == pa.heights).all()
        assert np.array_equal(pc.sorted_tris(), pa.sorted_tris())
        # which is the simulation's frost (half floats); a tap, a finger down, and seeds every
        # 4 hc = 28 px along its drag: one in its first 44.7 px, then from that seed (462.5,
        # 825.0) to (490, 880), 61.5 px, two more
        assert (pc.heights == feed.thread.geometry.heights.ravel().astype(np.float16)).all()
        assert len(feed.thread.touches) == 5
    serve(test)


def test_the_page_asked_for_has_its_snapshot_drawn_while_it_loads():
    """GET / starts the snapshot that the page's socket will wait for (the page loads its
    modules meanwhile); the socket then gets that one, not another drawn for it. A page's
    other files start nothing."""
    async def test(client, feed):
        async def drawn(n):
            for _ in range(400):
                if feed.redraws >= n:
                    return
                await asyncio.sleep(0.01)
            raise AssertionError(f"{feed.redraws} snapshots drawn, not {n}")

        assert (await client.get("/web/main.js")).status == 200
        await asyncio.sleep(0.3)
        assert feed.redraws == 0
        assert (await client.get("/")).status == 200
        await drawn(1)
        ws, page = await connect(client)
        assert page.snapshots == 1 and feed.redraws == 1
        await ws.close()
    serve(test)


def test_after_a_melt_the_late_page_still_matches():
    async def test(client, feed):
        a, pa = await connect(client)
        await a.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
        await read_until(a, pa, lambda: pa.tick > 60)
        await a.send_json({"type": "melt", "x": CENTRE[0] + 10, "y": CENTRE[1]})
        await read_until(a, pa, lambda: pa.tick > 66)
        await pause(a, pa)
        b, pb = await connect(client)
        assert (pb.heights == pa.heights).all()
        assert np.array_equal(pb.sorted_tris(), pa.sorted_tris())
    serve(test)


def test_a_token_is_needed_when_one_is_in_force():
    async def test(client, feed):
        for url in ("/", "/shaders/ice.frag", "/ws", "/backdrops/dusk.png"):
            resp = await client.get(url)
            assert resp.status == 403, url
            resp = await client.get(url + "?token=wrong")
            assert resp.status == 403, url
        for wrong in ("s3cretX", "s3cre", "s3cret%20", "%20s3cret", "S3CRET", "x&token=s3cret"):
            assert (await client.get(f"/meta?token={wrong}")).status == 403, wrong
        resp = await client.get("/shaders/ice.frag?token=s3cret")
        assert resp.status == 200 and "void main" in await resp.text()
        ws, _page = await connect(client, token="s3cret")
        await ws.close()
    serve(test, token="s3cret")


def test_static_files_stay_in_their_folders(tmp_path):
    web = tmp_path / "web"
    web.mkdir()
    (web / "index.html").write_text("<p>frost</p>", encoding="utf-8")
    (web / "app.js").write_text("export {};", encoding="utf-8")
    (tmp_path / "secret.txt").write_text("no", encoding="utf-8")
    (web / "link.txt").symlink_to(tmp_path / "secret.txt")

    async def test(client, feed):
        assert await (await client.get("/")).text() == "<p>frost</p>"
        resp = await client.get("/web/app.js")
        assert resp.status == 200 and resp.content_type == "text/javascript"
        for url in ("/web/..%2fsecret.txt", "/web/%2e%2e/secret.txt", "/web/../secret.txt",
                    "/web/%2Fetc%2Fpasswd", "/web//etc/passwd", "/web/link.txt",
                    "/shaders/..%2f..%2fpyproject.toml", "/shaders/%2e%2e%2fsetup.py",
                    "/backdrops/..%2fbackground.png",
                    "/web/" + "a" * 4000, "/shaders/" + "a/" * 2000 + "x"):  # names too long
            resp = await client.get(url)
            assert resp.status == 404, url[:40]
            assert await resp.text() != "no"
        png = await client.get("/backdrops/dusk.png")
        assert png.status == 200 and (await png.read())[:4] == b"\x89PNG"
    serve(test, web_dir=web)
    assert inside(web, "../secret.txt") is None and inside(web, str(tmp_path / "secret.txt")) is None
    assert inside(web, "app.js") == (web / "app.js").resolve()


def test_origin_must_name_the_host():
    assert same_origin("http://192.168.1.5:8025", "192.168.1.5:8025")
    assert not same_origin("http://evil.example", "192.168.1.5:8025")
    assert not same_origin("null", "127.0.0.1:8025")
    # another port of the same machine is another site (another program's page)
    assert not same_origin("http://192.168.1.5:9000", "192.168.1.5:8025")
    assert not same_origin("http://192.168.1.5", "192.168.1.5:8025")

    async def test(client, feed):
        host = f"{client.server.host}:{client.server.port}"
        for origin in ("http://evil.example", f"http://{client.server.host}:1"):
            resp = await client.get("/ws", headers={"Origin": origin,
                                                    "Connection": "Upgrade", "Upgrade": "websocket",
                                                    "Sec-WebSocket-Version": "13",
                                                    "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ=="})
            assert resp.status == 403, origin
        ws = await client.ws_connect("/ws", origin=f"http://{host}")
        await ws.close()
    serve(test)


def test_at_most_sixteen_pages():
    async def test(client, feed):
        sockets = [await client.ws_connect("/ws") for _ in range(MAX_PAGES)]
        # Closed at once with the reason, which a browser's page can show (of a 503 it
        # learns only that the connection failed); it never becomes a page.
        extra = await client.ws_connect("/ws")
        msg = await closing(extra)
        assert extra.close_code == 1013 and msg.extra == f"{MAX_PAGES} pages are connected already"
        assert len(feed.pages) == MAX_PAGES
        for ws in sockets:
            await ws.close()
    serve(test)


class Frame(bytes):
    """A text frame's payload sent as it is, even if it is no UTF-8 (the client would not)."""


@pytest.mark.parametrize("send, code, says", [
    ("not json", 1008, "not JSON"),
    ('{"type":"touch","x":"a","y":1}', 1008, "'x'"),
    ('{"type":"touch","x":1' + "0" * 400 + ',"y":1}', 1008, "'x' must be a finite number"),
    ('{"type":"warp"}', 1008, "unknown message type"),
    ("x" * 2000, 1009, "exceeds limit 1024"),
    (b"\x01\x02", 1008, "binary"),
    # Whatever its shape: "[" * 1000 (under 1 KiB) raised RecursionError in json, which
    # aiohttp logged as a traceback of 33 lines, and it sent no close frame.
    ("[" * 1000, 1008, "not JSON"),
    ('{"type":"touch","x":' + "[" * 990 + "1", 1008, "not JSON"),
    ('{"type":"ping","t":' + "9" * 1000 + "}", 1008, "'t' must be a finite number"),
    ('{"type":"touch","x":NaN,"y":1}', 1008, "not JSON"),
    ('{"type":"touch","x":-Infinity,"y":1}', 1008, "not JSON"),
    ('{"type":"touch","x":1,"y":2,"id":1e999}', 1008, "'id'"),
    ('{"type":"touch","x":1,"y":2,"phase":["down"]}', 1008, "'phase'"),
    ('{"type":["touch"]}', 1008, "string 'type'"),
    # Not UTF-8: aiohttp closes it itself, with the standard's code for it (1007)
    (Frame(b"\xff\xfe"), 1007, "Invalid UTF-8"),
])
def test_bad_input_closes_that_socket_in_one_line_of_log_and_changes_nothing(
        caplog, send, code, says):
    """A malformed message closes that socket with a close frame and its reason, is one
    line in the log (no traceback), changes nothing, and the other pages tick on."""
    async def test(client, feed):
        good, page = await connect(client)
        bad = await client.ws_connect("/ws")
        if isinstance(send, Frame):  # masked, as a client's frames are, by hand
            bad._writer.transport.write(bytes([0x81, 0x80 | len(send)]) + b"mask" + bytes(
                b ^ m for b, m in zip(send, b"mask" * 4, strict=False)))
        elif isinstance(send, bytes):
            await bad.send_bytes(send)
        else:
            await bad.send_str(send)
        msg = await closing(bad)
        # (The close frame's code. After a frame it cannot read, aiohttp closes the TCP
        # connection right behind its close frame, not waiting for the page's reply: the
        # client's own close_code is 1006 when its reply meets the closed socket first.)
        assert msg.type == WSMsgType.CLOSE and msg.data == code, (msg, bad.close_code)
        assert says in (msg.extra or "") or code in (1007, 1009)  # (aiohttp's own, no reason)
        tick = page.tick
        await read_until(good, page, lambda: page.tick > tick + 10)  # still ticking
        assert feed.thread.session().events == []
        await good.close()

    with caplog.at_level(logging.INFO):
        serve(test)
    said = [r for r in caplog.records if "closed:" in r.getMessage()]
    assert len(said) == 1 and says in said[0].getMessage(), [r.getMessage() for r in said]
    assert not [r for r in caplog.records if r.exc_info or r.levelno >= logging.ERROR]


def test_a_flood_is_cut_off_and_the_server_ticks_on():
    async def test(client, feed):
        good, page = await connect(client)
        flood = await client.ws_connect("/ws")
        for i in range(400):
            await flood.send_str(f'{{"type":"ping","t":{i}}}')
        msg = await closing(flood)
        assert flood.close_code == 1008 and "messages a second" in msg.extra
        tick = page.tick
        await read_until(good, page, lambda: page.tick > tick + 10)
    serve(test)


def stalled_socket(host: str, port: int) -> socket.socket:
    """A WebSocket opened by hand that never reads (a tiny receive buffer)."""
    s = socket.socket()
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.connect((host, port))
    s.sendall(b"GET /ws HTTP/1.1\r\nHost: %s:%d\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
              b"Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"
              % (host.encode(), port))
    return s


class StuckSocket:
    """A page's socket whose sends hang (the peer stopped reading) from the `after`-th on,
    until `gate` is set; what it sent goes into `page`."""

    def __init__(self, after: int):
        self.after, self.sent, self.gate = after, 0, asyncio.Event()
        self.page = PageModel()
        self.closed = False

    async def _send(self, data):
        self.sent += 1
        if self.sent > self.after:
            await self.gate.wait()
        if isinstance(data, bytes):
            self.page.apply(data)
        else:
            self.page.texts.append(json.loads(data))

    send_bytes = send_str = _send


def test_a_page_that_stops_reading_stalls_nobody(monkeypatch):
    monkeypatch.setattr(pages_module, "MAX_BEHIND_TICKS", 10)

    async def test(client, feed):
        good, page = await connect(client)
        stuck_tcp = stalled_socket(client.server.host, client.server.port)  # the real thing
        stuck = StuckSocket(after=3)  # hello, state and the snapshot's one part, then hangs
        slow = pages_module.ConnectedPage(stuck, "stuck", feed.ask_redraw)
        feed.pages.add(slow)
        slow.text(feed.hello())
        writer = asyncio.create_task(slow.write())
        try:
            most = 0
            for i in range(40):  # a scribble: deltas every tick
                await good.send_json({"type": "touch", "x": 100.0 + 9 * i, "y": 300.0 + 11 * i})
                await read_until(good, page, lambda t=page.tick: page.tick > t)
                most = max(most, len(slow.queue), slow.behind_ticks)
            assert slow.resyncs >= 1 and slow.waiting, "the stuck page was not dropped"
            assert most <= pages_module.MAX_BEHIND_TICKS + 2  # its queue stayed bounded
            assert feed.redraws <= 2  # a hung page asks for no snapshot while it hangs
            stuck.gate.set()  # it reads again: a snapshot brings it back to the frost
            await pause(good, page)
            for _ in range(100):
                if not slow.waiting and not slow.queue and not slow.busy:
                    break
                await asyncio.sleep(0.05)
            assert (stuck.page.heights == page.heights).all()
            assert np.array_equal(stuck.page.sorted_tris(), page.sorted_tris())
        finally:
            stuck_tcp.close()
            slow.close()
            feed.pages.discard(slow)
            writer.cancel()
    serve(test)


def test_the_session_written_replays_to_the_same_frost(tmp_path):
    seen = PageModel()

    async def test(client, feed):
        ws, page = await connect(client)
        await ws.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
        await ws.send_json({"type": "touch", "x": 200.0, "y": 300.0, "id": 1})
        await ws.send_json({"type": "touch", "x": 260.0, "y": 360.0, "id": 1, "phase": "move"})
        await read_until(ws, page, lambda: page.tick > 50)
        await ws.send_json({"type": "melt", "x": CENTRE[0], "y": CENTRE[1] + 8})
        await ws.send_json({"type": "key", "key": "EQUAL"})  # humidity up: a rebuild
        await read_until(ws, page, lambda: page.resets == 1)  # the rebuild
        await read_until(ws, page, lambda: page.tick > 30)
        await pause(ws, page)
        await ws.close()
        seen.heights, seen.tris = page.heights, page.tris

    feed = serve(test, session_dir=tmp_path)
    files = list(tmp_path.glob("session-*.json"))
    assert len(files) == 1
    log = SessionLog.load(files[0])
    kinds = [e["kind"] for e in log.events]
    assert kinds.count("touch") == 5 and "melt" in kinds and "params" in kinds
    again = replay(log)
    sim = feed.thread.sim
    assert np.array_equal(again.sim.crystals, sim.crystals)
    assert np.array_equal(again.sim.crystal_alive, sim.crystal_alive)
    assert (again.geometry.heights == feed.thread.geometry.heights).all()
    # and the page, which saw a rebuild on the way, holds that frost too
    assert (seen.heights == again.geometry.heights.ravel().astype(np.float16)).all()


def test_an_autosave_in_flight_never_replaces_the_last_save(tmp_path, monkeypatch):
    """A slow disk: an autosave is being written when the server stops with one more
    event; the save at the end waits for it, so the file keeps both events."""
    monkeypatch.setattr(session_module, "AUTOSAVE_PERIOD", 0.01)
    monkeypatch.setattr(session_keeper, "AUTOSAVE_PERIOD", 0.01)
    gate, save, writes = threading.Event(), SessionLog.save, []

    def slow_save(session, path):
        writes.append(len(session.events))
        if len(writes) == 1:
            assert gate.wait(10)
        return save(session, path)

    monkeypatch.setattr(SessionLog, "save", slow_save)
    feed = Feed(PAPER, seed=1)

    def touched(x: float, y: float) -> None:
        feed.thread.send("touch", ((x, y), None))
        feed.thread.tick()
        feed.pump()

    async def run():
        files = SessionFiles(feed, tmp_path)
        touched(*CENTRE)
        files.start()
        while not writes:  # the autosave of one event, held at the gate
            await asyncio.sleep(0.01)
        touched(200.0, 300.0)
        threading.Timer(0.2, gate.set).start()
        files.stop()
        await asyncio.sleep(0.5)  # (time for a write left behind to land)

    asyncio.run(run())
    [path] = tmp_path.glob("session-*.json")
    assert writes == [1, 2] and len(SessionLog.load(path).events) == 2


def test_a_drained_server_is_read_as_it_goes_and_stop_returns_all_it_printed(serve):
    """ServeProcess.drain (a benchmark's long run): its output read on in a thread of its
    own, so that a long log never fills the pipe; stop() still returns all of it, from the
    address it started with to the line Ctrl-C ends it with, and its status is Ctrl-C's."""
    served = serve().drain()
    said = served.stop()
    assert said.startswith(served.lines[0]) and f"open {served.url}" in served.lines[0]
    assert said.endswith("frost: interrupted (Ctrl-C)\n"), said
    assert served.proc.returncode == 130


@pytest.mark.parametrize("frost", [["-m", "app"], [str(WINDOWS_LIKE)]],
                         ids=["here", "as-on-windows"])
@pytest.mark.usefixtures("subprocesses")
def test_frost_serve_from_the_command_line(tmp_path, frost):
    """The command: it prints its URL, a page grows frost, Ctrl-C writes the session and
    exits 130 (as the window does), and the session replays to the frost the page saw; also
    as on Windows (tests/windows_like.py), whose event loops take no signal handlers."""
    import signal

    served = session_serve(tmp_path, frost)
    proc, url = served.proc, served.url
    try:
        page = PageModel()

        async def main():
            from aiohttp import ClientSession
            async with ClientSession() as http, http.ws_connect(url + "ws") as ws:
                await read_until(ws, page, lambda: page.snapshots >= 1)
                assert page.texts[0]["preset"] == "c-2"  # as asked (not its twin b-2)
                await ws.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
                await read_until(ws, page, lambda: near(page, CENTRE) and page.tick > 30)
                await pause(ws, page)
        asyncio.run(main())
        proc.send_signal(signal.SIGINT)
        assert proc.wait(30) == 130
        # as the window says it (the log's lines are in between)
        assert "\nfrost: interrupted (Ctrl-C)\n" in proc.stderr.read()
    finally:
        proc.kill()
        proc.wait()
    [path] = tmp_path.glob("session-*.json")
    again = replay(SessionLog.load(path))
    assert again.tick == page.tick
    assert (again.geometry.heights.ravel().astype(np.float16) == page.heights).all()


def test_a_clear_while_paused_clears_every_page():
    """A rebuild with no step after it (paused) still tells the pages to drop the frost."""
    async def test(client, feed):
        (a, pa), (b, pb) = await connect(client), await connect(client)
        await a.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
        await read_until(a, pa, lambda: near(pa, CENTRE) and pa.tick > 30)
        await pause(a, pa)
        await b.send_json({"type": "clear"})
        await read_until(a, pa, lambda: pa.resets == 1)
        await read_until(b, pb, lambda: pb.resets == 1)
        for page in (pa, pb):
            assert not page.heights.any() and len(page.tris) == 0
        assert feed.latest.stats.paused and feed.thread.session().events[-1]["kind"] == "clear"
    serve(test)


@pytest.mark.slow  # (seven phases, each a server of its own and its pages: 17 s and more)
def test_the_bench_prints_its_figures(capsys):
    """python -m bench serve runs (briefly) and says each figure, its attacks' too; no speed is
    asserted."""
    from bench import serve as bench
    bench.bytes_offline("c-2", 30, scribble=True)
    attacks = [a for name in bench.ATTACKS for a in ("--attack", name)]
    assert bench.main(["--skip-bytes", "--seconds", "1.5", "--pages", "2", *attacks,
                       "--grid", "fine"]) == 0
    out = capsys.readouterr().out
    for says in ("per tick p50", "snapshot", "no page", "2 pages: tick median", "memory (RSS)",
                 "pages received", "touch to first delta"):
        assert says in out, says
    fine = "(fern, hc 16, D 1, grid spacing 2 (the finest legal grid)): tick median"
    for name in bench.ATTACKS:
        assert f"  {name} {fine}" in out, name
    for says in ("each tenth: ticks/s", "fullest hash cell", "touches applied",
                 "input waiting at the end", "the attack", "closed by the server",
                 "a person's taps beside it: tap to the tick"):
        assert out.count(says) == len(bench.ATTACKS), says
    assert "the attack opened" in out  # (sockets: connections, not messages)


@pytest.mark.parametrize("hc", [7.0, 16.0])
def test_the_all_over_attack_asks_a_page_s_most_touches_at_fresh_spots_all_over(hc):
    """The attack's drag, cut into touches as the server cuts it (DRAG_SPACING_HC * hc
    apart along each move), stays within a page's message rate and asks for more touches
    a second than a page may leave, every spot on the screen and none twice, and reaches
    most hash cells (2 hc) inside the pane's margin within a few passes (those it misses
    are at its turns, by the pane's sides)."""
    import itertools

    from bench import attacks
    from sim.io.gestures import DRAG_SPACING_HC, path_points
    from sim.screen import HEIGHT, SIZE, WIDTH, touch_problem

    spots = list(itertools.islice(attacks.sweep(attacks.Attacker(0, 1, hc)), 4000))
    at, touches = spots[0], [spots[0]]
    for spot in spots[1:]:
        assert touch_problem(*spot, SIZE) is None
        points = path_points(at, spot, DRAG_SPACING_HC * hc)
        touches += points
        at = points[-1] if points else at  # as the server's finger goes on
    assert attacks.MESSAGES_PER_S < pages_module.RATE
    assert len(touches) / len(spots) * attacks.MESSAGES_PER_S > pages_module.POINT_RATE
    assert len(set(touches)) == len(touches)
    cell, margin = 2 * hc, attacks.MARGIN
    cells = {(int((x - margin) // cell), int((y - margin) // cell)) for x, y in touches}
    assert len(cells) >= 0.85 * ((WIDTH - 2 * margin) // cell) * ((HEIGHT - 2 * margin) // cell)


def test_the_attacks_pages_each_start_at_their_own_rows():
    """Page k of 16 begins k/16 of the way down the pane, so the pages sweep apart."""
    from bench import attacks

    firsts = [next(attacks.sweep(attacks.Attacker(k, 16, 7.0)))[1] for k in range(16)]
    assert firsts == sorted(firsts) and len(set(firsts)) == 16


def test_menu_and_keys_change_the_shared_frost_and_every_page_hears():
    async def test(client, feed):
        (a, pa), (b, pb) = await connect(client), await connect(client)
        assert pa.texts[0]["preset"] == "b-2" and pa.texts[0]["look"] == "paper"  # c-2's twin
        await a.send_json({"type": "look", "name": "glass"})
        await read_until(b, pb, lambda: pb.state("look") == "glass" and pb.resets == 1)
        await a.send_json({"type": "backdrop", "name": "lockscreen"})
        await read_until(b, pb, lambda: pb.state("backdrop") == "lockscreen")
        await a.send_json({"type": "preset", "name": "window"})
        await read_until(b, pb, lambda: pb.state("preset") == "window")
        await b.send_json({"type": "key", "key": "V"})  # the window's look key: back to paper
        await read_until(a, pa, lambda: pa.state("look") == "paper" and pa.resets == 3)
        for bad in ({"type": "preset", "name": "z-9"}, {"type": "backdrop", "name": "/etc"},
                    {"type": "key", "key": "S"}, {"type": "key", "key": "NOPE"}):
            await a.send_json(bad)
        asked = len(pa.texts)
        await a.send_json({"type": "ping", "t": 1})  # answered after the four
        await read_until(a, pa, lambda: pa.answered(1, asked))
        notes = [t["text"] for t in pa.texts if t["type"] == "notice"]
        for says in ("'z-9' refused", "backdrop '/etc' refused", "screenshot", "key NOPE"):
            assert any(says in n for n in notes), (says, notes)
        assert feed.controls.backdrop == "lockscreen"
        asked = len(pb.texts)
        await b.send_json({"type": "ping", "t": 2})  # (after a's notices, were they b's too)
        await read_until(b, pb, lambda: pb.answered(2, asked))
        assert not any("refused" in t.get("text", "") for t in pb.texts)  # a's alone
        events = feed.thread.session().events
        kinds = [e["kind"] for e in events]
        # look, preset, key V; nothing else changed the frost (the lock screen, chosen,
        # is recorded, and has its minutes recorded: docs/sessions.md)
        assert [k for k in kinds if k not in ("clock", "backdrop")] == ["params"] * 3
        assert [e["name"] for e in events if e["kind"] == "backdrop"] == ["lockscreen"]
        assert feed.controls.params == Params.preset("window").replace(look="paper")
    serve(test)


def test_the_backdrop_key_steps_through_the_built_ins_from_a_photo_first_to_the_first():
    """The X key (the window's backdrop key) on a page: over a photo or a file of the
    user's it goes to the first built-in, then steps through them in turn (BACKDROPS'
    order: dusk, lockscreen) and round again."""
    from app.backdrops import BACKDROPS
    from app.serve.protocol import Input

    feed = Feed(Params.preset("c-2"), seed=1, backdrop="photo-0123456789abcdef")
    shown = []
    for _ in range(3):
        feed.controls.handle(Input("key", name="X"), {})
        shown.append(feed.controls.backdrop)
    first, second = list(BACKDROPS)
    assert shown == [first, second, first] == ["dusk", "lockscreen", "dusk"]


@pytest.mark.usefixtures("subprocesses")
def test_a_port_taken_or_out_of_range_is_one_clear_error():
    import subprocess
    import sys

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        run = subprocess.run([sys.executable, "-m", "app", "serve", "--port", str(port)],
                             capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stderr.count("\n") == 1
    assert run.stderr.startswith(f"frost: error: cannot listen on 127.0.0.1:{port}")
    assert run.stderr.endswith(" (see frost serve --help)\n"), run.stderr  # (command-line.md)
    run = subprocess.run([sys.executable, "-m", "app", "serve", "--port", "65536"],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stderr.count("\n") == 1 and "--port" in run.stderr


@pytest.mark.parametrize("args, says", [
    (["--host", "no-such-host.invalid"], "cannot listen on no-such-host.invalid:0"),
    (["--session-dir", "/proc/no-such-folder"], "--session-dir /proc/no-such-folder"),
    (["--window"], "--window: no window can open here (DISPLAY is unset)"),
])
@pytest.mark.usefixtures("subprocesses")
def test_bad_command_lines_are_one_clear_error(args, says):
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    run = subprocess.run([sys.executable, "-m", "app", "serve", "--port", "0",
                          "--max-seconds", "5", *args],
                         capture_output=True, text=True, timeout=60, env=env)
    assert (run.returncode, run.stderr.count("\n")) == (2, 1), run.stderr
    assert run.stderr.startswith("frost: error: ") and says in run.stderr
    assert run.stderr.endswith(" (see frost serve --help)\n"), run.stderr  # (command-line.md)


def test_meta_states_the_parameters_seed_and_touches_of_the_frame_published():
    async def test(client, feed):
        ws, page = await connect(client)
        for x, y in ((300.0, 500.0), (450.0, 800.0)):
            await ws.send_json({"type": "touch", "x": x, "y": y})
        await read_until(ws, page, lambda: near(page, (300, 500)) and near(page, (450, 800)))
        await pause(ws, page)
        meta = await (await client.get("/meta")).json()
        session = feed.thread.session()
        assert meta["parameters"] == PAPER.as_dict() and meta["seed"] == 1
        assert meta["tick"] == page.tick == feed.latest.stats.tick
        # the session's touch events, as [tick, x, y]
        touches = [[e["tick"], e["x"], e["y"]] for e in session.events if e["kind"] == "touch"]
        assert meta["touches"] == touches and [t[1:] for t in touches] == [[300, 500], [450, 800]]
        assert meta["Software"] == "frost (page)"
    serve(test)


def test_meta_needs_the_token_too():
    async def test(client, feed):
        assert (await client.get("/meta")).status == 403
        assert (await client.get("/meta?token=sesame")).status == 200
    serve(test, token="sesame")


@pytest.mark.usefixtures("subprocesses")
def test_ctrl_c_with_a_page_connected_closes_it_and_writes_the_session(tmp_path):
    """The page's socket is closed by the server (1001) rather than waited on, and the
    server exits 130 with the session written."""
    import signal

    served = session_serve(tmp_path)
    proc, url = served.proc, served.url
    try:
        page = PageModel()

        async def main():
            from aiohttp import ClientSession
            async with ClientSession() as http, http.ws_connect(url + "ws", heartbeat=None) as ws:
                await read_until(ws, page, lambda: page.snapshots >= 1)
                await ws.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
                await read_until(ws, page, lambda: near(page, CENTRE))
                proc.send_signal(signal.SIGINT)
                return await closing(ws, timeout=15)
        closed = asyncio.run(main())
        assert closed.type in (WSMsgType.CLOSE, WSMsgType.CLOSED, WSMsgType.CLOSING)
        assert proc.wait(30) == 130
    finally:
        proc.kill()
        proc.wait()
    [path] = tmp_path.glob("session-*.json")
    assert [e["kind"] for e in SessionLog.load(path).events] == ["touch"]


def test_an_ipv6_host_is_bracketed_in_the_url(capsys):
    from app.serve.listen import announce

    announce("::1", 8025, None)
    assert "http://[::1]:8025/" in capsys.readouterr().out


def test_the_urls_and_their_qr_codes_are_printed_in_one_write(monkeypatch):
    """A log line of another thread between two writes would land inside a QR code (no
    camera reads it then): the announcement is one write, both codes whole in it."""
    import io

    import segno

    from app.serve import listen

    writes: list[str] = []

    class Console(io.StringIO):
        encoding = "utf-8"

        def write(self, text: str) -> int:
            writes.append(text)
            return len(text)

    monkeypatch.setattr(listen.sys, "stdout", Console())
    monkeypatch.setattr(listen, "lan_address", lambda: "192.0.2.7")
    listen.announce("0.0.0.0", 8025, "T0KEN", 8026)
    [said] = [w for w in writes if w]
    for url in ("http://192.0.2.7:8025/?token=T0KEN", "https://192.0.2.7:8026/?token=T0KEN"):
        drawn = io.StringIO()
        segno.make(url, error="m").terminal(out=drawn, compact=True)
        assert url in said and drawn.getvalue() in said


def test_input_waiting_for_the_thread_stays_bounded(monkeypatch):
    """A page dragging a warm finger corner to corner as fast as its message rate allows
    asks for far more melts than the thread applies; what waits stays bounded (the rest is
    dropped, and that page is told), and the thread goes on ticking."""
    from app.serve import turns

    monkeypatch.setattr(turns, "PAGE_WAITING", 50)
    corners = ({"x": 0, "y": 0}, {"x": 759, "y": 1279})

    async def test(client, feed):
        good, page = await connect(client)
        await pause(good, page)  # nothing applies but input: the backlog stays put
        thread = feed.thread
        ws = await client.ws_connect("/ws")
        sent = thread.sent
        await ws.send_json({"type": "melt", **corners[0], "phase": "down"})
        for i in range(12):  # each a path of about 125 melts
            await ws.send_json({"type": "melt", **corners[(i + 1) % 2], "phase": "move"})
        await ws.send_json({"type": "ping", "t": 1})
        told = []
        async for msg in ws:
            data = json.loads(msg.data) if msg.type == WSMsgType.TEXT else {}
            told += [data["text"]] if data.get("type") == "notice" else []
            if data.get("type") == "pong":
                break
        waiting = thread.sent - sent + feed.controls.turns.waiting()
        assert waiting <= 50 + turns.AHEAD + 130, waiting  # one path over the bound
        assert feed.controls.dropped >= 10 and any("dropped" in t for t in told)
        await good.send_json({"type": "pause"})
        tick = page.tick
        await read_until(good, page, lambda: page.tick > tick + 5)
        await ws.close()
    serve(test)


def test_a_storm_of_preset_changes_regrows_the_frost_a_few_times_not_each(monkeypatch):
    """Preset changes as fast as the message rate allows (the page's limit on changes
    lifted: the thread's part alone): each change waiting right behind another is replaced
    by it (each applied would regrow the whole frost, and the thread fell tens of seconds
    behind); the last one asked for is in force, and what waits drains at once."""
    monkeypatch.setattr(pages_module, "CHANGE_BURST", 1000.0)

    async def test(client, feed):
        good, page = await connect(client)
        await good.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
        await read_until(good, page, lambda: page.tick > 40)
        names = ["window", "fern"] * 60 + ["c-3"]
        for name in names:
            await good.send_json({"type": "preset", "name": name})
        await read_until(good, page, lambda: page.state("preset") == "c-3")
        thread, turns = feed.thread, feed.controls.turns
        # (the page's commands reach the thread in turns: none may still wait for one)
        await read_until(good, page, lambda: turns.waiting() == 0
                         and thread.handled == thread.sent, timeout=30)
        changes = [e for e in thread.session().events if e.get("kind") == "params"]
        assert 1 <= len(changes) < 20, len(changes)
        assert thread.params == Params.preset("c-3").replace(grid_spacing=PAPER.grid_spacing,
                                                             look=PAPER.look)
    serve(test)


def test_a_pages_input_waits_behind_a_few_of_anothers_not_all():
    """A page sweeping a warm finger as fast as its limits allow has hundreds of melts
    waiting; a person's touch on another page after them goes to the thread in its turn,
    behind at most a few, and is applied while the sweeper's melts still wait (in the order
    they came, it waited behind them all)."""
    from app.serve import turns

    corners = ({"x": 0, "y": 0}, {"x": 759, "y": 1279})

    async def test(client, feed):
        good, page = await connect(client)
        await pause(good, page)  # (input still applies each tick: the step waits)
        sweeper = await client.ws_connect("/ws")
        await sweeper.send_json({"type": "melt", **corners[0], "phase": "down"})
        for i in range(4):  # each a path of about 125 melts
            await sweeper.send_json({"type": "melt", **corners[(i + 1) % 2], "phase": "move"})
        await sweeper.send_json({"type": "ping", "t": 1})
        async for msg in sweeper:
            if msg.type == WSMsgType.TEXT and json.loads(msg.data)["type"] == "pong":
                break
        before = len(feed.thread.session().events)  # melts applied so far
        assert feed.controls.turns.waiting() > 100  # the sweeper's, in its queue
        await good.send_json({"type": "touch", "x": 380.0, "y": 640.0})
        await read_until(good, page, lambda: any(
            e["kind"] == "touch" for e in feed.thread.session().events), timeout=30)
        kinds = [e["kind"] for e in feed.thread.session().events]
        assert kinds.index("touch") <= before + turns.AHEAD + 1, (kinds.index("touch"), before)
        for _ in range(200):  # and the sweeper's go on in their turns, with no more input
            if not feed.controls.turns.waiting():
                break
            await asyncio.sleep(0.05)
        assert feed.controls.turns.waiting() == 0
        await sweeper.close()
    serve(test)


def test_changes_are_limited_to_a_few_a_second_and_refused_with_a_notice():
    """A preset change with a touch between each (so none replaces another) 40 times at
    once: the first ten (the burst) go to the thread, the rest are refused with a notice;
    touches are not counted."""
    async def test(client, feed):
        good, page = await connect(client)
        thread = feed.thread
        sent = thread.sent
        for i in range(40):
            await good.send_json({"type": "preset", "name": ("window", "fern")[i % 2]})
            await good.send_json({"type": "touch", "x": 100 + i, "y": 100})
        await good.send_json({"type": "ping", "t": 1})
        await read_until(good, page, lambda: any(t["type"] == "pong" for t in page.texts))
        refused = [t for t in page.texts if t["type"] == "notice" and "changes a second" in t["text"]]
        taken = thread.sent - sent + feed.controls.turns.waiting()  # (sent, or in turn)
        assert 40 + 10 <= taken <= 40 + 11  # a token may come back meanwhile
        assert len(refused) == 80 - taken
    serve(test)


def test_a_request_line_over_8_kib_is_refused_in_one_line_of_log(caplog):
    async def test(client, feed):
        reader, writer = await asyncio.open_connection(client.server.host, client.server.port)
        writer.write(b"GET /" + b"x" * 9000 + b" HTTP/1.1\r\nHost: a\r\n\r\n")
        assert (await asyncio.wait_for(reader.read(100), 10)).startswith(b"HTTP/1.0 400")
        writer.close()
        await asyncio.sleep(0.2)
    with caplog.at_level(logging.INFO, "aiohttp.server"):
        serve(test)
    said = [r for r in caplog.records if r.name == "aiohttp.server"]
    assert len(said) == 1 and said[0].exc_info is None and said[0].levelno == logging.INFO
    assert "bad request refused" in said[0].getMessage() and len(said[0].getMessage()) < 200


class _Sends:
    """A stand-in thread that counts what it is sent (nothing waits: it applies at once)."""

    sent = handled = 0

    def __init__(self):
        self.kinds: list[str] = []
        self.args: list = []

    def send(self, kind, arg=None):
        self.kinds.append(kind)
        self.args.append(arg)

    def show_backdrop(self, name):
        self.backdrops = [*getattr(self, "backdrops", []), name]
        return len(self.backdrops)


def _controls():
    from app.serve.controls import Controls

    return Controls(_Sends(), PAPER, 24.0, "dusk", lambda _text: None, lambda: 0)


def test_a_finger_faster_than_a_person_leaves_at_most_the_bound_of_melts():
    """Sweeping corner to corner 40 times in 0.2 s asks for ~5 000 melts; a page's fingers
    leave the burst plus the rate times the time (less the fractions of a melt the bucket
    still holds, or lost to its cap at the first move), the rest of each path skipped."""
    from app.serve.pages import POINT_BURST, POINT_RATE, TokenBucket
    from app.serve.protocol import Input

    now = [0.0]
    bucket = TokenBucket(POINT_RATE, POINT_BURST, clock=lambda: now[0])
    controls, fingers, told = _controls(), {}, []
    controls.handle(Input("melt", 0.0, 0.0, "down", 1), fingers, told.append, bucket)
    for i in range(40):
        now[0] += 0.005
        x, y = ((759.0, 1279.0), (0.0, 0.0))[i % 2]
        controls.handle(Input("melt", x, y, "move", 1), fingers, told.append, bucket)
    most = POINT_BURST + 0.2 * POINT_RATE
    assert most - 2 <= len(controls.thread.kinds) <= most
    assert controls.skipped > 4000 and len(told) >= 1 and "skipped" in told[0]


def test_a_person_dragging_loses_no_melt_or_touch_to_the_bound():
    """A finger at 3 000 px/s for two seconds leaves every point the same drag leaves with
    no bound at all (the oracle)."""
    from app.serve.pages import POINT_BURST, POINT_RATE, TokenBucket
    from app.serve.protocol import Input

    def drag(kind, bucket, now):
        controls, fingers = _controls(), {}
        controls.handle(Input(kind, 10.0, 640.0, "down", 1), fingers, None, bucket)
        for step in range(1, 201):  # 30 px each 10 ms, back and forth across the screen
            now[0] += 0.01
            x = 10.0 + (30.0 * step) % 1480.0
            x = x if x <= 740.0 else 1480.0 - x
            controls.handle(Input(kind, x, 640.0, "move", 1), fingers, None, bucket)
        return controls.thread.kinds

    for kind in ("melt", "touch"):
        now = [0.0]
        bucket = TokenBucket(POINT_RATE, POINT_BURST, clock=lambda at=now: at[0])
        bounded = drag(kind, bucket, now)
        assert bounded == drag(kind, None, [0.0]) and len(bounded) > 100


def test_a_drag_leaves_melts_evenly_spaced_along_its_path_from_where_it_landed():
    """The warm finger of radius 24 melts every 12 px (MELT_SPACING) along its path: landed
    at x = 100 and moved to 130 then 150, it melts at 100, 112, 124, 136 and 148 (each move
    goes on from the last melt, not from where the finger was seen)."""
    from app.serve.protocol import Input

    controls, fingers = _controls(), {}
    for phase, x in (("down", 100.0), ("move", 130.0), ("move", 150.0)):
        controls.handle(Input("melt", x, 640.0, phase, 1), fingers)
    assert [(round(x, 6), y, r) for x, y, r in controls.thread.args] == [
        (100.0, 640.0, 24.0), (112.0, 640.0, 24.0), (124.0, 640.0, 24.0), (136.0, 640.0, 24.0),
        (148.0, 640.0, 24.0)]


def test_a_change_to_what_is_in_force_sends_the_thread_nothing():
    """Each change of the parameters regrows the whole frost: a look or preset that leaves
    them as they are (the look in force, the preset they follow) is no rebuild; a change
    that is one is sent once, and asked again it is in force."""
    from app.serve.protocol import Input

    controls, fingers = _controls(), {}
    look = PAPER.look
    controls.handle(Input("look", name=look), fingers)
    controls.handle(Input("preset", name="c-2"), fingers)
    assert controls.thread.kinds == []
    other = next(name for name in ("paper", "glass") if name != look)
    controls.handle(Input("look", name=other), fingers)
    controls.handle(Input("look", name=other), fingers)
    assert controls.thread.kinds == ["params"] and controls.thread.args[0].look == other


def test_a_stats_line_in_words():
    from app.serve.server import stats_line

    assert stats_line(10.0, 250, [2.0, 3.0, 9.0], [1000, 3000, 2500], 2, False) == \
        "stats (10.0 s): sim 25.0 ticks/s, tick median 3.0 ms, 2 pages, 2.5 kB a tick each"
    assert stats_line(10.0, 0, [], [], 1, True) == "stats (10.0 s): sim paused, no tick, 1 page"


def test_the_server_logs_its_stats_while_it_serves(monkeypatch, caplog):
    import logging

    from app.serve import server

    monkeypatch.setattr(server, "STATS_PERIOD", 0.5)

    def lines() -> list[str]:
        return [r.getMessage() for r in caplog.records if "stats (" in r.getMessage()]

    async def test(client, feed):
        ws, page = await connect(client)
        await read_until(ws, page, lambda: page.tick > feed.tick() - 1 and page.tick >= 30)
        seen = len(lines())
        await until(lambda: len(lines()) > seen, "a stats line with the page connected")
        line = lines()[seen]
        assert re.search(r"sim \d+\.\d ticks/s, tick median \d+\.\d ms, 1 page", line), line

    with caplog.at_level(logging.INFO, logger="app.serve"):
        serve(test)


def test_the_stats_line_counts_ticks_stepped_across_a_rebuild(monkeypatch, caplog):
    # A new preset regrows the frost from tick 0 (its touches replanted at their ticks):
    # the tick goes back, but the simulation stepped on at its pace all along. The rate is
    # the steps taken (the session's count), never negative.
    import logging

    from app.serve import server

    monkeypatch.setattr(server, "STATS_PERIOD", 0.8)

    def rates() -> list[float]:
        return [float(m) for r in caplog.records
                for m in re.findall(r"sim (-?\d+\.\d) ticks/s", r.getMessage())]

    async def test(client, feed):
        ws, page = await connect(client)
        await read_until(ws, page, lambda: page.tick >= 40)
        await ws.send_json({"type": "preset", "name": "c-3"})
        await read_until(ws, page, lambda: page.state("preset") == "c-3")
        seen = len(rates())  # the rebuild is in the next line's while, the one after is past it
        await until(lambda: len(rates()) >= max(3, seen + 2), "two stats lines after the rebuild")

    with caplog.at_level(logging.INFO, logger="app.serve"):
        serve(test)
    assert all(rate >= 0 for rate in rates()), rates()  # (its pace is the machine's)


def test_a_flood_of_bad_requests_is_a_line_in_the_log_now_and_then(caplog, monkeypatch):
    # A client sending bad heads as fast as it can wrote a line each, 6 600 lines a
    # second: the log says the first, then at most one a BAD_LOG_S with the count since.
    from app.serve import logs

    monkeypatch.setattr(logs, "BAD_LOG_S", 60.0)

    async def bad(client, count):
        for _ in range(count):
            reader, writer = await asyncio.open_connection(client.server.host, client.server.port)
            writer.write(b"GET /meta HTTP/1.1\r\nHost: a\r\nBad Header\r\n\r\n")
            assert (await asyncio.wait_for(reader.read(100), 10)).startswith(b"HTTP/1.0 400")
            writer.close()

    def said() -> list[str]:
        return [r.getMessage() for r in caplog.records if r.name == "aiohttp.server"]

    async def test(client, feed):
        await bad(client, 50)
        await until(said, "a line on the bad requests")
        assert len(said()) == 1 and "more" not in said()[0]
        monkeypatch.setattr(logs, "BAD_LOG_S", 0.0)  # the while since the last line is over
        await bad(client, 1)
        await until(lambda: len(said()) >= 2, "a second line, after BAD_LOG_S")
        assert len(said()) == 2 and said()[1].endswith("; 49 more refused since the last such line")
    with caplog.at_level(logging.INFO, "aiohttp.server"):
        serve(test)


def test_pages_coming_and_going_in_a_flood_are_lines_in_the_log_now_and_then(caplog):
    # A client opening sockets as fast as it can (each reads its hello and goes) wrote a
    # line each, some 200 a second: sixteen pages are named as they come (a whole house at
    # once), then at most a line a PAGE_LOG_S, saying how many went unsaid before it.
    from app.serve import logs
    from app.serve.appkeys import PAGE_LINES

    clock = [0.0]

    async def come_and_go(client, count):
        for _ in range(count):
            ws = await client.ws_connect("/ws")
            assert (await ws.receive_json())["type"] == "hello"
            await ws.close()

    def said() -> list[str]:
        return [r.getMessage() for r in caplog.records if "connected (" in r.getMessage()]

    async def test(client, feed):
        lines = client.server.app[PAGE_LINES]
        lines.bucket.clock, lines.bucket.at = (lambda: clock[0]), 0.0
        await come_and_go(client, 30)
        assert len(said()) == logs.PAGE_LOG_BURST and "unsaid" not in said()[-1]
        clock[0] += logs.PAGE_LOG_S  # a line's worth of time
        await come_and_go(client, 2)
        assert len(said()) == logs.PAGE_LOG_BURST + 1
        assert said()[-1].endswith(f"({30 - logs.PAGE_LOG_BURST} such lines unsaid before it)")
    with caplog.at_level(logging.INFO, "app.serve"):
        serve(test)


def test_each_line_on_a_flood_counts_the_lines_unsaid_since_the_last_one():
    """RateLimitedLog by hand: a house of lines (PAGE_LOG_BURST), 20 more unsaid, a line a
    PAGE_LOG_S later saying those 20; 3 more unsaid, and the next line says those 3 (not
    23); a line after a quiet while, with none unsaid, says none."""
    from app.serve import logs

    clock = [0.0]
    lines = logs.RateLimitedLog()
    lines.bucket.clock, lines.bucket.at = (lambda: clock[0]), 0.0
    said: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record):
            said.append(record.getMessage())

    handler = Keep()
    logs.log.addHandler(handler)
    try:
        with_level = logs.log.level
        logs.log.setLevel(logging.INFO)
        for burst, wait in ((logs.PAGE_LOG_BURST + 20, logs.PAGE_LOG_S), (4, logs.PAGE_LOG_S),
                            (1, 100 * logs.PAGE_LOG_S)):
            for _ in range(burst):
                lines.info("page %s", "p")
            clock[0] += wait
        lines.info("page %s", "q")
    finally:
        logs.log.setLevel(with_level)
        logs.log.removeHandler(handler)
    assert said == ["page p"] * logs.PAGE_LOG_BURST + [
        "page p (20 such lines unsaid before it)", "page p (3 such lines unsaid before it)",
        "page q"]


def test_an_origin_of_another_scheme_is_not_the_pages():
    """Only a page the server served names it as its Origin, under the scheme of the port
    the socket came to (http on the HTTP port, https on the HTTPS one): the same host and
    port under another scheme is not the page's."""
    for port in ("http", "https"):
        assert same_origin(f"{port}://192.168.1.5:8025", "192.168.1.5:8025", port)
        for scheme in {"http", "https", "ws", "wss", "ftp", "chrome-extension", "file"} - {port}:
            assert not same_origin(f"{scheme}://192.168.1.5:8025", "192.168.1.5:8025", port), scheme


def test_without_a_token_only_a_loopback_host_is_answered():
    # With no token (the server bound to 127.0.0.1), a page of another site whose name
    # its DNS turns to 127.0.0.1 (DNS rebinding) asks with its own name as Host and Origin,
    # so the Origin check passes: such a page read /meta and drove the frost. Only the
    # names of this machine (any port: a tunnel) are answered; a token admits any name.
    upgrade = {"Connection": "Upgrade", "Upgrade": "websocket", "Sec-WebSocket-Version": "13",
               "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ=="}

    async def test(client, feed):
        for host in ("evil.example:8025", "evil.example", "192.168.1.5:8025", "127.0.0.1.evil.example",
                     "evil-localhost", "evil-localhost:8025", "notlocalhost", "localhost.evil.example"):
            assert (await client.get("/meta", headers={"Host": host})).status == 403, host
            resp = await client.get("/ws", headers={"Host": host, "Origin": f"http://{host}", **upgrade})
            assert resp.status == 403, host
        for host in ("127.0.0.1:8025", "localhost:9000", "LOCALHOST", "[::1]:8025", "127.0.0.2"):
            assert (await client.get("/meta", headers={"Host": host})).status == 200, host
        ws, _page = await connect(client)
        await ws.close()
    serve(test)

    async def with_token(client, feed):
        resp = await client.get("/meta?token=s3cret", headers={"Host": "192.168.1.5:8025"})
        assert resp.status == 200
    serve(with_token, token="s3cret")


def test_a_flood_of_deeply_nested_messages_is_a_few_lines_of_log():
    """Sockets opened as fast as a client can, each sending '[' * 1000 (under 1 KiB): each
    closed with 1008; the log says the first sixteen pages' comings and goings, then at
    most a line a while (268 tracebacks of 33 lines before)."""
    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record):
            records.append(record)

    async def test(client, feed):
        for _ in range(60):
            ws = await client.ws_connect("/ws")
            await ws.send_str("[" * 1000)
            await closing(ws)
            assert ws.close_code == 1008

    keep, root = Keep(logging.INFO), logging.getLogger()
    level = root.level
    root.addHandler(keep)
    root.setLevel(logging.INFO)
    try:
        serve(test)
    finally:
        root.removeHandler(keep)
        root.setLevel(level)
    assert not [r for r in records if r.exc_info or r.levelno >= logging.ERROR]
    pages = [r for r in records if "serve: page" in r.getMessage()]
    assert len(pages) <= 16 + 1, len(pages)  # the house of 16, and one a PAGE_LOG_S at most


def test_a_message_the_server_fails_on_closes_that_socket_alone_in_one_line(caplog, monkeypatch):
    """A bug of the server's met by one page's message (here: handling a touch raises)
    closes that socket with 1011 (internal error) and a line, no traceback; the others
    tick on."""
    from app.serve.controls import Controls

    def broken(self, message, *args):
        raise ValueError("a bug met")

    async def test(client, feed):
        good, page = await connect(client)
        bad = await client.ws_connect("/ws")
        monkeypatch.setattr(Controls, "handle", broken)
        await bad.send_json({"type": "touch", "x": 10, "y": 10})
        msg = await closing(bad)
        assert bad.close_code == 1011 and "ValueError" in msg.extra
        tick = page.tick
        await read_until(good, page, lambda: page.tick > tick + 5)
        await good.close()

    with caplog.at_level(logging.INFO):
        serve(test)
    said = [r.getMessage() for r in caplog.records if "closed:" in r.getMessage()]
    assert len(said) == 1 and "ValueError: a bug met" in said[0], said
    assert not [r for r in caplog.records if r.exc_info or r.levelno >= logging.ERROR]


CHANGES = [{"type": "key", "key": "NOPE"}, {"type": "preset", "name": "nope"},
           {"type": "look", "name": "nope"}, {"type": "backdrop", "name": "nope"},
           {"type": "step"}, {"type": "pause"}, {"type": "clear"}]


def test_every_kind_of_change_counts_against_the_change_limit():
    """Twelve of one kind at once (each its own page): the burst of ten goes through (a
    name refused or not), the rest are refused with a notice, whatever the kind; keys too,
    which the window's key table turns into any change at all."""
    async def test(client, feed):
        for change in CHANGES:
            ws, page = await connect(client)
            for _ in range(12):
                await ws.send_json(change)
            await ws.send_json({"type": "ping", "t": 1})
            await read_until(ws, page, lambda p=page: any(t["type"] == "pong" for t in p.texts))
            refused = [t for t in page.texts if t["type"] == "notice"
                       and "changes a second" in t["text"]]
            assert 1 <= len(refused) <= 2, (change, refused)  # (a token may come back meanwhile)
            await ws.close()
    serve(test)


def test_meta_states_the_tick_of_the_frame_published_not_the_simulations():
    """/meta describes the frame the pages were sent last: a simulation that ticked on
    since (its snapshots not yet published) is not that frame. The thread is ticked by
    hand here (no schedule, no loop) and the feed published by hand."""
    from aiohttp.test_utils import make_mocked_request

    feed = Feed(PAPER, seed=1, touches=[CENTRE])
    app = make_app(feed)
    for _ in range(5):
        feed.thread.tick()
    feed.pump()
    for _ in range(3):
        feed.thread.tick()
    assert feed.thread.sim.tick == 8 and feed.latest.stats.tick == 5

    async def ask() -> dict:
        request = make_mocked_request("GET", "/meta", app=app, headers={"Host": "127.0.0.1"})
        match = await app.router.resolve(request)
        return json.loads((await match.handler(request)).body)

    meta = asyncio.run(ask())
    assert meta["tick"] == 5 and meta["touches"] == [[0, *CENTRE]]


def test_a_page_gone_while_a_large_message_of_its_is_compressed_leaves_no_error_behind():
    """Browsers ask for permessage-deflate, and aiohttp compresses a message over 16 KiB in a
    shielded task of its own. A page gone in the middle (a phone's tab closed while its
    snapshot is sent) had its writer cancelled around that task, whose "Cannot write to
    closing transport" then went unretrieved: asyncio's "Task exception was never
    retrieved" and a traceback in the terminal, for about one such page in two."""
    import gc

    async def test(client, feed):
        errors: list[str] = []
        asyncio.get_running_loop().set_exception_handler(
            lambda _loop, context: errors.append(f"{context.get('message')}: "
                                                 f"{context.get('exception')!r}"))
        ws, page = await connect(client)
        for i in range(60):  # frost all over: a snapshot of large parts
            await ws.send_json({"type": "touch", "x": 40.0 + (i * 137) % 680,
                                "y": 40.0 + (i * 211) % 1200})
        await read_until(ws, page, lambda: page.tick > 150, timeout=60)
        big = 0
        for k in range(24):
            gone = await client.ws_connect("/ws", compress=15)
            assert gone.compress  # the extension a browser asks for, negotiated
            await gone.receive()  # its hello: the state and the snapshot follow
            await asyncio.sleep(0.002 * (k % 8))
            gone._response.connection.transport.abort()  # gone, mid-snapshot or after
            await asyncio.sleep(0.05)
            big = max(big, max((len(p) for p in feed.snapshots.kept.parts), default=0)
                      if feed.snapshots.kept else 0)
        await asyncio.sleep(0.5)
        gc.collect()  # (an unretrieved exception is reported when its task is collected)
        await asyncio.sleep(0.1)
        assert big > 16 * 1024, big  # the snapshot's parts took aiohttp's threaded path
        assert errors == []
    serve(test)


def test_nothing_follows_a_close_frame_sent_while_a_message_waits_to_be_written():
    """A page's message is written by a task that starts a moment after the writer takes it
    from the queue; a close frame sent meanwhile (its page broke a rule) must be the last
    frame on that socket (RFC 6455: no data frame after a Close)."""
    class Socket:  # what Page uses of aiohttp's WebSocketResponse
        def __init__(self):
            self.closed, self.frames = False, []

        async def send_str(self, message):
            self.frames.append(message)

        async def close(self):
            self.closed = True
            self.frames.append("close frame")

    async def main():
        ws = Socket()
        page = pages_module.ConnectedPage(ws, "p", lambda: None)
        page.waiting = False
        page.text("first")
        writer = asyncio.create_task(page.write())
        await asyncio.sleep(0)  # the writer took "first": its send starts at the next step
        assert not page.queue and page.busy
        await ws.close()
        for _ in range(5):
            await asyncio.sleep(0)
        page.close()
        await asyncio.wait_for(writer, 5)
        return ws.frames

    assert asyncio.run(main()) == ["close frame"]


def test_each_page_is_told_of_its_own_dropped_input(monkeypatch):
    """Two pages' taps while the thread takes none (never started): the thread holds
    MIN_AHEAD (4), each page's queue PAGE_WAITING (3), the rest is dropped. Page a drops
    one, page b five: each is told at its own first drop, with its own count (counted
    for all pages at once, b's first was the second drop and went untold)."""
    from app.serve import protocol, turns

    monkeypatch.setattr(turns, "PAGE_WAITING", 3)
    feed = Feed(PAPER, seed=1)
    told: dict[str, list[str]] = {"a": [], "b": []}
    queues = {name: feed.controls.turns.open() for name in told}

    def tap(name: str, k: int) -> None:
        message = protocol.parse_input(json.dumps({"type": "touch", "x": 100 + k, "y": 200,
                                                   "phase": "down"}))
        feed.controls.handle(message, {}, told[name].append, None, queues[name])

    for k in range(turns.MIN_AHEAD + 3 + 1):
        tap("a", k)
    for k in range(3 + 5):
        tap("b", k)
    assert feed.thread.sent == turns.MIN_AHEAD + 1  # (+1: the backdrop the feed starts on)
    assert feed.controls.dropped == 6
    assert [t.rsplit(": ", 1)[1] for t in told["a"]] == ["1 so far"]
    assert [t.rsplit(": ", 1)[1] for t in told["b"]] == ["1 so far"]
    assert all(t.startswith("too much input waiting (") for t in told["a"] + told["b"])
