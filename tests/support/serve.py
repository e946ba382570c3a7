"""`frost serve` as a user starts it: a subprocess, the URLs it prints read from its
output, stopped as Ctrl-C stops it. Every test that starts the command starts it here."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
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
    and a value of None removes one."""

    def __init__(self, *args: str, cwd: Path | None = None, env: dict | None = None,
                 https: bool = False, frost=FROST, stderr_apart: bool = False,
                 timeout: float = 60):
        env = {**os.environ, "PYTHONUNBUFFERED": "1", **(env or {})}
        self.proc = subprocess.Popen(
            [*frost, "serve", *args], cwd=cwd, text=True, stdout=subprocess.PIPE,
            env={k: v for k, v in env.items() if v is not None},
            stderr=subprocess.PIPE if stderr_apart else subprocess.STDOUT)
        self.lines: list[str] = []
        self.url = self.https = None
        self._read(https, time.monotonic() + timeout)
        if not self.url or https and not self.https:
            self.stop()
            raise AssertionError("frost serve did not start:\n" + "".join(self.lines))
        self.port = port_of(self.url)
        token = re.search(r"token=([\w-]+)", self.url)
        self.token = token.group(1) if token else None
        self.local = f"http://127.0.0.1:{self.port}/" + (f"?token={self.token}" if self.token else "")
        self.https_port = port_of(self.https) if self.https else None

    def _read(self, https: bool, deadline: float) -> None:
        """Its lines until it said its addresses, it ended, or the deadline passed (a
        readline that blocks past it ends with the process, stopped by the caller)."""
        while time.monotonic() < deadline and not (self.url and (self.https or not https)):
            line = self.proc.stdout.readline()  # type: ignore[union-attr]
            if not line:
                return
            self.lines.append(line)
            if found := re.search(r"open (http://\S+)", line):
                self.url = found.group(1)
            if found := re.search(r"as an app: (https://\S+)", line):
                self.https = found.group(1)

    def stop(self) -> str:
        """Stop as Ctrl-C does; everything it printed."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            rest, _ = self.proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rest, _ = self.proc.communicate()
        return "".join(self.lines) + (rest or "")


def port_of(url: str) -> int:
    return int(re.search(r":(\d+)/", url).group(1))  # type: ignore[union-attr]


def phone_serve(folder: Path, *args: str) -> ServeProcess:
    """`frost serve` on a free port (its own choice: --port 0), its sessions and files in
    `folder`, growing fern from seed 5 unless `args` say otherwise: the phone tests' server."""
    return ServeProcess("--port", "0", "--session-dir", str(folder), "--preset", "fern",
                        "--seed", "5", *args, cwd=folder)


def lan_serve(config: Path, *args: str, env: dict | None = None) -> ServeProcess:
    """`frost serve --host 0.0.0.0 --port 0` growing c-2, its config folder (its token, its
    authority) in `config`: its page's address and, unless --no-https, its HTTPS one."""
    from support import ROOT

    return ServeProcess("--host", "0.0.0.0", "--port", "0", "--preset", "c-2", *args, cwd=ROOT,
                        env={"XDG_CONFIG_HOME": str(config), **(env or {})},
                        https="--no-https" not in args)


def session_serve(folder: Path, frost=FROST[1:]) -> ServeProcess:
    """`frost serve` growing c-2 on a free port, writing its session in `folder`, its stderr
    kept apart (where it says why it stopped); its first line, the loopback page's address
    (`frost`: what runs it after the Python, e.g. the Windows-like launcher's file)."""
    s = ServeProcess("--port", "0", "--preset", "c-2", "--session-dir", str(folder),
                     frost=(sys.executable, *frost), stderr_apart=True)
    assert s.lines[0].startswith("frost serve: open http://127.0.0.1:"), s.lines
    return s
