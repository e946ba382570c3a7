"""A folder made once for a whole run: the workers of a run (pytest-xdist) share it, the
first to ask makes it while the others wait, so that what takes minutes to make (the
wheel, a virtualenv with the package installed) is made once, not once a worker."""

from __future__ import annotations

import fcntl
import os
import shutil
from collections.abc import Callable
from pathlib import Path


def made_once(tmp_path_factory, name: str, make: Callable[[Path], None]) -> Path:
    """The folder `name` of this run, `make(folder)` called on it by the first worker to
    ask (the others wait on a lock); a make that failed is tried again by the next."""
    base = tmp_path_factory.getbasetemp()
    # a worker's base folder is one of the run's (popen-gw0, ...): their parent is the run's
    run = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    folder, done = run / name, run / f"{name}.made"
    with open(run / f"{name}.lock", "w", encoding="utf-8") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            shutil.rmtree(folder, ignore_errors=True)  # what a failed make left
            folder.mkdir()
            make(folder)
            done.touch()
    return folder
