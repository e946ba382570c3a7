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


@pytest.mark.usefixtures("subprocesses")
def test_the_window_bench_grows_the_window_then_the_fern_in_one_page_and_prints_both(capsys,
                                                                                    monkeypatch):
    """`--preset window`: the frosted window grown from its frame in the page's worker (its
    stretches, 250 ticks in the bench, 100 here to keep the suite short), its frost drawn
    over the bare glass, then the fern's three touches in the same page; the two side by
    side. Behaviour only, no speed."""
    from bench import local
    from bench.page import main

    monkeypatch.setattr(local, "STRETCH", 100)
    monkeypatch.setattr(local, "GROW_TICKS", 100)
    assert main(["--local", "--preset", "window", "--cpu-slowdown", "2", "--ticks", "200"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    head = next(line for line in lines if line.startswith("window, "))
    assert ", 200 ticks, the page's CPU slowed 2x" in head, out
    crystals = int(re.search(r"; (\d+) crystals", head).group(1))
    share = float(re.search(r"the pane ([\d.]+) % frosted", head).group(1))
    assert crystals > 100 and 0 < share < 100, out
    worker = next(line for line in lines if line.startswith("window worker tick"))
    assert "2 stretches of 100" in worker, out
    p99s = [float(v) for v in re.search(r"each: ([\d., ]+)\)", worker).group(1).split(", ")]
    p99 = float(re.search(r"p99 ([\d.]+) ms \(the worst", worker).group(1))
    phone = float(re.search(r"slower: p99 ([\d.]+) ms", worker).group(1))
    assert len(p99s) == 2 and p99 == pytest.approx(max(p99s), abs=0.06), out
    assert phone == pytest.approx(2 * p99, abs=0.1) and "(goal 8 here, 32 on a phone)" in worker, out
    fern = next(line for line in lines if line.startswith("fern, three touches"))
    assert int(re.search(r"; (\d+) crystals", fern).group(1)) > 100, out  # (the taps grew it)
    side = next(line for line in lines if line.startswith("side by side"))
    (window_median, window_p99), (fern_median, fern_p99) = (
        (float(a), float(b)) for a, b in re.findall(r"([\d.]+) / ([\d.]+)", side))
    assert 0 < window_median <= window_p99 == pytest.approx(p99, abs=0.01), out
    assert 0 < fern_median <= fern_p99, out
    assert float(re.search(r"window worker ticks a second[^:]*: ([\d.]+)-", out).group(1)) > 0, out

