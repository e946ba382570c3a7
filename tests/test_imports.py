"""Imports point one way: window -> simulation thread -> sim, tools -> renderer -> sim.
Each check imports in a fresh interpreter and reads what ended up in sys.modules."""

from __future__ import annotations

import ast
import json
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest
from support.imports import import_graph

import app.bench
import app.tools
import bench
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


@pytest.mark.usefixtures("subprocesses")
def test_the_simulation_thread_loads_no_gl_no_window_and_no_tools():
    loaded = loaded_by("app.simthread.thread")
    assert "app.simthread.thread" in loaded and "sim.look.maps" in loaded  # it did import
    assert under(loaded, *GL_AND_WINDOW, "app.tools", "app.gl", "app.window") == set()


@pytest.mark.usefixtures("subprocesses")
def test_sim_loads_nothing_of_the_app_nor_gl_nor_images():
    names = modules_of(sim)
    assert "sim.look.maps" in names and "sim.look.material" in names
    loaded = loaded_by(*names)
    assert under(loaded, *GL_AND_WINDOW, "app", "PIL") == set()


@pytest.mark.usefixtures("subprocesses")
def test_the_server_loads_no_gl_and_no_window_library():
    loaded = loaded_by("app.serve.command", "bench.serve")
    assert "aiohttp" in loaded and "app.serve.feed" in loaded
    assert under(loaded, *GL_AND_WINDOW, "app.gl", "app.tools") == set()


@pytest.mark.usefixtures("subprocesses")
def test_the_server_loads_nothing_of_the_window_package():
    """The key table serves the window and the page: it lives outside app/window
    (app/keys.py), so the server loads no module of the window (`--window` opens one only
    when asked, at run time)."""
    loaded = loaded_by("app.serve.server", "app.serve.controls", "bench.serve")
    assert "app.keys" in loaded and "app.serve.controls" in loaded
    assert under(loaded, "app.window") == set()


@pytest.mark.usefixtures("subprocesses")
def test_the_tools_load_no_window():
    loaded = loaded_by(*modules_of(app.tools))
    assert "app.tools.maps" in loaded and "moderngl" in loaded  # the renderer's GL is theirs
    assert under(loaded, "glfw", "app.window") == set()


@pytest.mark.usefixtures("subprocesses")
def test_the_benchmarks_load_no_window_and_nothing_of_the_app_loads_them():
    loaded = loaded_by(*modules_of(app.bench))
    assert "app.bench.simulation" in loaded and "app.bench.render" in loaded  # it did import
    assert under(loaded, "glfw", "app.window") == set()
    users = {part for part, parts in app_imports().items() if "app.bench" in parts}
    assert users == {"app.cli"}  # the command line runs them; no other part leans on them


@pytest.mark.usefixtures("subprocesses")
def test_the_checkout_s_benchmarks_load_no_window():
    loaded = loaded_by(*modules_of(bench))
    assert "bench.page" in loaded and "bench.serve" in loaded  # it did import
    assert under(loaded, "glfw", "app.window") == set()


def test_nothing_of_the_app_nor_of_sim_imports_the_checkout_s_benchmarks():
    """bench/ stays out of the wheel (it drives a browser, shapes a network): a module of the
    package importing it, even inside a function, would fail for every user."""
    graph = import_graph(ROOT, "app", "sim", "bench")
    assert "bench.shaper" in graph["bench.page"]  # (bench's modules are in the graph)
    users = sorted(module for module, imported in graph.items() if not module.startswith("bench")
                   and any(other.split(".")[0] == "bench" for other in imported))
    assert users == []


def app_part(module: str) -> str | None:
    """The part of the app `module` belongs to (app.cli, app.tools, app.images, ...), or
    None for a module outside the app."""
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "app" and len(parts) > 1 else None


def app_imports() -> dict[str, set[str]]:
    """For each part of the app, the other parts its modules import anywhere in them,
    inside functions too (an import put off to run time still ties the parts)."""
    graph: dict[str, set[str]] = {}
    for path in sorted((ROOT / "app").rglob("*.py")):
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        source = app_part(module.removesuffix(".__init__"))
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module, *(f"{node.module}.{a.name}" for a in node.names)]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            for name in names:
                target = app_part(name)
                if source and target and target != source:
                    graph.setdefault(source, set()).add(target)
    return graph


def circle(graph: dict[str, set[str]]) -> list[str]:
    """One circle of imports in `graph` ([] if none), by depth-first search."""
    done: set[str] = set()

    def visit(node: str, path: list[str]) -> list[str]:
        if node in path:
            return path[path.index(node):] + [node]
        if node in done:
            return []
        for nxt in sorted(graph.get(node, ())):
            found = visit(nxt, path + [node])
            if found:
                return found
        done.add(node)
        return []

    return next((c for c in (visit(n, []) for n in sorted(graph)) if c), [])


def test_circle_finds_a_circle_of_three_and_none_in_a_chain():
    assert circle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert circle({"a": {"b", "c"}, "b": {"c"}}) == []


def test_the_apps_parts_import_each_other_in_no_circle():
    graph = app_imports()
    assert "app.tools" in graph["app.cli"]  # the command line runs the tools
    assert circle(graph) == [], " -> ".join(circle(graph))


def test_a_late_import_closing_a_circle_is_found(tmp_path):
    """The check sees a circle whose one side is an import inside a function (Python runs
    it fine: the late import finds the other module loaded), and none where a package's
    __init__ imports its own modules that import from the package."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from pkg.a import run\n", encoding="utf-8")
    (pkg / "a.py").write_text("from pkg import b\n\ndef run():\n    return b.go()\n", encoding="utf-8")
    (pkg / "b.py").write_text("def go():\n    from pkg.a import run\n    return run\n", encoding="utf-8")
    graph = import_graph(tmp_path, "pkg")
    assert graph["pkg.b"] == {"pkg.a"} and graph["pkg.a"] == {"pkg.b"}
    assert circle(graph) == ["pkg.a", "pkg.b", "pkg.a"]
    # a module of the package: not its __init__
    (pkg / "b.py").write_text("from pkg import a\n", encoding="utf-8")
    (pkg / "a.py").write_text("X = 1\n", encoding="utf-8")
    assert circle(import_graph(tmp_path, "pkg")) == []


def test_no_module_of_the_project_imports_itself_through_others():
    graph = import_graph(ROOT, "app", "sim", "bench")
    assert "app.serve.feed" in graph["app.serve.server"]  # (the graph is the project's)
    assert circle(graph) == [], " -> ".join(circle(graph))


@pytest.mark.usefixtures("subprocesses")
def test_every_module_imports_as_on_windows():
    """No SIGHUP, no `resource`, no `fcntl` (tests/windows_like.py): a module that reads one
    at import (the window read signal.SIGHUP) would stop `frost` on Windows."""
    script = Path(__file__).resolve().parent / "windows_like.py"
    run = subprocess.run([sys.executable, str(script), "--import-all"], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0 and "every module imported" in run.stdout, run.stdout + run.stderr
