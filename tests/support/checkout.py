"""The checkout's own files: what a test run must leave as it found them."""

from __future__ import annotations

import os

from support import ROOT

# What tooling may leave in the checkout; anything else a test run adds is a bug.
TOOLING = {".git", ".venv", "__pycache__", ".pytest_cache", ".ruff_cache", "frost.egg-info",
           "build"}


def checkout_files() -> set[str]:
    found = set()
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in TOOLING]
        found.update(os.path.relpath(os.path.join(folder, f), ROOT) for f in files)
    return found
