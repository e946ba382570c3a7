"""What the Makefile would run: `make -n`, run by nothing."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from support import ROOT


def planned(target: str, venv: Path) -> str:
    """What `make -n target` prints for a virtualenv at `venv`."""
    make = shutil.which("make")
    assert make, "make is missing: apt-get install make"
    done = subprocess.run([make, "-n", target, f"VENV={venv}"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stdout
