"""What the benchmarks' own command lines share (`frost bench sim` and `python -m bench page`
parse their arguments themselves)."""

from __future__ import annotations

import argparse


class Parser(argparse.ArgumentParser):
    """Refuses a bad command line in one line, naming the option, as `frost` does."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _within(text: str, kind, lowest, highest, what: str):
    """`text` read as `kind` if it lies in [lowest, highest]; else the argument's error."""
    try:
        n = kind(text)
    except ValueError:
        n = lowest - 1
    if not lowest <= n <= highest:
        raise argparse.ArgumentTypeError(f"{text!r} must be {what} from {lowest} to {highest}")
    return n


def count(text: str) -> int:
    """How many of something a benchmark does (--repeats, --samples, ...): a whole number
    from 1 to 100 000."""
    return _within(text, int, 1, 100_000, "a whole number")


def slowdown(text: str) -> float:
    """How many times slower the page's CPU runs (--cpu-slowdown): a number from 1 to 20."""
    return _within(text, float, 1, 20, "a number")
