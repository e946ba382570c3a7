"""The window without its tuning panel: where imgui-bundle is not installed (pip leaves it
out where it has no wheel: pyproject.toml's marker, docs/dependencies.md), key M says why
and the keys tune everything as before. `frost info` says which, and why."""

from __future__ import annotations

import logging
import platform
import sys

from sim.io.files import one_line

log = logging.getLogger("app.window")

PIN = "imgui-bundle==1.93.0"  # as pyproject.toml asks for it
KEYS = "the keys still tune every parameter (H)"
SONOMA_DARWIN = 23  # macOS 14's Darwin kernel: 1.93.0's one Mac wheel, macosx_14_0_arm64


def no_wheel(python: tuple[int, int] | None = None, system: str | None = None,
             machine: str | None = None, release: str | None = None) -> str | None:
    """Why imgui-bundle 1.93.0 has no wheel for this machine (Python `python`, sys.platform
    `system`, platform.machine() and platform.release(), this one's by default), so that
    pip leaves it out; None where pip installs it. pyproject.toml's marker says the same:
    the tests hold the two to each other."""
    python = python or (sys.version_info[0], sys.version_info[1])
    system = sys.platform if system is None else system
    machine = platform.machine() if machine is None else machine
    release = platform.release() if release is None else release
    if python < (3, 11):
        return "its wheels start at Python 3.11"
    if system != "darwin":
        return None
    if machine != "arm64":
        return "it has no wheel for an Intel Mac"
    if _major(release) < SONOMA_DARWIN:
        return "its Mac wheel needs macOS 14 or later"
    return None


def _major(release: str) -> int:
    """The major number of a Darwin release ("22.6.0": 22; 0 where it has none)."""
    head = release.split(".")[0]
    return int(head) if head.isdigit() else 0


def panel_problem() -> str | None:
    """Why the window has no tuning panel here, in one line; None where it has one (imgui
    imports: also where the user installed it against pip's marker)."""
    try:
        from imgui_bundle import imgui  # noqa: F401
    except ImportError as err:
        reason = no_wheel()
        if reason is not None:
            return f"the tuning panel needs {PIN}, and {reason}; {KEYS}"
        return (f"the tuning panel needs {PIN}, which cannot be imported "
                f"({one_line(str(err))}): pip install {PIN}; {KEYS}")
    return None


class NoPanel:
    """PanelHost's interface, doing nothing: input is never the panel's."""

    ids: tuple[int, ...] = ()  # no window of its own

    def __init__(self, say=None, error: str = ""):
        self.say = say or (lambda text: log.warning("%s", text))
        self.error = error  # the panel's ImportError, where imgui itself imports

    def toggle(self) -> None:
        self.say(panel_problem() or
                 f"the tuning panel could not be loaded ({one_line(self.error)}); {KEYS}")

    def needs_frame(self) -> bool:
        return False

    def frame(self, phone_drawn: bool) -> None:
        pass

    def readout(self, phone_frames: int) -> str | None:
        return None

    def lost(self, resource: int) -> tuple[int, ...]:
        return ()

    def close(self) -> None:
        pass
