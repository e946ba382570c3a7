"""`frost serve`, the command: the server alone until a signal (or --max-seconds), or
beside the desktop window (--window). Here, apart from the server and the window, because
it starts either: the server imports nothing of the window, the window the server."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import signal
import sys
import time

from aiohttp import web

from app.lockscreen import clock_from
from app.serve import trust
from app.serve.appkeys import FEED
from app.serve.feed import Feed
from app.serve.listen import Https, lan_address, listen
from app.serve.server import make_app
from app.serve.window import serve_with_window

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
        print(f"frost: error: {err}", file=sys.stderr)
        return 2
    if args.window:
        return serve_with_window(args, params, token, https, ca_der)
    feed = Feed(params, args.seed, args.touch, args.melt_radius, args.background,
                preset=args.preset or "", clock=clock_from(getattr(args, "clock_start", None)))
    app = make_app(feed, token, args.session_dir, ca_der=ca_der)
    status = asyncio.run(_serve(app, args.host, args.port, token, args.max_seconds, https))
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
    try:
        return await _until_ended(app[FEED], max_seconds)
    finally:  # (also when Ctrl-C cancels this where the loop takes no signal handlers)
        await runner.cleanup()


async def _until_ended(feed: Feed, max_seconds: float | None) -> int:
    """Wait for a signal (128 + its number, as the window exits), the deadline (0) or the
    simulation thread's death (1)."""
    loop, ended = asyncio.get_running_loop(), asyncio.Event()
    got: list[int] = []

    def on_signal(signum: int) -> None:
        got.append(signum)
        ended.set()

    for sig in ending_signals():
        # Windows' event loops take no signal handlers: there Ctrl-C cancels the main task
        # (asyncio.run; from Python 3.11) or raises KeyboardInterrupt in the loop (3.10),
        # and `_serve` cleans up (the session written) either way.
        with contextlib.suppress(NotImplementedError, RuntimeError):
            loop.add_signal_handler(sig, on_signal, sig)
    deadline = time.monotonic() + (max_seconds if max_seconds is not None else float("inf"))
    while not ended.is_set() and feed.error is None and time.monotonic() < deadline:
        with contextlib.suppress(asyncio.TimeoutError):
            await asyncio.wait_for(ended.wait(), 0.25)
    if got:
        log.info("serve: %s received: closing", signal.Signals(got[0]).name)
        return 128 + got[0]
    return 1 if feed.error else 0
