"""`frost serve`, the command: the server alone until a signal (or --max-seconds), or
beside the desktop window (--window). Here, apart from the server and the window, because
it starts either: the server imports nothing of the window, the window the server."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import signal
import time

from aiohttp import web

from app.lockscreen import clock_from
from app.serve import trust
from app.serve.appkeys import FEED
from app.serve.feed import Feed
from app.serve.listen import Https, lan_address, listen, say_error
from app.serve.server import close_pages, finish, make_app
from app.serve.window import serve_with_window
from app.weather.feed import feed_for

log = logging.getLogger("app.serve")

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def ending_signals() -> list[signal.Signals]:
    """The signals that end the server (as the window), those this platform has."""
    return [s for s in (getattr(signal, n, None) for n in ("SIGINT", "SIGTERM", "SIGHUP")) if s]


def serve(args, params) -> int:
    """`frost serve`: serve until Ctrl-C (or a signal, or --max-seconds); the exit status."""
    try:
        token, https, ca_der = plan(args)
    except trust.TrustError as err:
        say_error(str(err))
        return 2
    if args.window:
        return serve_with_window(args, params, token, https, ca_der)
    feed = Feed(params, args.seed, args.touch, args.melt_radius, args.background,
                preset=args.preset or "", clock=clock_from(getattr(args, "clock_start", None)))
    app = make_app(feed, token, args.session_dir, ca_der=ca_der)
    def say(line: str) -> None:  # a weather line: to the log, and to every page's status
        log.info("%s", line)
        feed.notice_soon(line)

    feed.weather = feed_for(args, feed.thread.show_weather, say)  # (beside the loop)
    try:
        status = asyncio.run(_serve(app, args.host, args.port, token, args.max_seconds, https))
    finally:
        if feed.weather is not None:
            feed.weather.stop()
    if status == 128 + signal.SIGINT:  # closed and saved: the command line says so, as
        raise KeyboardInterrupt        # it does for the window, and exits 130
    return status


def plan(args) -> tuple[str | None, Https | None, bytes]:
    """What the command line asks for: the token (None on loopback), HTTPS (None: HTTP
    alone) and the local authority's public certificate to serve (b"": none); TrustError
    (one line) where it cannot be had.

    Off loopback HTTPS is served unless --no-https; on loopback only when asked (--cert or
    --https-port), as a browser takes http://127.0.0.1 for a secure context already. The
    token and the authority are kept in the user's config folder (trust.config_dir)."""
    lan = trust.canonical(args.host) not in LOOPBACK
    if (args.cert is None) != (args.key is None):
        raise trust.TrustError("--cert and --key go together: the certificate and its "
                               "private key")
    if args.no_https and (args.cert is not None or args.https_port is not None):
        raise trust.TrustError("--no-https serves HTTP alone: it takes no --cert, --key or "
                               "--https-port")
    folder = trust.config_dir()
    token = trust.kept_token(folder, args.new_token) if lan else None
    if args.new_token and not lan:
        trust.kept_token(folder, True)  # replaced for the next LAN run; loopback needs none
    if args.no_https or not (lan or args.cert is not None or args.https_port is not None):
        return token, None, b""
    port = args.https_port
    if port is None:
        port = 0 if args.port == 0 else args.port + 1
        if port > 65535:
            raise trust.TrustError(f"--https-port: --port {args.port} leaves no next port "
                                   "for HTTPS: give one")
    if port != 0 and port == args.port:
        raise trust.TrustError(f"--https-port {port} is --port too: give two ports")
    if args.cert is not None:
        issued = trust.users_own(args.cert, args.key)
    else:
        issued = trust.local_certificate(
            folder, trust.machine_names(args.host, lan_address() if lan else None))
    return token, Https(port, issued.context()), issued.ca_der or b""


async def _serve(app: web.Application, host: str, port: int, token: str | None,
                 max_seconds: float | None, https: Https | None = None) -> int:
    runner = await listen(app, host, port, token, https)
    if runner is None:
        return 2
    signals, ended = Signals(asyncio.get_running_loop()), False
    try:
        status = await _until_ended(app[FEED], max_seconds, signals)
        finish(app)  # the session written, before the pages and the open requests end
        await _end_requests(app, runner, signals)
        ended = True
        return status
    finally:
        signals.restore()
        if not ended:  # (cancelled, or an error in between)
            await runner.cleanup()


async def _end_requests(app: web.Application, runner: web.AppRunner,
                        signals: Signals) -> None:
    """The server closed: the pages' sockets (each page's input until it saw the close
    counted: server.close_pages), then the requests still open given at most
    guard.SHUTDOWN_S to end (a photo half sent would hold the exit as long as it likes); a
    second signal meanwhile ends the wait at once (the session is written)."""
    for step in (lambda: close_pages(app), runner.cleanup):
        task = asyncio.ensure_future(step())
        while not task.done():
            if len(signals.got) > 1:
                log.info("serve: %s again: exiting now", signal.Signals(signals.got[-1]).name)
                task.cancel()
                return
            await asyncio.wait([task], timeout=0.1)


class Signals:
    """The signals that end the server, caught while it serves: by the loop where it takes
    signal handlers; else (Windows' loops) by `signal.signal`, whose handler hands the
    signal to the loop. `got` holds them, in order; `ended` is set at the first."""

    def __init__(self, loop: asyncio.AbstractEventLoop):
        self.loop, self.ended = loop, asyncio.Event()
        self.got: list[int] = []
        self._before: dict[signal.Signals, object] = {}
        for sig in ending_signals():
            try:
                loop.add_signal_handler(sig, self.on_signal, sig)
            except (NotImplementedError, RuntimeError):
                self._before[sig] = signal.signal(sig, self._handler)

    def on_signal(self, signum: int) -> None:
        self.got.append(signum)
        self.ended.set()

    def _handler(self, signum: int, _frame) -> None:
        self.loop.call_soon_threadsafe(self.on_signal, signum)

    def restore(self) -> None:
        """The handlers as they were before."""
        for sig in ending_signals():
            if sig in self._before:
                signal.signal(sig, self._before.pop(sig))  # type: ignore[arg-type]
            else:
                with contextlib.suppress(NotImplementedError, RuntimeError):
                    self.loop.remove_signal_handler(sig)


async def _until_ended(feed: Feed, max_seconds: float | None, signals: Signals) -> int:
    """Wait for a signal (128 + its number, as the window exits), the deadline (0) or the
    simulation thread's death (1)."""
    deadline = time.monotonic() + (max_seconds if max_seconds is not None else float("inf"))
    while not signals.ended.is_set() and feed.error is None and time.monotonic() < deadline:
        with contextlib.suppress(asyncio.TimeoutError):
            await asyncio.wait_for(signals.ended.wait(), 0.25)
    if signals.got:
        log.info("serve: %s received: closing", signal.Signals(signals.got[0]).name)
        return 128 + signals.got[0]
    return 1 if feed.error else 0
