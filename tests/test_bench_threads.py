"""bench/threads.py: the page's worker and main thread found in a /proc tree, and their CPU
time and time waiting for a core read from schedstat (a tree made here, its numbers
chosen: the oracle)."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.threads import ThreadTime, page_threads

MARKER = "/tmp/profile-x1"


def process(proc: Path, pid: int, cmdline: list[str], threads: dict[int, tuple[str, str | None]]) -> None:
    """Process `pid` of `cmdline` (NUL-separated, as the kernel keeps it) with `threads`:
    tid -> (name, schedstat line or None for none)."""
    root = proc / str(pid)
    (root / "task").mkdir(parents=True)
    (root / "cmdline").write_bytes("\0".join(cmdline).encode("utf-8") + b"\0")
    for tid, (name, stat) in threads.items():
        task = root / "task" / str(tid)
        task.mkdir()
        (task / "comm").write_text(name + "\n", encoding="utf-8")
        if stat is not None:
            (task / "schedstat").write_text(stat + "\n", encoding="utf-8")


@pytest.fixture
def proc(tmp_path: Path) -> Path:
    proc = tmp_path / "proc"
    # The browser and its GPU process (no worker), another profile's renderer with a
    # worker, and the page's renderer: main thread, its worker, a compositor.
    process(proc, 10, ["chromium", f"--user-data-dir={MARKER}"], {10: ("chromium", "1 2 3")})
    process(proc, 11, ["chromium", "--type=gpu-process", f"--user-data-dir={MARKER}"],
            {11: ("chromium", "5 6 7"), 12: ("Thread<00>", "9000000 8000000 10")})
    process(proc, 20, ["chromium", "--type=renderer", "--user-data-dir=/tmp/other"],
            {20: ("chromium", "1 1 1"), 21: ("DedicatedWorker", "7000000 7000000 7")})
    process(proc, 30, ["chromium --type=renderer --user-data-dir=" + MARKER],  # (a rewritten title)
            {30: ("chromium", "6500000000 2400000000 19057"),
             31: ("DedicatedWorker", "565000000 634000000 2005"),
             32: ("Compositor", "287000000 279000000 2844")})
    (proc / "self").mkdir()  # (not a process number)
    return proc


def test_the_pages_worker_and_main_thread_are_read_in_ms(proc: Path):
    assert page_threads(MARKER, proc) == {"worker": ThreadTime(565.0, 634.0),
                                          "page": ThreadTime(6500.0, 2400.0)}


def test_two_workers_are_summed_and_a_difference_is_the_time_between(proc: Path):
    (proc / "30" / "task" / "33").mkdir()
    (proc / "30" / "task" / "33" / "comm").write_text("DedicatedWorker\n", encoding="utf-8")
    (proc / "30" / "task" / "33" / "schedstat").write_text("1000000 3000000 4\n", encoding="utf-8")
    threads = page_threads(MARKER, proc)
    assert threads is not None
    assert threads["worker"] == ThreadTime(566.0, 637.0)
    since = threads["worker"] - ThreadTime(500.0, 600.0)
    assert (since.cpu_ms, since.wait_ms) == (pytest.approx(66.0), pytest.approx(37.0))


@pytest.mark.parametrize("broken", ["no worker", "no schedstat", "not numbers", "no proc"])
def test_nothing_is_said_where_proc_tells_nothing(proc: Path, broken: str):
    stat = proc / "30" / "task" / "31" / "schedstat"
    if broken == "no worker":
        (proc / "30" / "task" / "31" / "comm").write_text("Compositor\n", encoding="utf-8")
    elif broken == "no schedstat":
        stat.unlink()
    elif broken == "not numbers":
        stat.write_text("n/a\n", encoding="utf-8")
    else:
        proc = proc / "missing"
    assert page_threads(MARKER, proc) is None


@pytest.mark.parametrize(("rate", "throttled"), [(1.0, False), (4.0, True)])
def test_the_benchs_line_names_the_throttle_only_where_the_page_is_slowed(rate: float, throttled: bool):
    from bench.local import threads_line

    line = threads_line(ThreadTime(444.4, 727.0), ThreadTime(6903.0, 10.0), 10.64, rate)
    assert "the worker 444 ms on a CPU, 727 ms waiting for one" in line
    assert "over the 10.6 s grown" in line and "main thread 6903 ms on a CPU" in line
    assert ("throttle" in line) == throttled
