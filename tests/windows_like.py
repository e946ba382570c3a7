"""The frost command as it meets Windows, on this machine: no SIGHUP, no `resource` or
`fcntl` module, and event loops that take no signal handlers (Windows' raise
NotImplementedError), so that the portable paths (app/window/frost_window.py's signals,
app/serve/command.py's Ctrl-C, app/bench/memory.py) run here.

    python tests/windows_like.py ARGS...   # frost ARGS, as on Windows
    python tests/windows_like.py --import-all   # every module of app and sim imports
"""

from __future__ import annotations

import asyncio
import importlib
import pkgutil
import signal
import sys
from pathlib import Path


def as_on_windows() -> None:
    del signal.SIGHUP
    sys.modules["resource"] = None  # type: ignore[assignment]  # (an import of it fails)
    sys.modules["fcntl"] = None  # type: ignore[assignment]

    def refuse(self, *args, **kwargs):
        raise NotImplementedError  # as Windows' event loops do

    asyncio.AbstractEventLoop.add_signal_handler = refuse  # type: ignore[method-assign]
    asyncio.SelectorEventLoop.add_signal_handler = refuse  # type: ignore[method-assign]


def import_all() -> int:
    failed = []
    for name in ("sim", "app"):
        package = importlib.import_module(name)
        for info in pkgutil.walk_packages(package.__path__, name + "."):
            try:
                importlib.import_module(info.name)
            except Exception as err:
                failed.append(f"{info.name}: {err!r}")
    print("\n".join(failed) or "every module imported")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    as_on_windows()
    if sys.argv[1:] == ["--import-all"]:
        sys.exit(import_all())
    from app.cli import main
    sys.exit(main(sys.argv[1:]))
