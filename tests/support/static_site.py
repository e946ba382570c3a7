"""A plain static web server on loopback, in a thread (the standard library's http.server:
files, and nothing of frost's), for the static site of `frost web` (tests/test_site_e2e.py,
tests/test_webkit_e2e.py): the site built into ROOT/SUB, ROOT served, so that the site lies
under /SUB/ as GitHub Pages serves a repository's."""

from __future__ import annotations

import functools
import threading
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

SUB = "frost"  # the site's sub-path: https://USER.github.io/frost/ as GitHub Pages serves a repository


class Quiet(SimpleHTTPRequestHandler):
    """A plain static server's files, kept by a browser for 10 minutes as GitHub Pages
    lets it (Cache-Control: max-age=600): a new build must come past that."""

    def end_headers(self) -> None:
        self.send_header("Cache-Control", "max-age=600")
        super().end_headers()

    def log_message(self, *args) -> None:  # (the test's output is the test's)
        pass


class Server(ThreadingHTTPServer):
    def handle_error(self, request, client_address) -> None:
        pass  # (a page that went while a file was sent: no traceback)


class StaticServer:
    """A plain static web server of `root` on loopback (in a thread): files, and nothing
    of ours. `stop()` and `start()` again on the same port; `paths` lists what was asked."""

    def __init__(self, root: Path):
        self.root, self.port, self.http = root, 0, None
        self.paths: list[str] = []
        self.start()

    def start(self) -> None:
        paths = self.paths

        class Handler(Quiet):
            def do_GET(self):  # noqa: N802 (http.server's name)
                paths.append(self.path)
                super().do_GET()

        self.http = Server(("127.0.0.1", self.port),
                                        functools.partial(Handler, directory=str(self.root)))
        self.port = self.http.server_address[1]
        threading.Thread(target=self.http.serve_forever, daemon=True).start()

    def stop(self) -> None:
        self.http.shutdown()
        self.http.server_close()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}/{SUB}/"
