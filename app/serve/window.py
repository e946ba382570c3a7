"""`frost serve --window`: the desktop window on the same frost as the pages. The window
owns the main thread, the simulation thread and the session file, as it does alone; the
server runs its asyncio loop on a thread of its own, and its feed reads the thread's
snapshots beside the window (`SimThread.subscribe`)."""

from __future__ import annotations

import asyncio
import logging
import threading

from app.serve.feed import Feed
from app.serve.listen import Https, listen, listen_problem, say_error
from app.serve.server import make_app

log = logging.getLogger("app.serve")


class Background:
    """The server's loop on a thread of its own."""

    def __init__(self, host: str, port: int, token: str | None, https: Https | None = None,
                 ca_der: bytes = b"", photo_dir=None):
        self.host, self.port, self.token, self.photo_dir = host, port, token, photo_dir
        self.https, self.ca_der = https, ca_der
        self._loop: asyncio.AbstractEventLoop | None = None
        self._ended: asyncio.Event | None = None
        self._ready = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self, feed: Feed) -> None:
        """Serve `feed`; RuntimeError if it cannot listen."""
        self._thread = threading.Thread(target=lambda: asyncio.run(self._main(feed)),
                                        name="frost-serve", daemon=True)
        self._thread.start()
        self._ready.wait(30)
        if self._loop is None:
            raise RuntimeError(f"frost serve cannot listen on {self.host}:{self.port}")

    async def _main(self, feed: Feed) -> None:
        runner = await listen(make_app(feed, self.token, None, ca_der=self.ca_der,
                                       photo_dir=self.photo_dir), self.host,
                              self.port, self.token, self.https)
        if runner is None:
            self._ready.set()
            return
        self._loop, self._ended = asyncio.get_running_loop(), asyncio.Event()
        self._ready.set()
        await self._ended.wait()
        await runner.cleanup()

    def stop(self) -> None:
        if self._loop is not None and self._ended is not None and self._thread is not None:
            self._loop.call_soon_threadsafe(self._ended.set)
            self._thread.join(10)


def serve_with_window(args, params, token: str | None, https: Https | None = None,
                      ca_der: bytes = b"") -> int:
    """The window (its exit status) with the server beside it until it closes."""
    from app.backdrops import view_from
    from app.window import frost_window

    for port in [args.port] + ([https.port] if https else []):
        problem = listen_problem(args.host, port)  # before a window opens for nothing
        if problem:
            say_error(problem)
            return 2
    from pathlib import Path

    from app.photos import FOLDER
    server = Background(args.host, args.port, token, https, ca_der,
                        Path(args.session_dir) / FOLDER)  # (the window's session folder)

    def attach(window) -> None:
        feed = Feed(params, args.seed, melt_radius=args.melt_radius, backdrop=args.background,
                    thread=window.thread, preset=args.preset or "")
        feed.weather = window.weather  # (the window's, which it stops)
        server.start(feed)

    args.view = view_from(args)
    try:
        return frost_window.run(args, params, attach)
    finally:
        server.stop()


