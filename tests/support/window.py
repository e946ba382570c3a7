"""The window under Xvfb: a server of its own for a run, xdotool, a driver script's run
and its log."""

from __future__ import annotations

import contextlib
import json
import os
import re
import select
import subprocess
import sys
import time
from pathlib import Path

import pytest

from support import ROOT

SCREEN = "-screen 0 1280x1400x24"  # taller than the 1280 px phone


@contextlib.contextmanager
def display():
    """An Xvfb server of its own while the block runs; its DISPLAY (such as ":5").
    `-displayfd` makes the server pick a free display and say which once it accepts
    clients, so concurrent runs never share one and nothing waits on a guess (`xvfb-run -a`
    can race under load)."""
    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write), *SCREEN.split(), "-nolisten",
                               "tcp", "-noreset"], pass_fds=(write,), stderr=subprocess.DEVNULL)
    os.close(write)
    try:
        ready, _, _ = select.select([read], [], [], 60)
        number = os.read(read, 64).decode().strip() if ready else ""
        if not number:
            pytest.fail("Xvfb did not start within 60 s")
        yield f":{number}"
    finally:
        os.close(read)
        server.terminate()
        server.wait(10)


def xvfb(args: list, **kw) -> subprocess.CompletedProcess:
    """`args` run (captured) with DISPLAY on an Xvfb server of its own (`display`)."""
    with display() as number:
        env = {**os.environ, "DISPLAY": number}
        return subprocess.run(args, capture_output=True, text=True, env=env, **kw)


def xdo(*args: str) -> str:
    return subprocess.run(["xdotool", *args], check=True, capture_output=True, text=True,
                          timeout=30).stdout


def escape(wid: str) -> None:
    """Esc sent to the window `wid`: a key down, then a key up. The window may close at the
    down (Esc quits), before xdotool sends the up to it: X then answers BadWindow, which
    says the key arrived. Any other failure is raised."""
    done = subprocess.run(["xdotool", "key", "--window", wid, "Escape"], capture_output=True,
                          text=True, timeout=30)
    if done.returncode != 0 and "BadWindow" not in done.stderr:
        raise subprocess.CalledProcessError(done.returncode, done.args, done.stdout, done.stderr)


def window_id(timeout: float = 60, name: str = "^frost$") -> str:
    """The app's window titled `name` (waits up to `timeout` s until it is mapped)."""
    return subprocess.run(["xdotool", "search", "--sync", "--onlyvisible", "--name", name],
                          check=True, capture_output=True, text=True,
                          timeout=timeout).stdout.split()[0]


def finish(app: subprocess.Popen, out: Path, result: dict) -> None:
    """A driver's last step, whatever happened: the app ended, what it saw in result.json."""
    if app.poll() is None:
        app.kill()
    (out / "result.json").write_text(json.dumps(result), encoding="utf-8")


def played(script: str, out: Path, *args: str, timeout: float = 120) -> tuple[str, dict]:
    """Run the driver `script` (a test file run as a script) on an Xvfb server of its own
    with output folder `out`: the app's log and the driver's result."""
    xvfb([sys.executable, script, str(out), *args], cwd=ROOT, timeout=timeout)
    result = json.loads((out / "result.json").read_text(encoding="utf-8"))
    return (out / "app.log").read_text(encoding="utf-8"), result


def wait_for(log: Path, pattern: str, count: int = 1, timeout: float = 60.0) -> list[str]:
    """The first `count` matches of `pattern` in the log, waiting up to `timeout` s (a
    bound on a failure, however loaded the machine: never a claim on its speed)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        found = re.findall(pattern, log.read_text(encoding="utf-8"))
        if len(found) >= count:
            return found
        time.sleep(0.05)
    raise TimeoutError(f"{pattern!r} x{count} not in {log}")


# Mesa with a Mac's limits: OpenGL 4.1 core, GLSL 4.10, no ES 3 compatibility. A proxy for a
# Mac, not one (it still has functions newer than 4.1): docs/platforms.md says so.
MAC_LIMITS = {"MESA_GL_VERSION_OVERRIDE": "4.1", "MESA_GLSL_VERSION_OVERRIDE": "410",
              "MESA_EXTENSION_OVERRIDE": "-GL_ARB_ES3_compatibility"}
