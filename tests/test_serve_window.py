"""`frost serve --window` under Xvfb: a page's touch grows the frost the desktop window
shows, and the window's session file replays to what the page holds.

The test runs this file as a script on an Xvfb server of its own (test_window_e2e's way)."""

import asyncio
import json
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("window_tools")
ROOT = Path(__file__).resolve().parent.parent


def start_with_window(out: Path, preset: str, seconds: int) -> tuple[subprocess.Popen, str]:
    """`frost serve --window` (files in `out`, closing at `seconds`) and the URL it printed."""
    from bench.serve_process import ServeProcess

    served = ServeProcess("--window", "--port", "0", "--preset", preset, "--max-seconds",
                          str(seconds), "--session-dir", str(out), "--screenshot-dir", str(out),
                          cwd=ROOT, stderr_apart=True)
    return served.proc, served.url


def drive(out: Path) -> None:
    """Under Xvfb: start the command, be a page, then close the window with Esc (or it
    closes at --max-seconds, a bound on a failure)."""
    from support.page_model import CENTRE, PageModel, near, pause, read_until
    from support.window import escape, window_id

    app, url = start_with_window(out, "c-2", 120)
    page = PageModel()

    async def main():
        from aiohttp import ClientSession
        async with ClientSession() as http, http.ws_connect(url + "ws") as ws:
            await read_until(ws, page, lambda: page.snapshots >= 1, timeout=60)
            await ws.send_json({"type": "touch", "x": CENTRE[0], "y": CENTRE[1]})
            await read_until(ws, page, lambda: near(page, CENTRE) and page.tick > 30)
            await pause(ws, page)
    asyncio.run(main())
    escape(window_id())
    status = app.wait(60)
    np.save(out / "page.npy", page.heights)
    (out / "result.json").write_text(json.dumps({"status": status, "tick": page.tick,
                                                 "stderr": app.stderr.read()[-3000:]}), encoding="utf-8")


def drive_changes(out: Path) -> None:
    """Under Xvfb: a page chooses preset c-3, then, once the window says it took the page's
    change (its log), the window's `=` (humidity up); then Esc closes the window (or it
    closes at --max-seconds, a bound on a failure)."""
    from support.page_model import PageModel, read_until
    from support.window import escape, window_id, xdo

    app, url = start_with_window(out, "fern", 120)
    page = PageModel()
    said: list[str] = []  # the window's log, read as it comes

    def read_log() -> None:
        for line in app.stderr:  # type: ignore[union-attr]
            said.append(line)
    reader = threading.Thread(target=read_log, daemon=True)
    reader.start()

    async def main():
        from aiohttp import ClientSession
        async with ClientSession() as http, http.ws_connect(url + "ws") as ws:
            await read_until(ws, page, lambda: page.snapshots >= 1, timeout=60)
            await ws.send_json({"type": "preset", "name": "c-3"})
            await read_until(ws, page, lambda: page.state("preset") == "c-3" and page.resets)
            # (the page reads on meanwhile, as a page does)
            await read_until(ws, page, lambda: any("params (a page's change): " in line
                                                   for line in said), timeout=60)
            before = page.resets  # (the preset's may come in more than one)
            xdo("key", "--window", window_id(), "equal")
            await read_until(ws, page, lambda: page.resets > before, timeout=60)
    asyncio.run(main())
    escape(window_id())
    status = app.wait(60)
    reader.join(60)
    (out / "result.json").write_text(json.dumps({"status": status,
                                                 "stderr": "".join(said)[-3000:]}), encoding="utf-8")


def test_a_window_key_changes_the_parameters_a_page_chose_not_the_window_s_own(tmp_path):
    """With `frost serve --window`, a page's change (preset c-3) is the window's too: its
    `=` raised the humidity of its own stale parameters (fern's) and so undid the page's
    preset, silently, for every page and in the session."""
    from support.window import xvfb
    run = xvfb([sys.executable, __file__, str(tmp_path), "changes"], cwd=ROOT, timeout=180)
    assert run.returncode == 0, run.stderr[-3000:]
    result = json.loads((tmp_path / "result.json").read_text(encoding="utf-8"))
    assert result["status"] == 0, result["stderr"]
    from sim import Params
    from sim.io.session import SessionLog
    [path] = tmp_path.glob("session-*.json")
    changes = [e["params"] for e in SessionLog.load(path).events if e["kind"] == "params"]
    c3 = Params.preset("c-3")
    assert len(changes) == 2 and changes[0]["D"] == c3.D, changes
    assert changes[1]["D"] == c3.D and changes[1]["humidity"] == c3.humidity * 1.5, changes[1]


def test_a_page_and_the_window_share_the_frost(tmp_path):
    from support.window import xvfb
    run = xvfb([sys.executable, __file__, str(tmp_path)], cwd=ROOT, timeout=180)
    assert run.returncode == 0, run.stderr[-3000:]
    result = json.loads((tmp_path / "result.json").read_text(encoding="utf-8"))
    assert result["status"] == 0, result["stderr"]
    from sim.io.session import SessionLog
    from sim.io.timeline import replay
    [path] = tmp_path.glob("session-*.json")  # the window's, as it writes alone
    again = replay(SessionLog.load(path))
    assert again.tick == result["tick"]
    page = np.load(tmp_path / "page.npy")
    assert (again.geometry.heights.ravel().astype(np.float16) == page).all()
    assert "window:" in result["stderr"]  # the window did open


if __name__ == "__main__":
    sys.path[:0] = [str(ROOT), str(ROOT / "tests")]  # bench.serve_process, support
    (drive_changes if sys.argv[2:] == ["changes"] else drive)(Path(sys.argv[1]))
