"""`frost serve`'s connections against clients that never finish a request (app/serve/guard.py):
the server as `frost serve` listens (its runner, a free port), raw sockets and real
WebSockets against it, the deadlines shortened. The oracle is the clock and the socket:
closed (EOF or reset) or answered."""

from __future__ import annotations

import asyncio

import aiohttp
import pytest
from support.page_model import until

from app.serve import guard
from app.serve.feed import Feed
from app.serve.listen import listen
from app.serve.server import make_app
from sim import Params

HEAD = 0.4  # the shortened deadline for a request's head, s
GET = b"GET /meta HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"


@pytest.fixture
def short(monkeypatch):
    monkeypatch.setattr(guard, "HEAD_S", HEAD)
    monkeypatch.setattr(guard, "MAX_CONNECTIONS", 4)


def run(test, token: str | None = None):
    """`test(port, runner)` against a server listening as `frost serve` does."""
    async def main():
        feed = Feed(Params.preset("c-2"), seed=1)
        runner = await listen(make_app(feed, token), "127.0.0.1", 0, token)
        assert runner is not None
        try:
            await test(runner.addresses[0][1], runner)
        finally:
            await runner.cleanup()
    asyncio.run(main())


async def closed(reader: asyncio.StreamReader, within: float) -> bool:
    """Whether the server closes the connection (EOF or reset) within `within` s,
    reading and dropping whatever it sends before."""
    loop = asyncio.get_running_loop()
    end = loop.time() + within
    try:
        while loop.time() < end:
            data = await asyncio.wait_for(reader.read(65536), end - loop.time())
            if not data:
                return True
    except (ConnectionResetError, BrokenPipeError):
        return True
    except asyncio.TimeoutError:
        return False
    return False


async def answered(reader: asyncio.StreamReader) -> bytes:
    """The status line of the server's answer, read whole (head, then Content-Length bytes)."""
    head = await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), 5)
    length = [int(line.split(b":")[1]) for line in head.split(b"\r\n")
              if line.lower().startswith(b"content-length:")]
    await asyncio.wait_for(reader.readexactly(length[0] if length else 0), 5)
    return head.split(b"\r\n")[0]


def test_a_head_never_finished_is_closed_and_a_finished_one_answered(short):
    async def test(port, runner):
        r1, w1 = await asyncio.open_connection("127.0.0.1", port)
        w1.write(b"GET /meta HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # no blank line: unfinished
        r2, w2 = await asyncio.open_connection("127.0.0.1", port)
        w2.write(GET)
        assert (await answered(r2)).startswith(b"HTTP/1.1 200")
        assert not await closed(r1, HEAD / 2)  # not before its deadline
        assert await closed(r1, HEAD + 1.0)
        assert runner.timed_out == 1
        r3, w3 = await asyncio.open_connection("127.0.0.1", port)  # silent from the start
        assert await closed(r3, HEAD + 1.0)
        for w in (w1, w2, w3):
            w.close()
    run(test)


def test_a_head_dribbled_a_byte_at_a_time_is_timed_from_its_first_byte(short):
    # Bytes keep coming, each well within the deadline of the last, but the head as a
    # whole takes longer than HEAD_S: closed.
    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        loop = asyncio.get_running_loop()
        t0 = loop.time()
        for byte in GET[:-4]:
            writer.write(bytes([byte]))
            if await closed(reader, HEAD / 8):
                break
        else:
            raise AssertionError("a head dribbled for longer than the deadline stayed open")
        assert HEAD * 0.9 < loop.time() - t0 < HEAD + 1.0
        writer.close()
    run(test)


def test_a_kept_alive_connection_is_timed_again_for_its_next_head(short):
    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(GET)
        assert (await answered(reader)).startswith(b"HTTP/1.1 200")
        await asyncio.sleep(HEAD * 1.5)  # idle between requests: aiohttp's keep-alive
        writer.write(GET)  # a second request, whole: answered on the same connection
        assert (await answered(reader)).startswith(b"HTTP/1.1 200")
        writer.write(b"GET /meta HTTP/1.1\r\n")  # a third, never finished
        assert await closed(reader, HEAD + 1.0)
        writer.close()
    run(test)


def test_a_heads_end_split_across_two_reads_finishes_it(short):
    # The blank line's first three bytes end one read and its last byte starts the next:
    # the head is whole, its timer stopped, and the connection lives on past the deadline.
    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(GET[:-1])
        await writer.drain()
        await asyncio.sleep(HEAD / 4)  # (two reads on the server's side)
        writer.write(GET[-1:])
        assert (await answered(reader)).startswith(b"HTTP/1.1 200")
        assert not await closed(reader, HEAD * 1.5)
        writer.write(GET)  # the next request, on the same connection
        assert (await answered(reader)).startswith(b"HTTP/1.1 200")
        assert runner.timed_out == 0
        writer.close()
    run(test)


def test_a_full_house_makes_room_for_a_request_but_never_drops_a_page(short):
    async def test(port, runner):
        hung = []
        for _ in range(guard.MAX_CONNECTIONS):  # every slot held by an unfinished head
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(b"GET / HTTP/1.1\r\n")
            hung.append((reader, writer))
        await until(lambda: len(runner.conns) == guard.MAX_CONNECTIONS, "every slot held")
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(GET)
        assert (await answered(reader)).startswith(b"HTTP/1.1 200")  # a person gets in
        assert await closed(hung[0][0], HEAD / 4)  # in the oldest one's place
        assert not await closed(hung[1][0], 0.01)
        assert runner.evicted == 1
        for _, w in hung + [(reader, writer)]:
            w.close()
        await until(lambda: not runner.conns, "the closed ones gone from the house")
        # Pages in every slot, kept past the deadline: the next connection is refused,
        # and every page still hears the ticks.
        async with aiohttp.ClientSession() as session:
            pages = [await session.ws_connect(f"http://127.0.0.1:{port}/ws")
                     for _ in range(guard.MAX_CONNECTIONS)]
            await asyncio.sleep(HEAD * 2)
            late_reader, late_writer = await asyncio.open_connection("127.0.0.1", port)
            late_writer.write(GET)
            assert await closed(late_reader, 1.0)
            assert runner.refused >= 1
            for ws in pages:  # each still hears the ticks (a message a tick)
                ticks = 0
                while ticks < 3:
                    msg = await asyncio.wait_for(ws.receive(), 5)
                    assert msg.type in (aiohttp.WSMsgType.BINARY, aiohttp.WSMsgType.TEXT)
                    ticks += msg.type == aiohttp.WSMsgType.BINARY
                await ws.close()
            late_writer.close()
    run(test)


def test_a_full_house_of_idle_connections_gives_way_before_a_head_on_its_way(short):
    # A client that opens connections as fast as it can, each asking one thing and then
    # idling, keeps the house full of kept-alive connections: a person's connection,
    # whose head is still on its way, must not be the one closed for the next of them
    # (else every file of the page is reset, and the page never loads).
    async def test(port, runner):
        person_reader, person_writer = await asyncio.open_connection("127.0.0.1", port)
        person_writer.write(GET[:10])  # the head's first bytes, the rest on their way
        idle = []
        for _ in range(guard.MAX_CONNECTIONS - 1):  # asked, answered, idle; all younger
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(GET)
            assert (await answered(reader)).startswith(b"HTTP/1.1 200")
            idle.append((reader, writer))
        for _ in range(2):  # two more in a full house: two idle ones close for them
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(GET)
            assert (await answered(reader)).startswith(b"HTTP/1.1 200")
            idle.append((reader, writer))
        assert await closed(idle[0][0], HEAD / 4) and await closed(idle[1][0], HEAD / 4)
        assert not await closed(idle[2][0], 0.01)
        person_writer.write(GET[10:])
        assert (await answered(person_reader)).startswith(b"HTTP/1.1 200")
        assert runner.evicted == 2
        for _, w in idle + [(person_reader, person_writer)]:
            w.close()
    run(test)


def test_a_flood_of_connections_is_a_line_in_the_log_now_and_then(short, caplog, monkeypatch):
    # Thousands of connections a second, each closing an older one: the log says so once,
    # then at most once a LOG_S with the count since, not a line per thousand.
    monkeypatch.setattr(guard, "LOG_S", 60.0)

    async def flood(port, runner, count):
        held, end = [], runner.evicted + count
        while runner.evicted < end:
            _, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(b"G")
            held.append(writer)
            if len(held) > 8:
                held.pop(0).close()
        for w in held:
            w.close()

    def said() -> list[str]:
        return [r.getMessage() for r in caplog.records if "make room" in r.getMessage()]

    async def test(port, runner):
        await flood(port, runner, 2100)
        assert len(said()) == 1 and "(1 closed since the last such line, 1 in all)" in said()[0]
        evicted = runner.evicted
        monkeypatch.setattr(guard, "LOG_S", 0.0)  # the while since the last line is over
        await flood(port, runner, 1)
        assert len(said()) == 2
        assert f"({evicted} closed since the last such line, {evicted + 1} in all)" in said()[1]
    with caplog.at_level("INFO", logger="app.serve"):
        run(test)


def test_a_head_longer_than_any_page_sends_is_closed_at_once(short):
    # aiohttp keeps a head's lines until it is whole (up to 128 of 8 KiB each): 256 such
    # heads held 700 MB. One over MAX_HEAD_BYTES is closed as its bytes pass the mark,
    # long before its deadline; a long head within it is answered.
    line = b"X-Long: " + b"a" * 7990 + b"\r\n"
    within = guard.MAX_HEAD_BYTES // len(line) - 1

    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        for _ in range(2):  # each head counted from its own start, read a line at a time
            for part in (GET[:-2], *[line] * within, b"\r\n"):
                writer.write(part)
                await asyncio.sleep(0.005)
            assert (await answered(reader)).startswith(b"HTTP/1.1 200")
        writer.write(GET[:-2] + line * (within + 2))  # past the mark, unfinished
        assert await closed(reader, HEAD / 4)
        assert runner.timed_out == 0 and runner.too_long == 1
        writer.close()
    run(test)


def test_a_head_too_long_is_closed_though_it_came_a_line_at_a_time(short):
    # No read holds more than a line (8 KiB), yet the head's bytes add up past
    # MAX_HEAD_BYTES: it is closed once they do, not when its deadline comes.
    line = b"X-Long: " + b"a" * 7990 + b"\r\n"
    lines = guard.MAX_HEAD_BYTES // len(line) + 2

    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        for part in (GET[:-2], *[line] * lines):
            writer.write(part)
            await writer.drain()
            await asyncio.sleep(0.005)
        assert await closed(reader, HEAD / 4)
        assert runner.timed_out == 0 and runner.too_long == 1
        writer.close()
    run(test)


def test_an_upgrade_refused_for_its_token_stays_timed(short):
    # A socket asked for without the token (or with a wrong one) is a 403: its connection
    # is no page's, and a frame begun on it and never ended does not keep it open.
    async def test(port, runner):
        for query in ("", "?token=wrong"):
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(f"GET /ws{query} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                         "Connection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
                         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n".encode())
            assert (await answered(reader)).startswith(b"HTTP/1.1 403")
            assert not any(c.page for c in runner.conns)
            writer.write(b"\x81\x85abcd")  # a frame's first bytes, as if taken; no more
            assert await closed(reader, HEAD + 1.0)  # (aiohttp closes it at once)
            writer.close()
    run(test, token="secret")


def masked_text(text: str) -> bytes:
    """A client's WebSocket text frame (masked, as a client must send them)."""
    data, mask = text.encode(), b"frst"
    assert len(data) < 126
    return bytes([0x81, 0x80 | len(data)]) + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data))


def test_a_pages_socket_is_never_timed_though_its_first_frame_came_with_its_head(short):
    """A client may send its first frame right behind its upgrade request, before the 101:
    the guard reads those bytes as the next head begun (its deadline running), and taking
    the page's socket must stop that deadline, or the page is closed HEAD_S later."""
    async def test(port, runner):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                     "Connection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
                     "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n".encode()
                     + masked_text('{"type":"ping","t":7}'))
        head = await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), 5)
        assert head.startswith(b"HTTP/1.1 101")
        assert not await closed(reader, HEAD * 4)  # well past the head's deadline
        assert [c.page for c in runner.conns] == [True] and runner.timed_out == 0
        writer.close()
    run(test)


def test_aiohttp_is_asked_whether_a_connection_waits_for_its_next_request():
    """guard.awaits_request reads aiohttp's private RequestHandler._waiter (no public way
    exists): it must say True for a connection kept alive between two requests and False
    while a request is being answered. A change of aiohttp's makes this fail, not the guard
    silently close busy connections first (or never the idle ones)."""
    release = asyncio.Event()

    async def slow(_request):
        await release.wait()
        return aiohttp.web.Response(text="slow")

    async def quick(_request):
        return aiohttp.web.Response(text="quick")

    async def main():
        app = aiohttp.web.Application()
        app.router.add_get("/quick", quick)
        app.router.add_get("/slow", slow)
        runner = guard.GuardedRunner(app, access_log=None)
        await runner.setup()
        site = aiohttp.web.TCPSite(runner, "127.0.0.1", 0)
        await site.start()
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", runner.addresses[0][1])
            writer.write(b"GET /quick HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            assert (await answered(reader)).startswith(b"HTTP/1.1 200")
            [conn] = runner.conns
            assert guard.awaits_request(conn.inner) and conn.idle()  # kept alive, idle
            writer.write(b"GET /slow HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            await until(lambda: not guard.awaits_request(conn.inner), "aiohttp taking the request")
            assert not conn.idle()  # answering
            release.set()
            assert (await answered(reader)).startswith(b"HTTP/1.1 200")
            await until(lambda: guard.awaits_request(conn.inner) and conn.idle(),
                        "the connection kept alive and idle again")
            writer.close()
        finally:
            await runner.cleanup()

    asyncio.run(main())
