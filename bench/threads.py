"""Where a page's worker spent its time (`python -m bench page --local`): the CPU time and
the time waiting for a core of Chromium's threads, from Linux's
/proc/<pid>/task/<tid>/schedstat (ns on a CPU, ns runnable but waiting, time slices).

The worker times its ticks by the wall clock, so a tick it spends waiting for a core counts
as long as one it spends working; these figures tell the two apart. The page's main thread
is beside them: Chromium's CPU throttling on Linux slows that thread by a busy wait in a
signal handler, so under a 4x throttle it holds a core about three quarters of the time
whether the page has work or not (a phone's slower core holds none)."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

log = logging.getLogger(__name__)

PROC = Path("/proc")
WORKER = "DedicatedWorker"  # (a thread's name, as the kernel keeps it: 15 characters at most)


@dataclass(frozen=True)
class ThreadTime:
    """One thread's time, ms: on a CPU, and runnable but waiting for one."""

    cpu_ms: float
    wait_ms: float

    def __sub__(self, other: ThreadTime) -> ThreadTime:
        return ThreadTime(self.cpu_ms - other.cpu_ms, self.wait_ms - other.wait_ms)


def page_threads(marker: str, proc: Path = PROC) -> dict[str, ThreadTime] | None:
    """The time so far of the process whose command line holds `marker` (the browser's
    profile folder) that runs a dedicated worker (the page's renderer): "worker" (its
    worker threads, summed) and "page" (its main thread). None where /proc says nothing of
    it (not Linux, no such process)."""
    for pid in sorted(p for p in _listdir(proc) if p.isdigit()):
        cmdline = _read(proc / pid / "cmdline")
        if cmdline is None or marker not in cmdline:
            continue
        threads = {tid: _read(proc / pid / "task" / tid / "comm") for tid in _listdir(proc / pid / "task")}
        workers = [tid for tid, name in threads.items() if name is not None and name.strip() == WORKER]
        if not workers:
            continue
        main = _schedstat(proc / pid / "task" / pid / "schedstat")
        rest = [t for tid in workers if (t := _schedstat(proc / pid / "task" / tid / "schedstat"))]
        if main is None or len(rest) < len(workers):
            continue
        return {"worker": ThreadTime(sum(t.cpu_ms for t in rest), sum(t.wait_ms for t in rest)), "page": main}
    return None


def _schedstat(path: Path) -> ThreadTime | None:
    """A schedstat file's first two numbers (ns) in ms, or None where it has not two."""
    text = _read(path)
    fields = text.split() if text else []
    try:
        return ThreadTime(int(fields[0]) / 1e6, int(fields[1]) / 1e6)
    except (IndexError, ValueError):
        log.debug("%s: not a schedstat line: %r", path, text)
        return None


def _listdir(path: Path) -> list[str]:
    try:
        return [p.name for p in path.iterdir()]
    except OSError:  # (a process that ended, or no /proc)
        return []


def _read(path: Path) -> str | None:
    try:
        return path.read_bytes().replace(b"\0", b" ").decode("utf-8", "replace")
    except OSError:
        return None
