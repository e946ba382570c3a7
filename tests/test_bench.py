"""The simulation benchmark's sections run on their own and measure what they say."""
import contextlib
import io
import json
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from support import ROOT

from app import cli
from app.bench import growth, simulation
from sim.params import Params


@pytest.mark.parametrize("humidity", growth.BUSY_HUMIDITIES)
def test_busy_ticks_are_timed_with_the_whole_pool_walking(humidity, monkeypatch):
    """Each timed tick starts with >= 90 % of `humidity` walkers (a screen budget below
    the humidity would cap the pool and leave no busy tick to time)."""
    pools = []
    step = growth.FrostSim.step

    def counted(sim):
        pools.append(len(sim.water_area))
        step(sim)

    monkeypatch.setattr(growth.FrostSim, "step", counted)
    times = growth.busy_ticks(humidity, 3)
    assert len(times) == 3 == len(pools)
    assert min(pools) >= 0.9 * humidity


def test_a_busy_tick_that_cannot_happen_is_refused():
    """A budget below the humidity is said, not looped on forever."""
    small = Params.preset("c-2", humidity=3000, water_budget=1000)
    with pytest.raises(ValueError, match="no tick of it can be busy"):
        growth.busy_ticks_for(small, 3)


def test_each_section_runs_alone(capsys):
    """`--section memory` prints that section's figures and its JSON, and no other."""
    assert simulation.main(["--quick", "--section", "memory"]) == 0
    out = capsys.readouterr().out
    figures = json.loads(out.strip().splitlines()[-1])
    assert set(figures) == {"memory"}
    assert figures["memory"]["crystals"] > 0
    assert "Fig. 9" not in out


# ---- its command line -------------------------------------------------------------------

VALUES = st.one_of(st.sampled_from(["", "0", "-1", "1", "2.5", "1e9", "nan", "100000", "100001",
                                    "fig9", "busy", "memory", "nope", "3"]),
                   st.integers(-10**9, 10**9).map(str), st.text(max_size=5))
OPTIONS = st.lists(st.one_of(
    st.tuples(st.sampled_from(["--repeats", "--samples", "--section"]), VALUES)
    .map(lambda ov: f"{ov[0]}={ov[1]}"),
    st.sampled_from(["--quick", "--bogus", "stray"])), max_size=5)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=150)
@given(argv=OPTIONS)
@example(argv=["--repeats=0"])  # fig9 took the median of no runs: KeyError
@example(argv=["--samples=-1"])  # busy took the percentile of no ticks: IndexError
def test_frost_bench_sim_runs_or_is_refused_in_one_line(monkeypatch, argv):
    ran = []

    def section(args) -> dict:
        ran.append(args)
        return {}

    monkeypatch.setattr(simulation, "SECTIONS", dict.fromkeys(simulation.SECTIONS, section))
    err, out = io.StringIO(), io.StringIO()
    status: int | str | None
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            status = cli.main(["bench", "sim", *argv])
        except SystemExit as stop:  # argparse's way out, as in a real run
            status = stop.code
    if ran:
        assert status == 0
        args = ran[0]
        assert isinstance(args.repeats, int) and args.repeats >= 1
        assert isinstance(args.samples, int) and args.samples >= 1
    else:
        message = err.getvalue()
        assert status == 2, message
        assert message.count("\n") == 1 and message.startswith("frost bench sim: error: "), message


@pytest.mark.parametrize("preset", ["c-2", "fern"])
def test_the_phase_profiles_time_every_phase_a_tick_calls(preset):
    """Each phase the profiles name is one the simulation has and calls in a tick (the
    sections timed methods that a refactor had renamed, and crashed)."""
    sim = growth.FrostSim(Params.preset(preset), seed=0)
    sim.touch(*growth.CENTRE)
    spent = growth.time_phases(sim, more=True)
    for _ in range(30):
        sim.step()
    called = {name for name, s in spent.items() if s > 0}
    # Table 1's presets keep no pool topped up: no frozen water is replaced in a tick.
    idle = {"counted_and_new"} if preset == "c-2" else set()
    assert called == set(spent) - idle
    assert {"walk", "crystallize", "link", "register", "settle", "relocate"} <= called


@pytest.mark.parametrize("preset, version", [("fern", 7), ("fern", 8), ("window", 8)])
def test_a_taps_wait_is_the_ticks_until_its_seed_has_a_child(preset, version):
    """`taps.waits` against a run driven tap by tap: each tap applied before its tick, its
    seed's wait the ticks until some crystal has it for a parent (every crystal looked at)."""
    from app.bench import taps
    from sim import FrostSim

    n = 4
    got = taps.waits(preset, version, n, seed=1)
    sim = FrostSim(Params.preset(preset), seed=1, version=version)
    spots = taps.tap_spots(n)
    when = [int(k * taps.GAP_S * 25) for k in range(n)]
    seeds: dict[int, tuple[int, int]] = {}
    want = [taps.NEVER] * n
    for tick in range(when[-1] + taps.NEVER):
        for k in range(n):
            if when[k] == tick:
                sim.touch(float(spots[k][0]), float(spots[k][1]))
                seeds[k] = (len(sim.crystals) - 1, tick)
        sim.step()
        for k, (s, t) in seeds.items():
            if want[k] == taps.NEVER and s in set(sim.parents.tolist()) and tick + 1 - t <= taps.NEVER:
                want[k] = tick + 1 - t
    assert got.tolist() == want
    assert min(want) >= 1


@pytest.mark.parametrize("loadavg", [None, (1.234, 0.5, 0.25)], ids=["windows", "posix"])
def test_bench_render_says_the_load_or_that_it_is_unknown(monkeypatch, capsys, gl_ctx, loadavg):
    """Windows has no os.getloadavg: the load is "unknown" there, the figures all said."""
    import os

    from app.bench import render as bench

    if loadavg is None:
        monkeypatch.delattr(os, "getloadavg")
    else:
        monkeypatch.setattr(os, "getloadavg", lambda: loadavg)
    monkeypatch.setattr(bench, "make_context", lambda: gl_ctx)
    assert cli.main(["bench", "render", "--frames", "2", "--max-ticks", "3"]) == 0
    out = capsys.readouterr().out.splitlines()
    said = "unknown" if loadavg is None else "1.23"
    assert f"load: {said} (the last minute's average)" in out, out
    assert json.loads(out[-1])["load_average"] == (None if loadavg is None else 1.23)


@pytest.mark.parametrize("what", ["page", "serve"])
def test_frost_bench_of_a_checkout_s_benchmark_says_in_one_line_where_it_moved(what, capsys):
    """The page's and the server's benchmarks left the package (they drive a browser or load
    the server): `frost bench page|serve`, with or without arguments, names the command."""
    for extra in ([], ["--taps", "3"]):
        assert cli.main(["bench", what, *extra]) == 2
        captured = capsys.readouterr()
        assert captured.out == ""
        assert captured.err == (f"frost bench {what}: error: it moved out of the package: run "
                                f"`python -m bench {what}` from a checkout\n")


@pytest.mark.parametrize("argv, says", [
    (["shaper", "--to", "nowhere"],
     "python -m bench shaper: error: --to 'nowhere' must be HOST:PORT (a port from 1 to 65535)"),
    (["page", "--network", "wifi"], "python -m bench page: error: --network and --cpu-slowdown go with"),
    (["serve", "--attack", "x"], "python -m bench serve: error: argument --attack: invalid choice: 'x'"),
    (["minute", "--samples", "0"], "python -m bench minute: error: argument --samples: '0' must be"),
    (["tiles", "--max-ticks", "x"], "python -m bench tiles: error: argument --max-ticks: invalid int"),
    (["shaper", "--to", "127.0.0.1:9", "--record"],
     "python -m bench: error: --record: shaper measures nothing to keep"),
    (["sim"], "python -m bench: error: argument WHAT: invalid choice: 'sim'"),
    ([], "python -m bench: error: the following arguments are required: WHAT"),
])
@pytest.mark.usefixtures("subprocesses")
def test_python_m_bench_hands_the_rest_to_the_benchmark_named(argv, says):
    """`python -m bench WHAT ...` from the checkout: WHAT's own command line reads what
    follows (its refusals name it), and a missing or unknown WHAT is refused in one line."""
    done = subprocess.run([sys.executable, "-m", "bench", *argv], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith(says), done.stderr


def test_the_windows_figures_are_its_stretches_worst_p99_and_their_median():
    from bench.local import frosted_share, window_figures

    runs = [{"tickMedianMs": m, "tickP99Ms": p, "ticksPerSecond": r, "crystals": c, "tick": t}
            for m, p, r, c, t in ((1.0, 4.0, 25.0, 10, 250), (2.0, 9.0, 24.8, 20, 500),
                                  (1.5, 3.0, 25.2, 30, 750))]
    got = window_figures(runs)
    assert got["median"] == 1.5 and got["medians"] == (1.0, 2.0)
    assert got["p99"] == 9.0 and got["p99s"] == [4.0, 9.0, 3.0] and got["rates"] == (24.8, 25.2)
    assert got["crystals"] == 30 and got["tick"] == 750
    bare = np.zeros((4, 5, 3), int)
    now = bare.copy()
    now[0, :2] = 13  # frosted: more than 12 away
    now[1, 0] = (0, 0, 12)  # not
    assert frosted_share(bare, now) == 2 / 20
