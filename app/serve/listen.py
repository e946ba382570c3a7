"""The server's app listening on a host and port (and on a second port over HTTPS), and
the URLs to open said (with the token and their QR codes for a phone's camera)."""

from __future__ import annotations

import asyncio
import io
import re
import socket
import ssl
import sys
from dataclasses import dataclass
from urllib.parse import urlsplit

from aiohttp import web

from app.serve import guard, trust
from app.serve.appkeys import FILES, PORTS
from app.serve.trust import unspecified
from sim.io.files import one_line, why, write_atomic

HANDSHAKE_S = guard.HEAD_S  # s a TLS handshake may take (asyncio's own default: 60 s)


@dataclass
class Https:
    """HTTPS and WSS on a second port (0: any free one) with this TLS context."""
    port: int
    context: ssl.SSLContext


class TLSSite(web.TCPSite):
    """aiohttp's TCPSite whose TLS handshakes must end within HANDSHAKE_S: a connection
    that never finishes its handshake is under no guard until it does (guard.py sees a
    connection once TLS hands it over), and asyncio would hold it a minute. aiohttp's
    site takes no handshake timeout: its start is redone here with its own fields."""

    async def start(self) -> None:
        await web.BaseSite.start(self)  # registers the site with its runner
        server = self._runner.server
        assert server is not None
        self._server = await asyncio.get_running_loop().create_server(
            server, self._host, self._port, ssl=self._ssl_context, backlog=self._backlog,
            ssl_handshake_timeout=HANDSHAKE_S)


async def listen(app: web.Application, host: str, port: int, token: str | None,
                 https: Https | None = None) -> web.AppRunner | None:
    """The app served on host:port (and over HTTPS on host:https.port) and its URLs
    printed; None (the error said) if it cannot listen there."""
    runner = guard.GuardedRunner(app, handle_signals=False, access_log=None)
    await runner.setup()
    ports: list[int] = []
    sites = [(port, None)] + ([(https.port, https.context)] if https else [])
    try:
        for asked, context in sites:
            before = len(runner.addresses)
            site = TLSSite(runner, host, asked, ssl_context=context) if context \
                else web.TCPSite(runner, host, asked)
            await site.start()
            bound = runner.addresses[before:]
            ports.append(bound[0][1] if bound else asked)
    except OSError as err:
        app[FILES].folder = None  # nothing was served: no word on a session
        await runner.cleanup()
        say_error(listen_problem(host, asked, err) or "")
        return None
    app[PORTS].update(http=ports[0], https=ports[1] if https else None)
    announce(host, ports[0], token, ports[1] if https else None)
    return runner


def say_error(problem: str) -> None:
    """`frost serve`'s error: one line on stderr, naming the problem and, as every error of
    the command line does (docs/command-line.md), its help."""
    print(f"frost: error: {one_line(problem)} (see frost serve --help)", file=sys.stderr)


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


def announce(host: str, port: int, token: str | None, https_port: int | None = None) -> None:
    """Print the URLs to open (with the token, and their QR codes for a phone's camera):
    the HTTP one, then the HTTPS one where it is served. All in one write, so that no log
    line of another thread lands inside a QR code (which no camera could read then)."""
    said: list[str] = []
    if token is None:
        said.append(f"frost serve: open http://{url_host(host)}:{port}/ (Ctrl-C ends it)\n")
        if https_port is not None:
            said.append(f"frost serve: over HTTPS: https://{url_host(host)}:{https_port}/\n")
    else:
        shown = lan_address() if unspecified(host) else host
        url = f"http://{url_host(shown)}:{port}/?token={token}"
        said.append(f"frost serve: open {url} on a phone of this network (Ctrl-C ends it)\n")
        said.append(_qr(url, qr_name("page", url)))
        if https_port is not None:
            url = f"https://{url_host(shown)}:{https_port}/?token={token}"
            said.append(f"frost serve: as an app: {url} once the phone trusts this computer "
                        "(the page's menu: Make it an app)\n")
            said.append(_qr(url, qr_name("app", url)))
    _write("".join(said))


def _write(text: str) -> None:
    """`text` on stdout, whatever its encoding: a character it has no byte for (a config
    folder's path under a user's name in another script, on a cp1252 console) is written
    as its escape (\\u0436), the rest as it is, rather than the whole lost to an error."""
    encoding = getattr(sys.stdout, "encoding", None) or "ascii"
    try:
        text.encode(encoding)
    except UnicodeEncodeError:
        text = text.encode(encoding, "backslashreplace").decode(encoding)
    except LookupError:
        pass
    sys.stdout.write(text)
    sys.stdout.flush()


def qr_name(kind: str, url: str) -> str:
    """The name of the PNG of `url`'s QR code (`kind`: page, app), its host and port in it:
    servers that share a config folder (each on its own port) each write their own, e.g.
    qr-page-192.168.1.20-8025.png."""
    parts = urlsplit(url)
    host = re.sub(r"[^A-Za-z0-9.]+", "-", parts.hostname or "").strip("-.") or "host"
    return f"qr-{kind}-{host}-{parts.port}.png"


def _qr(url: str, name: str) -> str:
    """`url`'s QR code to draw in the console, where its encoding has the code's block
    characters; else (a redirected Windows console in cp1252, say) written as the PNG
    `name` in the user's config folder, beside the token it carries (a folder for the user
    alone), and a line saying where."""
    try:
        import segno
    except ImportError:
        return "frost serve: (no QR code: the segno package is missing)\n"
    code = segno.make(url, error="m")
    drawn = io.StringIO()
    code.terminal(out=drawn, compact=True)
    encoding = getattr(sys.stdout, "encoding", None) or "ascii"
    try:
        drawn.getvalue().encode(encoding)
    except (UnicodeEncodeError, LookupError):
        return f"frost serve: {_qr_file(code, name, encoding)}\n"
    return drawn.getvalue()


def _qr_file(code, name: str, encoding: str) -> str:
    """The QR `code` written as a PNG `name` in the config folder: a line saying where, or
    why it could not be written."""
    path = trust.config_dir() / name
    try:
        write_atomic(path, lambda f: code.save(f, kind="png", scale=8, border=4))
    except OSError as err:
        return f"(no QR code: the console ({encoding}) cannot show one, nor {why(err, path)})"
    return f"the console ({encoding}) cannot show the QR code: open the image {path}"
