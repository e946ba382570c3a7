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


def test_the_tools_load_no_window():
    loaded = loaded_by(*modules_of(app.tools))
    assert "app.tools.maps" in loaded and "moderngl" in loaded  # the renderer's GL is theirs
    assert under(loaded, "glfw", "app.window") == set()


def imported_modules(path: Path, name: str, known: set[str]) -> set[str]:
    """The modules among `known` that module `name` (file `path`) imports, anywhere in it
    (a function's late import too); `from .x import y` counts as x.y where that is a module."""
    import ast

    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.rsplit(".", node.level - 1)[0] if node.level else ""
            module = ".".join(p for p in (base, node.module or "") if p)
            found |= {module, *(f"{module}.{alias.name}" for alias in node.names)}
    return found & known - {name}


def test_no_module_of_sim_imports_itself_through_others():
    files = {m: ROOT / (m.replace(".", "/") + ".py") for m in modules_of(sim)}
    files = {m: p if p.exists() else p.with_suffix("") / "__init__.py" for m, p in files.items()}
    graph = {m: imported_modules(p, m, set(files)) for m, p in files.items()}
    for start in graph:  # a walk from each module must never come back to it
        seen, todo = set(), list(graph[start])
        while todo:
            module = todo.pop()
            assert module != start, f"{start} imports itself through {sorted(seen)}"
            if module not in seen:
                seen.add(module)
                todo.extend(graph[module])
