"""What the benchmarks' own command lines share (`frost bench sim` and `frost bench page`
parse their arguments themselves)."""

from __future__ import annotations

import argparse


class Parser(argparse.ArgumentParser):
    """Refuses a bad command line in one line, naming the option, as `frost` does."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def count(text: str) -> int:
    """How many of something a benchmark does (--repeats, --samples, ...): a whole number
    from 1 to 100 000."""
    try:
        n = int(text)
    except ValueError:
        n = 0
    if not 1 <= n <= 100_000:
        raise argparse.ArgumentTypeError(f"{text!r} must be a whole number from 1 to 100000")
    return n


def slowdown(text: str) -> float:
    """How many times slower the page's CPU runs (--cpu-slowdown): a number from 1 to 20."""
    try:
        n = float(text)
    except ValueError:
        n = 0.0
    if not 1 <= n <= 20:
        raise argparse.ArgumentTypeError(f"{text!r} must be a number from 1 to 20")
    return n
