"""`frost serve` as a user starts it: a subprocess, the URLs it prints read from its
output, stopped as Ctrl-C stops it. Every benchmark and every test that starts the command
starts it here (the tests through tests/support/serve.py): the checkout's, outside the
wheel, where both import it from."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

# What runs the checkout's `frost`; a test may name another (the installed one, the
# Windows-like launcher: tests/windows_like.py).
FROST = (sys.executable, "-m", "app")


class ServeProcess:
    """`frost serve *args` in `cwd`, its output read until it said its page's address (and
    its HTTPS one, with `https`). What it printed: `lines`; the page's address: `url`
    (`port`, `token`: None without one; `local`: the address a page on this machine
    opens, as a LAN address names another interface); the HTTPS one: `https`,
    `https_port` (None without). With `stderr_apart` its stderr is kept apart, for the
    test to read from `proc.stderr`; `env` replaces the environment's variables it names,
    and a value of None removes one. RuntimeError, with what it printed, if it did not
    start within `timeout` s."""

    def __init__(self, *args: str, cwd: Path | str | None = None, env: dict | None = None,
                 https: bool = False, frost=FROST, stderr_apart: bool = False,
                 timeout: float = 60):
        env = {**os.environ, "PYTHONUNBUFFERED": "1", **(env or {})}
        self.proc = subprocess.Popen(
            [*frost, "serve", *args], cwd=cwd, text=True, stdout=subprocess.PIPE,
            env={k: v for k, v in env.items() if v is not None},
            stderr=subprocess.PIPE if stderr_apart else subprocess.STDOUT)
        self.lines: list[str] = []
        self._reader: threading.Thread | None = None
        said = self._read(https, time.monotonic() + timeout)
        if "url" not in said or https and "https" not in said:
            self.stop()
            raise RuntimeError("frost serve did not start:\n" + "".join(self.lines))
        self.url: str = said["url"]
        self.https: str | None = said.get("https")
        self.port = port_of(self.url)
        token = re.search(r"token=([\w-]+)", self.url)
        self.token = token.group(1) if token else None
        self.local = f"http://127.0.0.1:{self.port}/" + (f"?token={self.token}" if self.token else "")
        self.https_port = port_of(self.https) if self.https else None

    def _read(self, https: bool, deadline: float) -> dict[str, str]:
        """Its lines until it said its addresses (`url`, `https`: what it said), it ended,
        or the deadline passed (a readline that blocks past it ends with the process,
        stopped by the caller)."""
        said: dict[str, str] = {}
        while time.monotonic() < deadline and not ("url" in said and ("https" in said or not https)):
            line = self.proc.stdout.readline()  # type: ignore[union-attr]
            if not line:
                break
            self.lines.append(line)
            if found := re.search(r"open (http://\S+)", line):
                said["url"] = found.group(1)
            if found := re.search(r"as an app: (https://\S+)", line):
                said["https"] = found.group(1)
        return said

    def drain(self) -> ServeProcess:
        """Read its output on, into `lines`, in a thread of its own: the log of a long run
        never fills the pipe (which would stop the server). `stop` returns it all."""
        self._reader = threading.Thread(
            target=lambda: self.lines.extend(self.proc.stdout or ()), daemon=True)
        self._reader.start()
        return self

    def stop(self) -> str:
        """Stop as Ctrl-C does; everything it printed. (Read through the file that read its
        first lines: what that read ahead is in its buffer, which `communicate`, reading
        the pipe itself, would lose.)"""
        if self._reader is None:
            self.drain()
            if self.proc.stderr is not None:  # (kept apart: read, so that it never blocks the end)
                threading.Thread(target=self.proc.stderr.read, daemon=True).start()
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        self._wait(self.proc.wait)
        self._reader.join(30)  # type: ignore[union-attr]
        return "".join(self.lines)

    def _wait(self, wait):
        """`wait(timeout=30)`, or the process killed and waited for if it is still there."""
        try:
            return wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return wait()


def port_of(url: str) -> int:
    return int(re.search(r":(\d+)/", url).group(1))  # type: ignore[union-attr]
