"""The system Chromium for the benches and the tests that drive the phone page: where it is,
whether Playwright can drive it here, and how it is launched (headless, WebGL2 on
SwiftShader or the system's OpenGL, the desktop-only popups off)."""

from __future__ import annotations

import json
import os
import re
import sys
from collections.abc import Sequence
from contextlib import ExitStack, contextmanager
from importlib.metadata import version
from pathlib import Path
from typing import Any

CHROMIUM = "/usr/bin/chromium"
# SwiftShader (Chromium's CPU rasteriser) for WebGL2, on any machine, GPU or not.
CHROMIUM_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
# Or the system's OpenGL through EGL (Mesa's llvmpipe here: the desktop renderer's rasteriser).
ANGLE = {"swiftshader": CHROMIUM_ARGS, "gl-egl": ["--use-angle=gl-egl", "--ignore-gpu-blocklist"]}
# Chromium 151 and later render the desktop address bar's popup (a WebUI page, in a renderer
# of its own) ahead of time for every new window, headless too: about half a second of CPU
# while each new context's page loads, on the two cores the page, the browser and the
# server share (a late join: 1.88 against 1.41 s, docs/results/bench-page.md, run 9). A
# phone's browser has no such popup; Puppeteer turns both off by default.
QUIET_FEATURES = ("WebUIOmniboxPopup", "WebUIOmniboxAimPopup")


def browser_problem() -> str | None:
    """Why the page cannot be driven here (no playwright, no chromium), or None."""
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "the playwright package is missing (pip install playwright; it is in the dev extra)"
    if not Path(CHROMIUM).is_file():
        return f"{CHROMIUM} is missing (apt-get install chromium)"
    return None


def launch(playwright, angle: str = "swiftshader", args: Sequence[str] = ()):
    """The system Chromium, headless, with WebGL2 on SwiftShader (or `angle` of ANGLE) and
    `args` more."""
    return playwright.chromium.launch(**chromium_options(playwright, [*ANGLE[angle], *args]))


def chromium_options(playwright, args) -> dict[str, Any]:
    """Launch options for the system Chromium, headless, with `args` and QUIET_FEATURES off.
    Chromium keeps only the last --disable-features it is given, and Playwright gives its
    own: so that list is left out and given again with QUIET_FEATURES added."""
    options: dict[str, Any] = {"executable_path": CHROMIUM, "headless": True, "args": list(args)}
    default = playwright_disabled(playwright)
    if default is not None:
        names = [n for n in default.split("=", 1)[1].split(",") if n]
        options["ignore_default_args"] = [default]
        options["args"].append("--disable-features=" + ",".join([*names, *QUIET_FEATURES]))
    return options


_DISABLED: list[str | None] = []
# Where that switch is kept once read, for every later process of this virtualenv (the
# suite's workers, each benchmark it starts): beside the environment's own files, keyed by
# the Playwright and the Chromium that gave it. Reading it again costs a browser's launch.
# Outside a virtualenv (a system's Python) nothing is kept.
SWITCH_FILE: Path | None = (Path(sys.prefix) / "frost-chromium-switch.json"
                            if sys.prefix != sys.base_prefix else None)
SWITCH = re.compile(r"--disable-features=[\w,.-]*")


def playwright_disabled(playwright) -> str | None:
    """Playwright's own --disable-features switch, as the browser was given it (read from
    chrome://version of a browser launched for it, once for this Playwright and Chromium:
    SWITCH_FILE), or None if it has none or it cannot be read (then QUIET_FEATURES stay as
    they are)."""
    if not _DISABLED:
        file = SWITCH_FILE
        if file is None:
            _DISABLED.append(read_switch(playwright))
        else:
            key = switch_key()
            with switch_lock(file):
                kept = kept_switch(file, key)
                _DISABLED.append(kept["disabled"] if kept is not None else read_switch(playwright))
                if kept is None:
                    keep_switch(file, key, _DISABLED[0])
    return _DISABLED[0]


def read_switch(playwright) -> str | None:
    """The --disable-features switch of a Chromium that `playwright` launched, or None."""
    try:
        b = playwright.chromium.launch(executable_path=CHROMIUM, headless=True)
        try:
            page = b.new_page()
            page.goto("chrome://version")
            line = page.evaluate("document.getElementById('command_line').textContent")
            return next((a for a in line.split() if a.startswith("--disable-features=")), None)
        finally:
            b.close()
    except Exception as e:  # (an older or odd Chromium: the popups are its own business)
        print(f"bench: Chromium's command line could not be read ({e}); its features as they are")
        return None


def switch_key() -> list:
    """What the switch depends on: Playwright's version and the Chromium binary's file."""
    try:
        st = Path(CHROMIUM).stat()
        binary = [st.st_size, st.st_mtime_ns]
    except OSError:
        binary = None
    return [version("playwright"), CHROMIUM, binary]


def kept_switch(file: Path, key: list) -> dict | None:
    """`file`'s entry if it was kept for `key` and reads as a switch (or none), else None."""
    try:
        kept = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(kept, dict) or kept.get("key") != key:
        return None
    disabled = kept.get("disabled")
    return kept if disabled is None or isinstance(disabled, str) and SWITCH.fullmatch(disabled) else None


def keep_switch(file: Path, key: list, disabled: str | None) -> None:
    """Write `file` (not where the environment's folder cannot be written: then each
    process reads the switch again)."""
    try:
        tmp = file.with_name(f"{file.name}.{os.getpid()}")
        tmp.write_text(json.dumps({"key": key, "disabled": disabled}), encoding="utf-8")
        os.replace(tmp, file)
    except OSError:
        pass


@contextmanager
def switch_lock(file: Path):
    """One process at a time reads or writes `file` (the suite's workers start
    together: one launches the browser, the others wait for what it kept). Where locking
    is not to be had (no fcntl, a folder not written), none."""
    with ExitStack() as held:
        try:
            import fcntl

            lock = held.enter_context(file.with_name(file.name + ".lock").open("a"))
            fcntl.flock(lock, fcntl.LOCK_EX)
        except (ImportError, OSError):
            pass
        yield
