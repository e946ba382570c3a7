"""Imports point one way: window -> simulation thread -> sim, tools -> renderer -> sim.
Each check imports in a fresh interpreter and reads what ended up in sys.modules."""

from __future__ import annotations

import json
import pkgutil
import subprocess
import sys
from pathlib import Path

import app.tools
import sim

ROOT = Path(__file__).resolve().parent.parent
GL_AND_WINDOW = ("moderngl", "glfw", "glcontext", "glm")
_LIST_LOADED = ("import importlib, json, sys\n"
                "for name in sys.argv[1:]:\n"
                "    importlib.import_module(name)\n"
                "print(json.dumps(sorted(sys.modules)))")


def loaded_by(*modules: str) -> set[str]:
    """Every module a fresh interpreter holds after importing `modules`."""
    run = subprocess.run([sys.executable, "-c", _LIST_LOADED, *modules], cwd=ROOT,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return set(json.loads(run.stdout))


def under(loaded: set[str], *packages: str) -> set[str]:
    """The loaded modules that are `packages` or lie inside them."""
    return {m for m in loaded if any(m == p or m.startswith(p + ".") for p in packages)}


def modules_of(package) -> list[str]:
    """Every module of `package`, its sub-packages' included."""
    return [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")]


def test_the_simulation_thread_loads_no_gl_no_window_and_no_tools():
    loaded = loaded_by("app.simthread.thread")
    assert "app.simthread.thread" in loaded and "sim.look.maps" in loaded  # it did import
    assert under(loaded, *GL_AND_WINDOW, "app.tools", "app.gl", "app.window") == set()


def test_sim_loads_nothing_of_the_app_nor_gl_nor_images():
    names = modules_of(sim)
    assert "sim.look.maps" in names and "sim.look.material" in names
    loaded = loaded_by(*names)
    assert under(loaded, *GL_AND_WINDOW, "app", "PIL") == set()


def test_the_server_loads_no_gl_and_no_window_library():
    loaded = loaded_by("app.serve.server", "app.serve.bench")
    assert "aiohttp" in loaded and "app.serve.feed" in loaded
    assert under(loaded, *GL_AND_WINDOW, "app.gl", "app.tools") == set()


def test_the_tools_load_no_window():
    loaded = loaded_by(*modules_of(app.tools))
    assert "app.tools.maps" in loaded and "moderngl" in loaded  # the renderer's GL is theirs
    assert under(loaded, "glfw", "app.window") == set()
