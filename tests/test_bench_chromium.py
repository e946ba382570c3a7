"""bench.chromium keeps Playwright's --disable-features switch once read: a process that
finds it kept for its Playwright and Chromium launches no browser to read it, and the
suite's workers, starting together, read it once between them. A stand-in Playwright
counts the browsers launched (the real switch is held to a real browser's in
test_network_e2e)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from support import ROOT

import bench.chromium as chromium

SWITCH = "--disable-features=Alpha,Beta-2"


class StandIn:
    """A Playwright whose Chromium's chrome://version states `line`; `launches` counted."""

    def __init__(self, line: str = f"/usr/bin/chromium --headless {SWITCH} about:blank"):
        self.line, self.launches = line, 0
        self.chromium = self

    def launch(self, **_options):
        self.launches += 1
        return self

    def new_page(self):
        return self

    def goto(self, _url):
        pass

    def evaluate(self, _script):
        return self.line

    def close(self):
        pass


@pytest.fixture
def kept(tmp_path, monkeypatch) -> Path:
    """SWITCH_FILE in tmp_path, for a Chromium binary there; nothing read yet this process."""
    binary = tmp_path / "chromium"
    binary.write_text("#!/bin/sh\n", encoding="utf-8")
    monkeypatch.setattr(chromium, "CHROMIUM", str(binary))
    monkeypatch.setattr(chromium, "SWITCH_FILE", tmp_path / "switch.json")
    monkeypatch.setattr(chromium, "_DISABLED", [])
    return tmp_path / "switch.json"


def another_process(monkeypatch) -> None:
    """As a new process: nothing read in memory."""
    monkeypatch.setattr(chromium, "_DISABLED", [])


def test_the_switch_is_read_once_and_then_taken_from_the_file(kept, monkeypatch):
    first = StandIn()
    assert chromium.playwright_disabled(first) == SWITCH
    assert first.launches == 1
    assert json.loads(kept.read_text(encoding="utf-8"))["disabled"] == SWITCH
    another_process(monkeypatch)
    later = StandIn(line="a browser that should not have been launched")
    assert chromium.playwright_disabled(later) == SWITCH
    assert later.launches == 0


def test_a_switch_kept_for_another_playwright_or_chromium_is_read_again(kept, monkeypatch):
    chromium.playwright_disabled(StandIn())
    for change in ("playwright", "chromium"):
        another_process(monkeypatch)
        if change == "playwright":
            monkeypatch.setattr(chromium, "version", lambda _name: "0.0.1")
        else:
            Path(chromium.CHROMIUM).write_text("#!/bin/sh\n# upgraded\n", encoding="utf-8")
        newer = StandIn(line="chromium --disable-features=Gamma")
        assert chromium.playwright_disabled(newer) == "--disable-features=Gamma", change
        assert newer.launches == 1, change


@pytest.mark.parametrize("text, disabled", [("{", None), ("[]", None), ('{"key": null}', None),
                                            (None, "--disable-features=A --no-sandbox"), (None, 7)],
                         ids=["broken", "a list", "no key", "another switch slipped in", "a number"])
def test_a_file_that_holds_no_switch_is_read_again(kept, text, disabled):
    """Broken JSON, another shape, or a value that is not one --disable-features switch:
    the switch is read from a browser again and kept."""
    if text is None:
        text = json.dumps({"key": chromium.switch_key(), "disabled": disabled})
    kept.write_text(text, encoding="utf-8")
    browser = StandIn()
    assert chromium.playwright_disabled(browser) == SWITCH
    assert browser.launches == 1
    assert json.loads(kept.read_text(encoding="utf-8"))["disabled"] == SWITCH


def test_a_chromium_without_the_switch_is_kept_as_none(kept, monkeypatch):
    assert chromium.playwright_disabled(StandIn(line="chromium --headless about:blank")) is None
    another_process(monkeypatch)
    later = StandIn()
    assert chromium.playwright_disabled(later) is None
    assert later.launches == 0


def test_where_the_file_cannot_be_written_the_switch_is_read_each_process(tmp_path, kept, monkeypatch):
    monkeypatch.setattr(chromium, "SWITCH_FILE", tmp_path / "no such folder" / "switch.json")
    for _ in range(2):
        another_process(monkeypatch)
        browser = StandIn()
        assert chromium.playwright_disabled(browser) == SWITCH
        assert browser.launches == 1


def test_outside_a_virtualenv_nothing_is_kept_and_the_switch_is_read_each_process(kept, monkeypatch):
    """A system's Python (no virtualenv: SWITCH_FILE is None) keeps nothing in its folder."""
    monkeypatch.setattr(chromium, "SWITCH_FILE", None)
    for _ in range(2):
        another_process(monkeypatch)
        browser = StandIn()
        assert chromium.playwright_disabled(browser) == SWITCH
        assert browser.launches == 1
    assert list(kept.parent.glob("switch*")) == []


WORKER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    import bench.chromium as chromium

    folder = Path(sys.argv[1])
    chromium.CHROMIUM = str(folder / "chromium")
    chromium.SWITCH_FILE = folder / "switch.json"

    class StandIn:
        chromium = None
        def launch(self, **_options):
            with open(folder / "launches", "a") as log:
                log.write("launched\\n")
            time.sleep(0.5)  # (a browser takes a while: the others come meanwhile)
            return self
        def new_page(self): return self
        def goto(self, _url): pass
        def evaluate(self, _script): return "chromium --disable-features=Delta"
        def close(self): pass

    pw = StandIn()
    pw.chromium = pw
    sys.stdout.write(str(chromium.playwright_disabled(pw)))
""")


@pytest.mark.skipif(sys.platform == "win32", reason="the lock is fcntl's")
@pytest.mark.usefixtures("subprocesses")
def test_workers_starting_together_launch_one_browser_between_them(kept):
    folder = kept.parent
    runs = [subprocess.Popen([sys.executable, "-c", WORKER, str(folder)], cwd=ROOT,
                             stdout=subprocess.PIPE, text=True) for _ in range(3)]
    said = [run.communicate(timeout=60)[0] for run in runs]
    assert said == ["--disable-features=Delta"] * 3
    assert (folder / "launches").read_text(encoding="utf-8").splitlines() == ["launched"]
