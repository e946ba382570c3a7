"""`--record`: a benchmark's figures kept as a dated entry of its results file,
`docs/results/bench-NAME.md`, newest first: `frost bench sim|render`'s as JSON, what a
checkout's `python -m bench NAME` printed as text (`keep_printed`).

The reference pages (docs/benchmarks.md) hold each benchmark's current figures and no date;
the results file holds the history: each entry says when, on which commit, on which
machine and under what load its figures were taken, as those decide what a time means.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import io
import json
import os
import platform
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

from sim.io.files import not_regular, refusal, why, write_atomic

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "docs" / "results"
ENTRY = "## "  # each entry is a second-level heading: the command that measured it


def results_file(name: str) -> Path:
    """Where `frost bench NAME --record` keeps its entries."""
    return RESULTS / f"bench-{name}.md"


def shown(name: str) -> str:
    """The results file as a message names it: relative to the checkout, where it lies."""
    path = results_file(name)
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def keep(name: str, command: str, figures: dict | str, prog: str, head: str) -> int:
    """`--record` at a benchmark's end: `figures` kept in its results file, with `head`, the
    commit taken when the run started (the code that ran). Exit status 0, or 1 when the
    file cannot be written (the figures are printed already: none is lost)."""
    problem = record(results_file(name), command, figures, head=head, title=prog)
    if problem:
        print(f"{prog}: error: --record: {problem}", file=sys.stderr)
        return 1
    print(f"recorded in {shown(name)}")
    return 0


def keep_printed(name: str, prog: str, argv: list[str], run: Callable[..., int]) -> int:
    """`run(argv, prog=prog)`, a benchmark, with what it prints shown as it comes and kept,
    dated, as an entry of its results file headed by `prog argv`: the file checked before
    the run (which may take minutes), the commit taken at its start. A run that fails, or
    stops at its own command line (`--help`, a bad option: SystemExit), keeps nothing."""
    problem = record_problem(results_file(name))
    if problem:
        print(f"{prog}: error: --record: {problem}", file=sys.stderr)
        return 2
    head = commit()
    printed = Tee(sys.stdout)
    with contextlib.redirect_stdout(printed):
        status = run(argv, prog=prog)
    if status:
        return status
    return keep(name, " ".join([prog, *argv]), printed.kept.getvalue(), prog, head)


class Tee(io.TextIOBase):
    """A stream that writes through to `shown` (the terminal) and keeps a copy."""

    def __init__(self, shown):
        self.shown, self.kept = shown, io.StringIO()

    def write(self, text: str) -> int:
        self.shown.write(text)
        return self.kept.write(text)

    def flush(self) -> None:
        self.shown.flush()


def record_problem(path: Path) -> str | None:
    """Why `path` cannot take a record (checked before the benchmark runs, which may take
    minutes); None if it can."""
    if not path.parent.is_dir():
        return f"{path.parent}: no such folder (--record writes into a checkout's docs/results/)"
    kind = not_regular(path)
    if kind:
        return f"{path}: {refusal(kind)}"
    if not os.access(path if path.exists() else path.parent, os.W_OK):
        return f"{path}: not writable"
    return None


def record(path: Path, command: str, figures: dict | str, now: dt.datetime | None = None,
           head: str | None = None, title: str | None = None) -> str | None:
    """Put an entry for `figures` (what `command` printed: JSON's figures, or its text) at
    the top of `path`'s entries, under its title; the file is made if missing, titled by
    `title` (the benchmark's command, default `frost bench NAME`). `head`: the commit
    (default: the checkout's now). Returns why it could not be written (one line), or None."""
    text = path.read_text(encoding="utf-8") if path.exists() else header(path, title)
    new = entry(command, figures, now, head)
    try:
        write_atomic(path, lambda f: f.write(insert(text, new).encode()))
    except OSError as err:
        return why(err, path)
    return None


def header(path: Path, title: str | None = None) -> str:
    """A new results file's title and what it holds."""
    name = title or f"frost bench {path.stem.removeprefix('bench-')}"
    return (f"# Results: {name}\n\nEach run of `{name} --record`, "
            "newest first: the command, when, on which commit, on which machine and under "
            "what load, and the figures it printed. [benchmarks.md](../benchmarks.md) holds the "
            "current figures.\n")


def insert(text: str, new: str) -> str:
    """`text` with `new` before its first entry (after its title and introduction)."""
    lines = text.splitlines(keepends=True)
    first = next((i for i, line in enumerate(lines) if line.startswith(ENTRY)), len(lines))
    head = "".join(lines[:first]).rstrip("\n") + "\n\n"
    rest = "".join(lines[first:])
    return head + new + ("\n" + rest if rest else "")


def entry(command: str, figures: dict | str, now: dt.datetime | None = None,
          head: str | None = None) -> str:
    """One entry: headed by the command, so that a link to the command's heading finds its
    newest entry (the first of that name); the facts that decide what the figures mean;
    the figures as the benchmark printed them."""
    when = (now or dt.datetime.now(dt.timezone.utc)).strftime("%Y-%m-%d %H:%M UTC")
    return (f"{ENTRY}`{command}`\n\n"
            f"- date: {when}\n"
            f"- commit: {head or commit()}\n"
            f"- machine: {machine()}\n"
            f"- load average (1, 5, 15 min): {load()}\n\n"
            + (f"```text\n{figures.rstrip()}\n```\n" if isinstance(figures, str) else
               f"```json\n{as_json(figures)}\n```\n"))


def as_json(figures: dict) -> str:
    """`figures` as JSON, a line for each section: short enough to read, and one
    section's change is one line of a diff."""
    lines = [f" {json.dumps(name)}: {json.dumps(value)}" for name, value in figures.items()]
    return "{\n" + ",\n".join(lines) + "\n}" if lines else "{}"


def commit() -> str:
    """The checkout's commit (short hash, `+` when files differ from it), or "unknown"
    outside a checkout or without git."""
    try:
        head = _git("rev-parse", "--short", "HEAD")
        # The results files themselves change with each record: not a change of the code.
        dirty = _git("status", "--porcelain", "--untracked-files=no", "--", ".",
                     ":!docs/results")
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("+" if dirty else "") if head else "unknown"


def _git(*argv: str) -> str:
    done = subprocess.run(["git", *argv], cwd=ROOT, capture_output=True, text=True,
                          timeout=30, check=True)
    return done.stdout.strip()


def machine() -> str:
    """Cores, CPU model and operating system, e.g. "2 cores, AMD EPYC 7B13, Debian GNU/Linux
    12 (bookworm)"."""
    return f"{os.cpu_count() or '?'} cores, {cpu_model()}, {system()}"


def cpu_model() -> str:
    """The CPU's name: Linux's /proc/cpuinfo, else what platform knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            for line in info:
                key, _, value = line.partition(":")
                if key.strip() in ("model name", "Hardware", "Processor") and value.strip():
                    return value.strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def system() -> str:
    """The operating system's own name for itself where it has one (Linux's os-release)."""
    try:
        return platform.freedesktop_os_release()["PRETTY_NAME"]
    except (OSError, KeyError, AttributeError):
        return platform.platform(terse=True)


def load() -> str:
    """The load averages, or "unknown" where the system gives none (Windows)."""
    averages = load_averages()
    return " / ".join(f"{v:.2f}" for v in averages) if averages else "unknown"


def load_averages() -> tuple[float, float, float] | None:
    """The load averages of the last 1, 5 and 15 minutes; None where the system keeps none
    (Windows: no os.getloadavg there)."""
    try:
        return os.getloadavg()
    except (AttributeError, OSError):  # (OSError: a system that has it but cannot say)
        return None
