"""The shaping proxy of `python -m bench page --network` (bench/shaper.py) against servers
of the test's own (an echo, a recorder), timed with the test's own clock: bytes arrive
unchanged and in order, each way waits at least its delay less its jitter, N bytes take at
least N * 8 / rate seconds, and a close on either side closes the other. Only lower bounds
are held: a loaded machine only adds time. Exact times only on a virtual clock (VirtualLoop,
no sockets): a connection's handshake waits alone."""

from __future__ import annotations

import asyncio
import random
import selectors
import time

import pytest

from bench import page as page_bench
from bench.shaper import PROFILES, Profile, Shaper, profile

# Delays long beside a loaded machine's scheduling, jitter nearly as large, so that
# pieces given to the link within a few ms of each other would cross if it reordered.
JITTERY = Profile("test", delay=0.030, jitter=0.025, down_bps=1e9, up_bps=1e9)
WAIT = 30.0  # s: a generous bound on anything the tests wait for (never a timing claim)


def run(coroutine):
    return asyncio.run(asyncio.wait_for(coroutine, 120))


async def echo(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    while data := await reader.read(65536):
        writer.write(data)
        await writer.drain()
    writer.close()


async def started(handler, shaper_profile: Profile, **kw) -> tuple[asyncio.Server, Shaper]:
    server = await asyncio.start_server(handler, "127.0.0.1", 0)
    target = ("127.0.0.1", server.sockets[0].getsockname()[1])
    return server, await Shaper(target, shaper_profile, **kw).start()


async def stopped(server: asyncio.Server, shaper: Shaper) -> None:
    await shaper.stop()
    server.close()
    await server.wait_closed()


def through(handler, link: Profile, client):
    """`client(reader, writer)` on one connection through a shaper of profile `link` to a
    server running `handler`: what it returns (the writer closed after it, the shaper and
    the server stopped)."""
    async def main():
        server, shaper = await started(handler, link)
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", shaper.port)
            try:
                return await client(reader, writer)
            finally:
                writer.close()
        finally:
            await stopped(server, shaper)

    return run(main())


def test_the_profiles_are_the_issues_figures():
    """wifi: 20 ms round trip +- 5 ms, 30 Mbit/s each way; 4g: 60 +- 15 ms, 9 down, 1.5 up."""
    wifi, g4 = PROFILES["wifi"], PROFILES["4g"]
    assert (2 * wifi.delay, 2 * wifi.jitter, wifi.down_bps, wifi.up_bps) == (0.020, 0.005, 30e6, 30e6)
    assert (2 * g4.delay, 2 * g4.jitter, g4.down_bps, g4.up_bps) == (0.060, 0.015, 9e6, 1.5e6)
    with pytest.raises(ValueError, match="no network profile '5g' \\(choose from wifi, 4g\\)"):
        profile("5g")


def test_bytes_arrive_unchanged_and_in_order_both_ways():
    """Writes of random sizes (1 byte to 20 kB, some back to back, some apart) through a
    jittery link to an echo and back: the same bytes, in the same order."""
    rng = random.Random(5)
    sent = rng.randbytes(600_000)

    async def client(reader, writer):
        at = 0
        while at < len(sent):
            n = rng.choice([1, 2, 7, 100, 1500, 4096, 4097, 20_000])
            writer.write(sent[at:at + n])
            at += n
            if rng.random() < 0.2:
                await asyncio.sleep(rng.choice([0, 0.001, 0.005]))
        writer.write_eof()
        return await asyncio.wait_for(reader.read(-1), WAIT)  # to the echo's close

    got = through(echo, JITTERY, client)
    assert len(got) == len(sent)
    assert got == sent


def test_each_way_waits_at_least_its_delay_less_its_jitter():
    """Ping-pong of single bytes: the recorder notes when each byte arrives and when it
    answers; each way took at least delay - jitter (20 samples each way), and the first byte
    of a connection one round trip more (the TCP handshake) and its own way."""
    p = Profile("test", delay=0.040, jitter=0.015, down_bps=1e9, up_bps=1e9)
    arrived: list[float] = []
    answered: list[float] = []

    async def recorder(reader, writer):
        while await reader.read(1):
            arrived.append(time.monotonic())
            answered.append(time.monotonic())
            writer.write(b"p")
            await writer.drain()
        writer.close()

    async def main():
        server, shaper = await started(recorder, p)
        try:
            connecting = time.monotonic()
            reader, writer = await asyncio.open_connection("127.0.0.1", shaper.port)
            sends, receipts = [], []
            for _ in range(21):
                sends.append(time.monotonic())
                writer.write(b"q")
                await asyncio.wait_for(reader.readexactly(1), WAIT)
                receipts.append(time.monotonic())
            writer.close()
            return connecting, sends, receipts
        finally:
            await stopped(server, shaper)

    connecting, sends, receipts = run(main())
    assert len(arrived) == len(sends) == 21
    least = p.delay - p.jitter
    assert arrived[0] - connecting >= 2 * p.delay + least
    up = [a - s for s, a in zip(sends, arrived, strict=True)]
    down = [r - a for a, r in zip(answered, receipts, strict=True)]
    assert min(up) >= least, up
    assert min(down) >= least, down


def test_n_bytes_take_at_least_n_bits_over_the_rate_each_way():
    """100 kB up at 2 Mbit/s take >= 0.4 s; 100 kB down at 1 Mbit/s take >= 0.8 s (no delay,
    no jitter: the cap alone)."""
    p = Profile("test", delay=0.0, jitter=0.0, down_bps=1e6, up_bps=2e6)
    n = 100_000
    times: dict[str, float] = {}

    async def sink(reader, writer):
        got = 0
        while got < n:
            got += len(await reader.read(65536))
        times["up_done"] = time.monotonic()
        times["down_start"] = time.monotonic()
        writer.write(bytes(n))
        await writer.drain()
        writer.close()

    async def client(reader, writer):
        times["up_start"] = time.monotonic()
        writer.write(bytes(n))
        await asyncio.wait_for(reader.readexactly(n), WAIT)
        times["down_done"] = time.monotonic()

    through(sink, p, client)
    assert times["up_done"] - times["up_start"] >= n * 8 / p.up_bps
    assert times["down_done"] - times["down_start"] >= n * 8 / p.down_bps


def test_connections_share_the_link():
    """Two connections uploading 50 kB each at once over 1 Mbit/s: the last byte of both
    arrives >= 0.8 s after the start (the cap is the link's, not each connection's)."""
    p = Profile("test", delay=0.0, jitter=0.0, down_bps=1e9, up_bps=1e6)
    n, done = 50_000, []

    async def sink(reader, writer):
        got = 0
        while got < n:
            got += len(await reader.read(65536))
        done.append(time.monotonic())
        writer.close()

    async def main():
        server, shaper = await started(sink, p)
        try:
            pairs = [await asyncio.open_connection("127.0.0.1", shaper.port) for _ in range(2)]
            start = time.monotonic()
            for _, writer in pairs:
                writer.write(bytes(n))
            for reader, writer in pairs:
                await asyncio.wait_for(reader.read(), WAIT)  # the sink's close
                writer.close()
            return start
        finally:
            await stopped(server, shaper)

    start = run(main())
    assert len(done) == 2
    assert max(done) - start >= 2 * n * 8 / p.up_bps


class VirtualTime(selectors.DefaultSelector):
    """A selector whose waits take no time: with nothing ready it moves `now` on by the wait
    the loop asked for (to its next timer). A loop over it (VirtualLoop) with no real I/O
    runs on its own clock, the same under any load."""

    def __init__(self) -> None:
        super().__init__()
        self.now = 0.0

    def select(self, timeout: float | None = None):
        ready = super().select(0)
        if not ready:
            if timeout is None:
                raise RuntimeError("the loop waits for nothing that will come")
            self.now += timeout
        return ready


class VirtualLoop(asyncio.SelectorEventLoop):
    def __init__(self) -> None:
        self.clock = VirtualTime()
        super().__init__(self.clock)

    def time(self) -> float:
        return self.clock.now


class End:
    """A side's writer in memory: each write with its (loop) time; what is written fed on
    to `then` (a StreamReader: the server's echo), when given."""

    def __init__(self, then: asyncio.StreamReader | None = None):
        self.then, self.got = then, []

    def write(self, data: bytes) -> None:
        self.got.append((asyncio.get_running_loop().time(), data))
        if self.then is not None:
            self.then.feed_data(data)

    async def drain(self) -> None:
        pass

    def can_write_eof(self) -> bool:
        return True

    def write_eof(self) -> None:
        if self.then is not None:
            self.then.feed_eof()


def test_a_connections_handshake_waits_alone():
    """A page's connection A pings an echo; B opens, its first bytes sent at once (as a
    browser's request is). B's first bytes reach the server one round trip late (its
    handshake), but A's ping, sent while B's handshake is under way, still takes one round
    trip: B's handshake does not hold the shared link. On a virtual clock (no sockets), so
    each time is exact: a byte takes delay + 8 / rate each way."""
    p = Profile("test", delay=0.100, jitter=0.0, down_bps=1e6, up_bps=1e6)
    way = p.delay + 8 / 1e6  # one byte, one way

    async def main():
        shaper = Shaper(("127.0.0.1", 9), p)
        a_page, a_back, b_page, b_back = (asyncio.StreamReader() for _ in range(4))
        a_out, a_echo, b_out, b_server = End(), End(a_back), End(), End()
        a_ways = shaper.join(a_page, a_out, a_back, a_echo)  # type: ignore[arg-type]
        loop = asyncio.get_running_loop()

        async def at(t: float) -> None:
            await asyncio.sleep(t - loop.time())

        async def until(done) -> None:
            while not done():
                await asyncio.sleep(0.001)  # virtual: the times asserted are the writes'

        async def ping(t: float) -> float:
            """A's round trip of a byte sent at `t`."""
            await at(t)
            seen = len(a_out.got)
            a_page.feed_data(b"p")
            await until(lambda: len(a_out.got) > seen)
            return a_out.got[-1][0] - t

        tasks = [asyncio.ensure_future(w.run()) for w in a_ways]
        try:
            first = await ping(0.0)  # A's own handshake
            alone = await ping(1.0)
            await at(2.0)
            b_ways = shaper.join(b_page, b_out, b_back, b_server)  # type: ignore[arg-type]
            tasks += [asyncio.ensure_future(w.run()) for w in b_ways]
            b_page.feed_data(b"GET")
            during = await ping(2.01)
            await until(lambda: b_server.got)
            return first, alone, during, b_server.got[0][0] - 2.0
        finally:
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    loop = VirtualLoop()
    try:
        first, alone, during, b_first = loop.run_until_complete(asyncio.wait_for(main(), WAIT))
    finally:
        loop.close()
    assert first == pytest.approx(2 * p.delay + 2 * way, abs=1e-6)  # A's handshake, then there and back
    assert alone == pytest.approx(2 * way, abs=1e-6)
    assert b_first == pytest.approx(2 * p.delay + p.delay + 3 * 8 / 1e6, abs=1e-6)
    assert during == pytest.approx(2 * way, abs=1e-6)


def close_test(closer: str) -> tuple[bytes, bytes]:
    """A connection through the shaper closed by `closer` ("client" or "server") after a
    greeting each way: what the other side read to its end (within WAIT s)."""
    seen: dict[str, bytes] = {}

    async def server_side(reader, writer):
        writer.write(b"hello from the server")
        await writer.drain()
        if closer == "server":
            writer.close()
            return
        seen["server"] = await asyncio.wait_for(reader.read(-1), WAIT)
        writer.close()

    async def client(reader, writer):
        writer.write(b"hello from the client")
        await writer.drain()
        if closer == "client":
            await asyncio.wait_for(reader.readexactly(21), WAIT)
            writer.close()
            for _ in range(int(WAIT * 10)):
                if "server" in seen:
                    break
                await asyncio.sleep(0.1)
        else:
            seen["client"] = await asyncio.wait_for(reader.read(-1), WAIT)
        return seen

    got = through(server_side, JITTERY, client)
    return got.get("server", b"?"), got.get("client", b"?")


def test_a_client_that_closes_closes_the_servers_side():
    """The server reads the client's bytes, then its end (read(-1) returns)."""
    server_read, _ = close_test("client")
    assert server_read == b"hello from the client"


def test_a_server_that_closes_closes_the_clients_side():
    client_read, = close_test("server")[1:]
    assert client_read == b"hello from the server"


def test_a_half_close_still_gets_its_answer():
    """A client that sends, then shuts its writing side (a half-close), gets the answer
    the server sends after reading that end."""
    async def answer(reader, writer):
        asked = await reader.read(-1)
        writer.write(b"answer to " + asked)
        await writer.drain()
        writer.close()

    async def client(reader, writer):
        writer.write(b"question")
        writer.write_eof()
        return await asyncio.wait_for(reader.read(-1), WAIT)

    assert through(answer, JITTERY, client) == b"answer to question"


def test_a_server_that_is_not_there_closes_the_client():
    async def main():
        server, shaper = await started(echo, JITTERY)
        server.close()  # nothing listens on the target port any more
        await server.wait_closed()
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", shaper.port)
            got = await asyncio.wait_for(reader.read(-1), WAIT)
            writer.close()
            return got
        finally:
            await shaper.stop()

    assert run(main()) == b""


@pytest.mark.parametrize("argv, says", [
    (["--taps", "3", "--network", "5g"],
     "argument --network: no network profile '5g' (choose from wifi, 4g)"),
    (["--taps", "3", "--cpu-slowdown", "0"], "argument --cpu-slowdown: '0' must be a number from 1 to 20"),
    (["--join", "2", "--cpu-slowdown", "x"], "argument --cpu-slowdown: 'x' must be a number from 1 to 20"),
    (["--network", "wifi"], "--network and --cpu-slowdown go with --taps, --join, --scribble or --photo"),
])
def test_a_bad_network_option_is_one_line(argv, says, capsys):
    with pytest.raises(SystemExit) as stop:
        page_bench.main(argv, prog="python -m bench page")
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"python -m bench page: error: {says}")


@pytest.mark.parametrize("argv, says", [
    (["--to", "127.0.0.1:8025", "--network", "5g"], "no network profile '5g' (choose from wifi, 4g)"),
    (["--to", "nowhere"], "--to 'nowhere' must be HOST:PORT"),
    (["--to", "127.0.0.1:8025", "--port", "70000"], "--port 70000 must be from 0 to 65535"),
])
def test_the_proxys_own_bad_command_line_is_one_line(argv, says, capsys):
    from bench import shaper

    with pytest.raises(SystemExit) as stop:
        shaper.main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err
