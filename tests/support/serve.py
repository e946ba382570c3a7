"""The tests' `frost serve`s: on a free port growing fern (the phone tests'), on the LAN
with its token and authority, or writing its session; each a ServeProcess
(bench/serve_process.py, which the benchmarks start theirs with too)."""

from __future__ import annotations

import sys
from pathlib import Path

from bench.serve_process import FROST, ServeProcess


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
