"""The page's own JavaScript (app/web/local/: the simulation, its geometry and encoding)
tested with Node: `node --test` over tests/web/*.test.mjs. The Node tests hold the page's
figures against `sim/`, which they run through this checkout's Python (FROST_PYTHON, a
script of tests/support). Node is a test dependency (Makefile's APT_PKGS: Debian's
`nodejs`); where it is missing the tests say so and are skipped."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest
from support import ROOT

WEB_TESTS = ROOT / "tests" / "web"
# A whole run of the Node files, Python oracles included, on a loaded two-core machine.
NODE_TIMEOUT_S = 1500


def node_test(*files: str, deep: bool = False) -> subprocess.CompletedProcess:
    """`node --test` over `files` (relative to tests/web), with the checkout's Python for
    the oracles and FROST_DEEP set for the validation runs."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is missing: apt-get install nodejs (`make test` does)")
    env = {**os.environ, "FROST_PYTHON": sys.executable, "FROST_ROOT": str(ROOT),
           **({"FROST_DEEP": "1"} if deep else {})}
    return subprocess.run([node, "--test", *(str(WEB_TESTS / f) for f in files)], cwd=ROOT,
                          env=env, capture_output=True, text=True, timeout=NODE_TIMEOUT_S)


def web_test_files() -> list[str]:
    return sorted(p.name for p in WEB_TESTS.glob("*.test.mjs"))


# A file a test, so that the suite's two workers share them (all in one `node --test`
# took over half a minute on one worker while the other waited).
@pytest.mark.slow
@pytest.mark.usefixtures("subprocesses")
@pytest.mark.parametrize("name", web_test_files())
def test_the_pages_javascript_passes_its_node_tests(name):
    """Each tests/web/*.test.mjs passes (the long validation runs are skipped there)."""
    run = node_test(name)
    assert run.returncode == 0, run.stdout[-6000:] + run.stderr[-3000:]


@pytest.mark.validation
@pytest.mark.usefixtures("subprocesses")
def test_the_pages_long_growth_holds_to_sim():
    """The validation runs of the Node tests (FROST_DEEP: the paper's long growth)."""
    run = node_test(*web_test_files(), deep=True)
    assert run.returncode == 0, run.stdout[-6000:] + run.stderr[-3000:]
