"""The system Chromium for the benches and the tests that drive the phone page: where it is,
whether Playwright can drive it here, and how it is launched (headless, WebGL2 on
SwiftShader or the system's OpenGL, the desktop-only popups off)."""

from __future__ import annotations

from collections.abc import Sequence
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


def playwright_disabled(playwright) -> str | None:
    """Playwright's own --disable-features switch, as the browser was given it (read once a
    process from chrome://version of a browser launched for it), or None if it has none or
    it cannot be read (then QUIET_FEATURES stay as they are)."""
    if not _DISABLED:
        found = None
        try:
            b = playwright.chromium.launch(executable_path=CHROMIUM, headless=True)
            try:
                page = b.new_page()
                page.goto("chrome://version")
                line = page.evaluate("document.getElementById('command_line').textContent")
                found = next((a for a in line.split() if a.startswith("--disable-features=")), None)
            finally:
                b.close()
        except Exception as e:  # (an older or odd Chromium: the popups are its own business)
            print(f"bench: Chromium's command line could not be read ({e}); its features as they are")
        _DISABLED.append(found)
    return _DISABLED[0]
