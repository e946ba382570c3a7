"""A TCP proxy that makes loopback behave like a phone's link: each way a delay with jitter
and a bandwidth cap, the bytes of a connection kept in order (`python -m bench page --network`).

Chromium's own network emulation does not delay WebSocket frames, so the delay has to be
on the socket itself. The proxy listens on 127.0.0.1 (a free port) and forwards every
connection to the server, byte for byte; in between, each direction is a `Link`, shared by
all the connections (as a phone's radio is shared by its page's connections):

- a bandwidth cap: the link sends one piece at a time, each taking len * 8 / rate seconds
  (a serialization delay, no burst), so N bytes take at least N * 8 / rate seconds, however
  many connections carry them;
- then a one-way delay, `delay` plus a jitter drawn uniformly in [-jitter, +jitter] for
  each piece, but never earlier than the piece before it: jitter delays a piece, it never
  reorders the bytes of one TCP stream (nor did it on a real link: TCP hands them over in
  order);
- a new connection's first bytes wait one round trip more (the TCP handshake a real link
  makes before any data), on their own: they reach the link once it is done, and other
  connections' bytes cross it meanwhile;
- at most BUFFER bytes waiting on a link: past them the proxy stops reading, so the sender
  meets the link's pace through TCP's own backpressure, as over a slow real link.

Closing: an end-of-file from one side reaches the other after the bytes before it (a
half-close, passed on as one); once both ways ended, or either side reset or failed,
both connections are closed.

Used as `Shaper` on a running asyncio loop, or `ShaperThread` (its own loop on a thread)
beside synchronous code such as Playwright's.

python -m bench shaper --to 127.0.0.1:8025 [--port 8026] [--network 4g]
"""

from __future__ import annotations

import asyncio
import random
import threading
from collections import deque
from dataclasses import dataclass

PIECE = 4096  # bytes: what the link sends at a time (a read is cut into pieces this big)
BUFFER = 256 * 1024  # bytes waiting on one link before the proxy stops reading


@dataclass(frozen=True)
class Profile:
    """A link, the same each way but for its rate. Delays are one way, in seconds: a round
    trip is twice `delay`, give or take twice `jitter`."""

    name: str
    delay: float  # s, one way
    jitter: float  # s, one way: each piece's delay is delay +- up to this (uniform)
    down_bps: float  # bits a second, server to page
    up_bps: float  # bits a second, page to server
    about: str = ""

    def describe(self) -> str:
        return (f"{self.name}: {2e3 * self.delay:g} ms round trip +- {2e3 * self.jitter:g} ms, "
                f"{self.down_bps / 1e6:g} Mbit/s down, {self.up_bps / 1e6:g} Mbit/s up")


PROFILES = {
    "wifi": Profile("wifi", 0.010, 0.0025, 30e6, 30e6, "a phone on a good home Wi-Fi"),
    "4g": Profile("4g", 0.030, 0.0075, 9e6, 1.5e6, "a phone on a fair 4G (LTE) signal"),
}


def profile(name: str) -> Profile:
    """The profile called `name`; ValueError, in one line, naming the choices, if none is."""
    try:
        return PROFILES[name]
    except KeyError:
        raise ValueError(f"no network profile {name!r} (choose from "
                         + ", ".join(PROFILES) + ")") from None


class Link:
    """One direction of the link, shared by every connection over it (as a phone's radio
    is by the page's connections): when each piece given to it reaches the far end."""

    def __init__(self, delay: float, jitter: float, bps: float, rng: random.Random):
        self.delay, self.jitter, self.bps, self.rng = delay, jitter, bps, rng
        self.free = 0.0  # when the link has sent everything given to it so far

    def arrives(self, size: int, now: float) -> float:
        """A piece of `size` bytes handed to the link at `now`: when it reaches the far end
        (the caller keeps its own connection's pieces in order)."""
        start = max(now, self.free)
        self.free = start + size * 8 / self.bps
        return self.free + self.delay + self.rng.uniform(-self.jitter, self.jitter)


class _Pipe:
    """Bytes read from one side, held until the link says they are due, written to the other."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter, link: Link,
                 hold_until: float = 0.0):
        self.reader, self.writer, self.link = reader, writer, link
        self.pieces: deque[tuple[float, bytes | None]] = deque()  # (due, bytes; None: EOF)
        self.waiting = 0  # bytes on the link
        self.arrived = asyncio.Event()
        self.room = asyncio.Event()
        self.hold_until = hold_until  # nothing leaves before this (the handshake)
        self.last = 0.0  # when the last piece read is due
        self.bytes = 0

    def due(self, size: int, now: float) -> float:
        """When a piece read at `now` is due: as the link has it, but never before the
        piece ahead of it (jitter never reorders a stream)."""
        self.last = max(self.link.arrives(size, now), self.last)
        return self.last

    async def read(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            data = await self.reader.read(65536)
            held = self.hold_until - loop.time()
            if held > 0:
                # The handshake: the bytes reach the link once it is done. Handed to it
                # now, due then, they would book the shared link until then, and every
                # other connection's bytes would wait behind this one's handshake.
                await asyncio.sleep(held)
            now = loop.time()
            if not data:
                self.pieces.append((max(self.last, now + self.link.delay), None))
                self.arrived.set()
                return
            for k in range(0, len(data), PIECE):
                piece = data[k:k + PIECE]
                self.pieces.append((self.due(len(piece), now), piece))
            self.waiting += len(data)
            self.arrived.set()
            while self.waiting > BUFFER:
                self.room.clear()
                await self.room.wait()

    async def write(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            while not self.pieces:
                self.arrived.clear()
                await self.arrived.wait()
            wait = self.pieces[0][0] - loop.time()
            if wait > 0:
                await asyncio.sleep(wait)
            now, batch = loop.time(), []
            while self.pieces and self.pieces[0][0] <= now and self.pieces[0][1] is not None:
                batch.append(self.pieces.popleft()[1])
            if batch:
                data = b"".join(batch)  # type: ignore[arg-type]
                self.writer.write(data)
                await self.writer.drain()
                self.bytes += len(data)
                self.waiting -= len(data)
                self.room.set()
            elif self.pieces and self.pieces[0][1] is None and self.pieces[0][0] <= now:
                if self.writer.can_write_eof():
                    self.writer.write_eof()
                return

    async def run(self) -> None:
        """Until the end-of-file is passed on; raises what the reading or the writing met."""
        ways = {asyncio.ensure_future(self.read()), asyncio.ensure_future(self.write())}
        try:
            done, _ = await asyncio.wait(ways, return_when=asyncio.FIRST_EXCEPTION)
            for way in done:
                if way.exception() is not None:
                    raise way.exception()  # type: ignore[misc]
        finally:
            for way in ways:
                way.cancel()


class Shaper:
    """The proxy: listens on `host`:`port` (0: a free one; `self.port` once started) and
    shapes every connection to `target` (host, port) with `profile`."""

    def __init__(self, target: tuple[str, int], profile: Profile, host: str = "127.0.0.1",
                 port: int = 0, seed: int = 0, handshake: bool = True):
        self.target, self.profile, self.host, self.port = target, profile, host, port
        rng = random.Random(seed)
        self.up = Link(profile.delay, profile.jitter, profile.up_bps, rng)
        self.down = Link(profile.delay, profile.jitter, profile.down_bps, rng)
        self.handshake = handshake
        self.server: asyncio.Server | None = None
        self.connections: set[asyncio.Task] = set()
        self.pipes: list[tuple[_Pipe, _Pipe]] = []  # (up, down) of every connection so far

    @property
    def up_bytes(self) -> int:
        """Bytes forwarded from the page's side to the server's so far, all connections."""
        return sum(up.bytes for up, _ in self.pipes)

    @property
    def down_bytes(self) -> int:
        return sum(down.bytes for _, down in self.pipes)

    async def start(self) -> Shaper:
        self.server = await asyncio.start_server(self._connection, self.host, self.port)
        self.port = self.server.sockets[0].getsockname()[1]
        return self

    async def stop(self) -> None:
        if self.server is not None:
            self.server.close()
        for task in list(self.connections):
            task.cancel()
        if self.connections:
            await asyncio.gather(*self.connections, return_exceptions=True)
        if self.server is not None:
            await self.server.wait_closed()

    def join(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter,
             far_reader: asyncio.StreamReader, far_writer: asyncio.StreamWriter) -> tuple[_Pipe, _Pipe]:
        """A new connection's two ways over the shared links, (up, down): the page's side
        (`reader`, `writer`) and the server's (`far_...`). Each way's first bytes wait one
        round trip from now (the TCP handshake) when `handshake`, on their own: the link
        carries other connections' bytes meanwhile."""
        hold = asyncio.get_running_loop().time() + (2 * self.profile.delay if self.handshake else 0.0)
        up = _Pipe(reader, far_writer, self.up, hold)
        down = _Pipe(far_reader, writer, self.down, hold)
        self.pipes.append((up, down))
        return up, down

    async def _connection(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        assert task is not None
        self.connections.add(task)
        try:
            try:
                far_reader, far_writer = await asyncio.open_connection(*self.target)
            except OSError:
                writer.close()
                return
            up, down = self.join(reader, writer, far_reader, far_writer)
            ways = [asyncio.ensure_future(up.run()), asyncio.ensure_future(down.run())]
            try:
                # Both ways to their end; a reset (or any failure) on one ends both.
                done, pending = await asyncio.wait(ways, return_when=asyncio.FIRST_EXCEPTION)
                for task_ in pending:
                    task_.cancel()
                await asyncio.gather(*ways, return_exceptions=True)
            finally:
                for task_ in ways:
                    task_.cancel()
                for w in (far_writer, writer):
                    w.close()
        except asyncio.CancelledError:
            # stop(): end quietly (asyncio's stream server asks a cancelled handler for
            # its exception, which raises, and logs it as an error in Python 3.11).
            pass
        finally:
            self.connections.discard(task)
            writer.close()


class ShaperThread:
    """A Shaper on an event loop of its own, on a thread: for synchronous callers. Use as a
    context manager; `port` is where it listens."""

    def __init__(self, target: tuple[str, int], profile: Profile, seed: int = 0):
        self.loop = asyncio.new_event_loop()
        self.shaper = Shaper(target, profile, seed=seed)
        self.thread = threading.Thread(target=self.loop.run_forever, name="shaper", daemon=True)

    def __enter__(self) -> ShaperThread:
        self.thread.start()
        asyncio.run_coroutine_threadsafe(self.shaper.start(), self.loop).result(30)
        return self

    @property
    def port(self) -> int:
        return self.shaper.port

    def __exit__(self, *exc) -> None:
        asyncio.run_coroutine_threadsafe(self.shaper.stop(), self.loop).result(30)
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(30)
        self.loop.close()


def main(argv: list[str] | None = None, prog: str = "python -m bench shaper") -> int:
    from app.bench.options import Parser

    p = Parser(prog=prog,
               description="Forward 127.0.0.1:PORT to a server through a phone-like link.")
    p.add_argument("--to", required=True, metavar="HOST:PORT", help="the server, e.g. 127.0.0.1:8025")
    p.add_argument("--port", type=int, default=0, help="port to listen on (default: a free one)")
    p.add_argument("--network", default="wifi", metavar="PROFILE",
                   help="the link: " + "; ".join(x.describe() for x in PROFILES.values()))
    args = p.parse_args(argv)
    try:
        chosen = profile(args.network)
    except ValueError as err:
        p.error(str(err))
    host, _, port = args.to.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        p.error(f"--to {args.to!r} must be HOST:PORT (a port from 1 to 65535)")
    if not 0 <= args.port < 65536:
        p.error(f"--port {args.port} must be from 0 to 65535")

    async def serve() -> None:
        shaper = await Shaper((host, int(port)), chosen, port=args.port).start()
        print(f"shaper: http://127.0.0.1:{shaper.port}/ -> {args.to} ({chosen.describe()}); "
              "Ctrl-C ends it", flush=True)
        await asyncio.Event().wait()

    try:
        asyncio.run(serve())
    except KeyboardInterrupt:
        return 130
    except OSError as err:
        print(f"shaper: error: {err}")
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
