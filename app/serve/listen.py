"""The server's app listening on a host and port, and the URL to open said (with the token
and its QR code for a phone's camera)."""

from __future__ import annotations

import socket
import sys

from aiohttp import web

from app.serve import guard
from app.serve.appkeys import FILES


async def listen(app: web.Application, host: str, port: int,
                 token: str | None) -> web.AppRunner | None:
    """The app served on host:port and its URL printed; None (the error said) if it cannot
    listen there."""
    runner = guard.GuardedRunner(app, handle_signals=False, access_log=None)
    await runner.setup()
    try:
        site = web.TCPSite(runner, host, port)
        await site.start()
    except OSError as err:
        app[FILES].folder = None  # nothing was served: no word on a session
        await runner.cleanup()
        print(f"frost: error: {listen_problem(host, port, err)}", file=sys.stderr)
        return None
    announce(host, runner.addresses[0][1] if runner.addresses else port, token)
    return runner


def listen_problem(host: str, port: int, err: OSError | None = None) -> str | None:
    """Why host:port cannot be listened on (None: it can now), from `err` if given, else
    by binding a socket there and closing it."""
    if err is None:
        try:
            family = socket.AF_INET6 if ":" in host else socket.AF_INET
            socket.create_server((host, port), family=family).close()
            return None
        except (OSError, OverflowError) as error:
            err = error if isinstance(error, OSError) else OSError(str(error))
    return f"cannot listen on {url_host(host)}:{port}: {err.strerror or err}"


def lan_address() -> str:
    """This machine's address on its network (where a phone can reach it); no packet is
    sent (a UDP socket's connect only picks the route)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("10.254.254.254", 1))
            return s.getsockname()[0]
        except OSError:
            return socket.gethostname()


def url_host(host: str) -> str:
    """A host as a URL writes it: an IPv6 address in brackets."""
    return f"[{host}]" if ":" in host else host


def announce(host: str, port: int, token: str | None) -> None:
    """Print the URL to open (with the token, and its QR code for a phone's camera)."""
    if token is None:
        print(f"frost serve: open http://{url_host(host)}:{port}/ (Ctrl-C ends it)", flush=True)
        return
    shown = lan_address() if host in ("0.0.0.0", "::", "") else host
    url = f"http://{url_host(shown)}:{port}/?token={token}"
    print(f"frost serve: open {url} on a phone of this network (Ctrl-C ends it)", flush=True)
    try:
        import segno
        segno.make(url, error="m").terminal(compact=True)
    except ImportError:
        print("frost serve: (no QR code: the segno package is missing)")
    sys.stdout.flush()
