"""The frost command as it meets Windows, on this machine: what Windows' Python (3.10-3.12)
lacks is taken away (os functions, modules, signals), and event loops take no signal
handlers (Windows' raise NotImplementedError), so that the portable paths (the window's
signals, serve's Ctrl-C, the benchmarks' memory and load, every file write) run here.

Text opened without an encoding reads the locale's (cp1252 on Windows): this run starts
Python with -X warn_default_encoding and makes frost's EncodingWarning an error.

    python tests/windows_like.py ARGS...   # frost ARGS, as on Windows
    python tests/windows_like.py --import-all   # every module of app and sim imports
"""

from __future__ import annotations

import asyncio
import importlib
import os
import pkgutil
import signal
import sys
import warnings
from pathlib import Path

# What Linux's Python has and Windows' lacks, that frost or its libraries might reach for.
OS_FUNCTIONS = ("fchmod", "getloadavg", "sched_getaffinity", "fork", "getuid", "geteuid",
                "pathconf", "fpathconf")
MODULES = ("pwd", "grp", "resource", "fcntl", "termios")
SIGNALS = ("SIGHUP", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM", "SIGPIPE")
# The modules whose text files must say their encoding: frost's own (and this script).
FROSTS = r"((app|sim)(\..*)?|__main__)\Z"


def as_on_windows() -> None:
    for name in OS_FUNCTIONS:
        delattr(os, name)
    for name in MODULES:
        sys.modules[name] = None  # type: ignore[assignment]  # (an import of it fails)
    for name in SIGNALS:
        delattr(signal, name)

    def refuse(self, *args, **kwargs):
        raise NotImplementedError  # as Windows' event loops do

    for loop in (asyncio.AbstractEventLoop, asyncio.SelectorEventLoop):
        loop.add_signal_handler = refuse  # type: ignore[method-assign]
        loop.remove_signal_handler = refuse  # type: ignore[method-assign]
    warnings.filterwarnings("error", category=EncodingWarning, module=FROSTS)


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
    if not sys.flags.warn_default_encoding:  # (read at start-up only: start again with it)
        os.execv(sys.executable, [sys.executable, "-X", "warn_default_encoding", *sys.argv])
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    as_on_windows()
    if sys.argv[1:] == ["--import-all"]:
        sys.exit(import_all())
    from app.cli import main
    sys.exit(main(sys.argv[1:]))
