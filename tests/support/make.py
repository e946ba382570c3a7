"""What the Makefile would run: `make -n`, run by nothing."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from support import ROOT


def planned(target: str, venv: Path) -> str:
    """What `make -n target` prints for a virtualenv at `venv`, as a user's make prints it
    even when the tests run under make (`make test`): an inner make would take the outer
    one's flags and say which folder it enters and leaves."""
    make = shutil.which("make")
    assert make, "make is missing: apt-get install make"
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
    done = subprocess.run([make, "-n", target, f"VENV={venv}"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60, env=env)
    assert done.returncode == 0, done.stderr
    return done.stdout
