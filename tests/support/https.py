"""A Chromium that trusts frost's local authority: what it needs, and its HOME."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path


def browser_problem() -> str | None:
    from bench.chromium import browser_problem as problem

    found = problem()
    if found is None and not Path("/usr/bin/certutil").is_file():
        return "certutil is missing (apt-get install libnss3-tools; `make test` does)"
    return found


def trusting_home(home: Path, cafile: Path | None) -> Path:
    """A HOME whose NSS database trusts `cafile` as an authority for web sites (or nothing)."""
    db = home / ".pki" / "nssdb"
    db.mkdir(parents=True)
    subprocess.run(["certutil", "-d", f"sql:{db}", "-N", "--empty-password"], check=True)
    if cafile is not None:
        subprocess.run(["certutil", "-d", f"sql:{db}", "-A", "-t", "C,,", "-n", "frost",
                        "-i", str(cafile)], check=True)
    return home


def trusting_chromium(pw, home: Path, name: str):
    """The system Chromium with `home` as its HOME (its NSS database of trusted
    authorities is home/.pki/nssdb) and `name` resolved to this machine: a name that is no
    loopback name, so that only HTTPS makes the page a secure context."""
    from bench.chromium import ANGLE, chromium_options
    from support.phone import TEST_ANGLE, TEST_ARGS

    args = [*ANGLE[TEST_ANGLE], *TEST_ARGS, f"--host-resolver-rules=MAP {name} 127.0.0.1"]
    return pw.chromium.launch(**chromium_options(pw, args), env={**os.environ, "HOME": str(home)})
