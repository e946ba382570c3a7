"""docs/architecture.md against the code: every module of app/, sim/ and bench/ and every
script of the page (app/web/) has its line there, every line names a file that exists, and the arrows
between folders are the ones the imports make (tests/test_imports.py reads them)."""

from __future__ import annotations

import re
from pathlib import Path

from support import ROOT
from support.imports import import_graph, project_modules

PAGE = ROOT / "docs" / "architecture.md"
PACKAGES = ("app", "sim", "bench")  # bench/: the checkout's benchmarks, outside the wheel
# A module's line: "- `app/window/hud.py`: ..."
MODULE_LINE = re.compile(r"^- `((?:app|sim|bench)/[\w/.-]+\.(?:py|js))`:", re.M)
# A folder's arrow: "- `app/window` → `app`, `app/gl`, ..."
ARROW_LINE = re.compile(r"^- `([\w/]+)` → (.+)$", re.M)


def listed(text: str) -> list[str]:
    return MODULE_LINE.findall(text)


def modules(root: Path) -> set[str]:
    """Every .py under app/, sim/ and bench/ and every .js under app/web/, as paths from
    `root`."""
    found = [*(p for top in PACKAGES for p in (root / top).rglob("*.py")),
             *(root / "app" / "web").rglob("*.js")]
    return {p.relative_to(root).as_posix() for p in found}


def arrows(text: str) -> dict[str, set[str]]:
    """The page's arrows: each folder and the folders it imports."""
    return {source: set(re.findall(r"`([\w/]+)`", targets))
            for source, targets in ARROW_LINE.findall(text)}


def folder_imports(root: Path) -> dict[str, set[str]]:
    """Each folder of app/, sim/ and bench/ and the other folders its modules import."""
    files = project_modules(root, *PACKAGES)
    where = {m: p.parent.relative_to(root).as_posix() for m, p in files.items()}
    graph: dict[str, set[str]] = {}
    for module, imported in import_graph(root, *PACKAGES).items():
        for other in imported:
            if where[other] != where[module]:
                graph.setdefault(where[module], set()).add(where[other])
    return graph


def test_the_page_reading_finds_modules_and_arrows_in_a_hand_written_page():
    text = ("- `sim/a.py`: one\n- `app/web/b.js`: two\n- not `sim/c.py`: three\n"
            "- `bench/d.py`: four\n- `sim` → `sim/core`\n- `app/x` → `app`, `sim/io`\n")
    assert listed(text) == ["sim/a.py", "app/web/b.js", "bench/d.py"]
    assert arrows(text) == {"sim": {"sim/core"}, "app/x": {"app", "sim/io"}}


def test_folder_imports_of_a_hand_made_tree(tmp_path):
    """A module of sim/core importing sim/index's (late, in a function) and its own
    folder's; app/ importing sim/ and app/gl/, bench/ app/gl/: the arrows between folders
    only."""
    for name, source in {"sim/__init__.py": "", "sim/core/__init__.py": "",
                         "sim/core/a.py": "from sim.core import b\n\ndef f():\n"
                                          "    from sim.index import grid\n",
                         "sim/core/b.py": "", "sim/index/__init__.py": "",
                         "sim/index/grid.py": "import numpy\n", "app/__init__.py": "",
                         "app/keys.py": "from sim.core.a import f\n", "app/gl/__init__.py": "",
                         "app/gl/r.py": "from app import keys\n", "bench/__init__.py": "",
                         "bench/p.py": "def f():\n    from app.gl import r\n"}.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(source, encoding="utf-8")
    assert folder_imports(tmp_path) == {"sim/core": {"sim/index"}, "app": {"sim/core"},
                                        "app/gl": {"app"}, "bench": {"app/gl"}}


def test_every_module_is_listed_once_in_docs_architecture():
    names = listed(PAGE.read_text(encoding="utf-8"))
    twice = sorted({n for n in names if names.count(n) > 1})
    assert twice == [], f"docs/architecture.md lists these modules more than once: {twice}"
    missing = sorted(modules(ROOT) - set(names))
    assert missing == [], f"docs/architecture.md has no line for these modules: {missing}"


def test_every_module_listed_in_docs_architecture_exists():
    gone = sorted(set(listed(PAGE.read_text(encoding="utf-8"))) - modules(ROOT))
    assert gone == [], f"docs/architecture.md lists modules that do not exist: {gone}"


def test_the_arrows_of_docs_architecture_are_the_imports_of_the_code():
    said, made = arrows(PAGE.read_text(encoding="utf-8")), folder_imports(ROOT)
    for folder in sorted(set(said) | set(made)):
        unsaid = sorted(made.get(folder, set()) - said.get(folder, set()))
        untrue = sorted(said.get(folder, set()) - made.get(folder, set()))
        assert (unsaid, untrue) == ([], []), (
            f"docs/architecture.md: {folder} imports {unsaid} (no arrow there) and "
            f"does not import {untrue} (an arrow there)")


def serve_popens(path: Path) -> list[int]:
    """The lines of `path` where a subprocess.Popen's argument list names `serve`: a
    `frost serve` started by hand."""
    import ast

    text = path.read_text(encoding="utf-8")
    if "Popen" not in text:  # (most files: no tree to walk)
        return []
    return [node.lineno for node in ast.walk(ast.parse(text))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr == "Popen" and node.args and isinstance(node.args[0], ast.List)
            and any(isinstance(e, ast.Constant) and e.value == "serve" for e in node.args[0].elts)]


def test_the_finder_of_a_frost_serve_started_by_hand_finds_one(tmp_path):
    (tmp_path / "x.py").write_text(
        "import subprocess, sys\n\n"
        "subprocess.run([sys.executable, '-m', 'app', 'serve', '--port', '99999'])\n"
        "p = subprocess.Popen([sys.executable, '-m', 'app', 'serve', '--port', '0'])\n",
        encoding="utf-8")
    assert serve_popens(tmp_path / "x.py") == [4]


def test_every_frost_serve_a_benchmark_or_a_test_starts_is_a_serve_process():
    """One ServeProcess (bench/serve_process.py) starts `frost serve` for the benchmarks
    and the tests: none starts it by hand (a run refused at once may be a subprocess.run)."""
    found = [f"{path.relative_to(ROOT)}:{line}"
             for folder in ("bench", "tests", "tests/support") for path in (ROOT / folder).glob("*.py")
             if path.name != "serve_process.py" for line in serve_popens(path)]
    assert found == []
