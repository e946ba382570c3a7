"""The phone page in WebKit, the iPhone's engine: Debian's WebKitWebDriver driving WebKitGTK's
MiniBrowser (`--automation`) on an Xvfb display of its own, through a small W3C WebDriver
client over HTTP (a few JSON requests: a session, a page, a script, a pointer's actions, a
screenshot). Written here rather than taken from Selenium: these are all the tests need,
and the client adds no package."""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import socket
import subprocess
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
from PIL import Image

from support.window import display

DRIVER = "WebKitWebDriver"
# Debian's libwebkit2gtk-4.1-0 (which webkit2gtk-driver depends on) ships the MiniBrowser.
BROWSERS = [Path(f"/usr/lib/{arch}/webkit2gtk-4.1/MiniBrowser")
            for arch in ("x86_64-linux-gnu", "aarch64-linux-gnu")]


def webkit_problem() -> str | None:
    """Why WebKit cannot run here (None: it can)."""
    if shutil.which(DRIVER) is None:
        return f"{DRIVER} missing: apt-get install webkit2gtk-driver (`make test` does)"
    if browser() is None:
        return "WebKitGTK's MiniBrowser missing: apt-get install webkit2gtk-driver (`make test` does)"
    if shutil.which("Xvfb") is None:
        return "Xvfb missing: apt-get install xvfb (`make test` does)"
    return None


def browser() -> Path | None:
    return next((b for b in BROWSERS if b.exists()), None)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class WebDriverError(RuntimeError):
    pass


class WebKit:
    """One WebKitWebDriver on its own loopback port, one MiniBrowser session of it, on an
    Xvfb display of its own; `close()` ends all three."""

    def __init__(self, folder: Path, width: int = 390, height: int = 844):
        self._display = display()
        env = {**os.environ, "DISPLAY": self._display.__enter__(),
               # (the browser's caches, its service workers' storage: the test's own)
               "HOME": str(folder), "XDG_CACHE_HOME": str(folder / "cache"),
               "XDG_DATA_HOME": str(folder / "data"), "XDG_CONFIG_HOME": str(folder / "config")}
        self.driver = None
        self.session = None
        self.log = folder / "webkitwebdriver.log"
        try:
            for _ in range(5):  # (a port picked free may be taken before the driver binds it)
                self.port = free_port()
                with open(self.log, "wb") as log:
                    self.driver = subprocess.Popen(
                        [DRIVER, f"--port={self.port}", "--host=127.0.0.1"], env=env,
                        stdout=log, stderr=subprocess.STDOUT)
                if self._wait_ready():
                    break
                self.driver.kill()
                self.driver.wait(10)
            else:
                said = self.log.read_text(encoding="utf-8", errors="replace")[-2000:]
                raise WebDriverError(f"{DRIVER} did not start: {said}")
            caps = {"capabilities": {"alwaysMatch": {"webkitgtk:browserOptions": {
                "binary": str(browser()), "args": ["--automation"]}}}}
            self.session = self._call("POST", "/session", caps, timeout=120)["sessionId"]
            self.call("POST", "/window/rect", {"width": width, "height": height})
        except BaseException:
            self.close()
            raise

    def _wait_ready(self, timeout: float = 60) -> bool:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.driver.poll() is not None:
                return False
            try:
                return bool(self._call("GET", "/status", timeout=5).get("ready", True))
            except (OSError, WebDriverError):
                time.sleep(0.1)
        return False

    def _call(self, method: str, path: str, body: dict | None = None, timeout: float = 60):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", data=data,
                                         method=method,
                                         headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request, timeout=timeout) as r:
                return json.loads(r.read())["value"]
        except urllib.error.HTTPError as err:
            raise WebDriverError(f"{method} {path}: {err.code} {err.read()[:2000]!r}") from None

    def call(self, method: str, path: str, body: dict | None = None, timeout: float = 60):
        """A command of this session (`path` after /session/ID)."""
        return self._call(method, f"/session/{self.session}{path}", body, timeout)

    def open(self, url: str) -> None:
        self.call("POST", "/url", {"url": url}, timeout=120)

    def reload(self) -> None:
        self.call("POST", "/refresh", {}, timeout=120)

    def js(self, expression: str, *args):
        """The value of the JavaScript `expression` (`arguments[i]` are `args`)."""
        return self.call("POST", "/execute/sync", {"script": f"return ({expression});",
                                                     "args": list(args)})

    def wait_for(self, expression: str, timeout: float = 60, what: str = "") -> object:
        """Until `expression` is truthy in the page (polled); its value. A bound on a
        failure, never a claim on speed: the failure says `what` the page was doing."""
        end = time.monotonic() + timeout
        while True:
            value = self.js(expression)
            if value:
                return value
            if time.monotonic() > end:
                seen = self.js(what) if what else None
                raise AssertionError(f"never true within {timeout} s: {expression} ({seen})")
            time.sleep(0.1)

    def click(self, x: float, y: float) -> None:
        """A mouse's press and release at (x, y), CSS px of the viewport."""
        self.call("POST", "/actions", {"actions": [{
            "type": "pointer", "id": "finger", "parameters": {"pointerType": "mouse"},
            "actions": [{"type": "pointerMove", "duration": 0, "x": round(x), "y": round(y)},
                        {"type": "pointerDown", "button": 0},
                        {"type": "pointerUp", "button": 0}]}]})
        self.call("DELETE", "/actions")

    def screenshot(self) -> np.ndarray:
        """The viewport, H x W x 3 (device px)."""
        png = base64.b64decode(self.call("GET", "/screenshot"))
        return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))

    def close(self) -> None:
        try:
            if self.session is not None:
                self._call("DELETE", f"/session/{self.session}", timeout=30)
        except (OSError, WebDriverError):
            pass
        finally:
            self.session = None
            if self.driver is not None and self.driver.poll() is None:
                self.driver.terminate()
                try:
                    self.driver.wait(10)
                except subprocess.TimeoutExpired:
                    self.driver.kill()
                    self.driver.wait(10)
            self._display.__exit__(None, None, None)
