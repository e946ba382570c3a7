"""The project's import graph, read from the source (ast): which module imports which."""

from __future__ import annotations

import ast
from pathlib import Path


def imported_modules(path: Path, name: str, known: set[str]) -> set[str]:
    """The modules among `known` that module `name` (file `path`) imports, anywhere in it
    (a function's late import too: it ties the modules as surely, only later). `from x
    import y` counts as x.y where that is a module, else as x; a package's __init__ that
    runs first is not counted (a package importing its own modules is no circle)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.rsplit(".", node.level - 1)[0] if node.level else ""
            module = ".".join(p for p in (base, node.module or "") if p)
            found |= {f"{module}.{a.name}" if f"{module}.{a.name}" in known else module
                      for a in node.names}
    return found & known - {name}


def project_modules(root: Path, *packages: str) -> dict[str, Path]:
    """Every module of `packages` under `root`, by name: its file."""
    found = {}
    for top in packages:
        for path in sorted((root / top).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def import_graph(root: Path, *packages: str) -> dict[str, set[str]]:
    files = project_modules(root, *packages)
    return {m: imported_modules(p, m, set(files)) for m, p in files.items()}
