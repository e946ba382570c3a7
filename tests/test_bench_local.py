"""`python -m bench page --local` (bench/local.py): the phone's own frost's figures printed,
the worker's own tick, its phone figure (times the slowdown), the page's frames and the
Python tick beside; no speed asserted. (A module of its own: the bench drives its own
Playwright, which cannot run beside another module's.)"""

from __future__ import annotations

import re

import pytest
from support.phone import PROBLEM

pytestmark = [pytest.mark.browser, pytest.mark.slow,
              pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]


@pytest.mark.usefixtures("subprocesses")
def test_the_bench_prints_the_workers_figures_and_the_python_tick(capsys):
    from bench.page import main

    assert main(["--local", "--cpu-slowdown", "2", "--ticks", "50"]) == 0
    out = capsys.readouterr().out
    lines = dict(zip(("head", "worker", "rate", "frames", "python"), out.splitlines(), strict=False))
    figures = {name: [float(v) for v in re.findall(r"(\d+(?:\.\d+)?) ms", line)]
               for name, line in lines.items()}
    median, p99, phone = figures["worker"]
    assert 0 < median <= p99 and phone == pytest.approx(2 * p99, abs=0.1), out
    assert float(re.search(r"last 5 s\): ([\d.]+)", out).group(1)) > 0, out
    assert len(figures["frames"]) == 2 and len(figures["python"]) == 2, out
    assert "slowed 2x" in out and ", 50 ticks," in lines["head"], out
