"""pyproject.toml's dependencies as pip reads them on each platform (packaging's own marker
evaluation: what pip vendors), and the window's words for a missing tuning panel
(app/window/no_panel.py) held to the same rule. Whether the wheels exist is PyPI's to
say: docs/dependencies.md gives what `pip download` found for each platform."""

from __future__ import annotations

import re
import sys

import pytest
from packaging.requirements import Requirement
from support import ROOT

from app.window import no_panel

if sys.version_info >= (3, 11):
    import tomllib
else:  # (pip's vendored copy of the same parser)
    from pip._vendor import tomli as tomllib


def requirements() -> list[Requirement]:
    with open(ROOT / "pyproject.toml", "rb") as f:
        return [Requirement(r) for r in tomllib.load(f)["project"]["dependencies"]]


def imgui() -> Requirement:
    (found,) = [r for r in requirements() if r.name == "imgui-bundle"]
    return found


def environment(python: str, system: str, machine: str, release: str) -> dict[str, str]:
    """The marker variables of a machine (those the markers here read, and the rest set)."""
    names = {"linux": "posix", "darwin": "posix", "win32": "nt"}
    platforms = {"linux": "Linux", "darwin": "Darwin", "win32": "Windows"}
    return {"python_version": python, "python_full_version": f"{python}.0",
            "sys_platform": system, "platform_system": platforms[system], "os_name": names[system],
            "platform_machine": machine, "platform_release": release, "platform_version": "",
            "platform_python_implementation": "CPython", "implementation_name": "cpython",
            "implementation_version": f"{python}.0", "extra": ""}


# (machine, Python, sys.platform, platform.machine(), platform.release(), the panel's
# library asked for): by hand, from the wheels of imgui-bundle 1.93.0 on PyPI (cp311 and
# on; manylinux x86_64 and aarch64; win_amd64 and win_arm64; macosx_14_0_arm64 alone)
MACHINES = [
    ("Debian 12 (CI, make run)", "3.11", "linux", "x86_64", "6.1.0-18-amd64", True),
    ("Linux, a kernel of its own", "3.12", "linux", "x86_64", "6.18.44-fc-v669", True),
    ("Linux on ARM", "3.13", "linux", "aarch64", "6.8.0-1012-raspi", True),
    ("Linux, Python 3.10", "3.10", "linux", "x86_64", "5.15.0-91-generic", False),
    ("Windows 11", "3.12", "win32", "AMD64", "11", True),
    ("Windows 10", "3.11", "win32", "AMD64", "10", True),
    ("macOS 12 Monterey, Intel", "3.12", "darwin", "x86_64", "21.6.0", False),
    ("macOS 13 Ventura, Apple silicon", "3.12", "darwin", "arm64", "22.6.0", False),
    ("macOS 14 Sonoma, Intel", "3.12", "darwin", "x86_64", "23.6.0", False),
    ("macOS 14 Sonoma, Apple silicon", "3.12", "darwin", "arm64", "23.0.0", True),
    ("macOS 15 Sequoia, Apple silicon", "3.13", "darwin", "arm64", "24.6.0", True),
    ("macOS 26 Tahoe, Apple silicon", "3.14", "darwin", "arm64", "25.1.0", True),
    ("macOS 26, Apple silicon, Python 3.10", "3.10", "darwin", "arm64", "25.1.0", False),
    ("an Apple-silicon Mac, Intel Python (Rosetta)", "3.12", "darwin", "x86_64", "24.6.0", False),
]


@pytest.mark.parametrize(("python", "system", "machine", "release", "asked"),
                         [m[1:] for m in MACHINES], ids=[m[0] for m in MACHINES])
def test_the_panels_library_is_asked_for_where_its_wheel_is(python, system, machine, release, asked):
    marker = imgui().marker
    assert marker is not None
    assert marker.evaluate(environment(python, system, machine, release)) is asked
    # the window's words say the same: a reason where pip leaves it out, none where not
    major, minor = map(int, python.split("."))
    reason = no_panel.no_wheel((major, minor), system, machine, release)
    assert (reason is None) is asked, reason


def test_the_window_names_the_release_pyproject_pins():
    assert f"{imgui().name}{imgui().specifier}" == no_panel.PIN


def test_every_other_dependency_is_asked_for_on_every_machine():
    """numpy, moderngl, glfw, pyglm, Pillow, aiohttp, segno and cryptography have wheels on
    all three desktops: no marker leaves one out anywhere."""
    others = [r for r in requirements() if r.name != "imgui-bundle"]
    assert {r.name for r in others} >= {"numpy", "moderngl", "glfw", "pyglm", "Pillow", "aiohttp",
                                         "segno", "cryptography"}
    for _, *machine, _ in MACHINES:
        env = environment(*machine)
        assert all(r.marker is None or r.marker.evaluate(env) for r in others), machine


def test_the_release_is_never_parsed_as_a_version():
    """packaging 22 to 25 (vendored by pip 24.1 to 25.x) raise InvalidVersion for a marker
    that puts platform_release left of a comparison where the release is no version
    (Linux's "6.1.0-18-amd64"): the whole install fails. Right of it, the release is only
    ever part of a version specifier, refused quietly and compared as text."""
    marker = str(imgui().marker)
    assert "platform_release" in marker
    assert not re.search(r"platform_release\s*(?:[<>=!~]=?|===?)", marker), marker


@pytest.mark.parametrize(("python", "system", "machine", "release", "says"), [
    ((3, 10), "linux", "x86_64", "6.1.0", "its wheels start at Python 3.11"),
    ((3, 12), "darwin", "x86_64", "23.6.0", "it has no wheel for an Intel Mac"),
    ((3, 12), "darwin", "arm64", "22.6.0", "its Mac wheel needs macOS 14 or later"),
    ((3, 12), "darwin", "arm64", "not.a.release", "its Mac wheel needs macOS 14 or later")])
def test_the_window_says_why_the_panel_is_missing(monkeypatch, python, system, machine, release, says):
    monkeypatch.setitem(sys.modules, "imgui_bundle", None)  # (its import fails, as uninstalled)
    monkeypatch.setattr(sys, "version_info", (*python, 0, "final", 0))
    monkeypatch.setattr(sys, "platform", system)
    monkeypatch.setattr(no_panel.platform, "machine", lambda: machine)
    monkeypatch.setattr(no_panel.platform, "release", lambda: release)
    problem = no_panel.panel_problem()
    said: list[str] = []
    no_panel.NoPanel(said.append).toggle()  # key M
    assert said == [problem]
    assert problem == f"the tuning panel needs imgui-bundle==1.93.0, and {says}; the keys " \
                      "still tune every parameter (H)"
