"""This process's memory for the benchmarks' figures, where the platform tells it: resident
now from /proc (Linux), the peak from `resource` (Linux and a Mac: kB there, bytes on a
Mac); None where the platform has neither (Windows), which the figure then says."""

from __future__ import annotations

import sys
from pathlib import Path

STATUS = Path("/proc/self/status")


def rss_mb() -> float | None:
    """Resident memory now, MB; None where /proc is not."""
    try:
        for line in STATUS.read_text(encoding="utf-8").splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def peak_rss_mb() -> float | None:
    """The most resident memory so far, MB; None where `resource` is not."""
    try:
        import resource
    except ImportError:
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / (1 << 20) if sys.platform == "darwin" else peak / 1024.0


def mb(value: float | None) -> str:
    """A figure of MB for a line, or words saying it is unavailable here."""
    return "unavailable on this platform" if value is None else f"{value:.0f} MB"
