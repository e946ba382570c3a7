"""`frost bench sim --record`, `frost bench render --record` and `python -m bench NAME
--record`: each run's figures kept as a dated entry at the top of the benchmark's results
file (app/bench/results.py); and the tables of current figures in docs/ against the newest
entry of the results they link."""

from __future__ import annotations

import contextlib
import datetime as dt
import io
import json
import re
import subprocess
import sys
import types
from pathlib import Path

import pytest

from app import cli
from app.bench import results, simulation
from bench import __main__ as python_m_bench

ROOT = Path(__file__).resolve().parent.parent
FIELDS = ("date", "commit", "machine", "load average (1, 5, 15 min)")


def entries(text: str) -> list[dict]:
    """The file's entries, top to bottom, read back by hand: the heading's date, each
    `- name: value` line, the JSON block (`figures`) and the text block (`printed`)."""
    found = []
    for block in re.split(r"^## ", text, flags=re.MULTILINE)[1:]:
        heading, _, body = block.partition("\n")
        fields = dict(line[2:].split(": ", 1) for line in body.splitlines()
                      if line.startswith("- "))
        figures = re.search(r"```json\n(.*?)\n```", body, flags=re.DOTALL)
        printed = re.search(r"```text\n(.*?)\n```", body, flags=re.DOTALL)
        found.append({"command": heading, **fields,
                      "figures": json.loads(figures.group(1)) if figures else None,
                      "printed": printed.group(1) if printed else None})
    return found


def run(argv: list[str]) -> tuple[int | str | None, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = cli.main(argv)
        except SystemExit as stop:
            status = stop.code
    return status, out.getvalue(), err.getvalue()


def test_two_records_stand_newest_first_under_the_title(tmp_path):
    path = tmp_path / "bench-sim.md"
    first = dt.datetime(2026, 11, 20, 9, 5, tzinfo=dt.timezone.utc)
    assert results.record(path, "frost bench sim --section memory", {"memory": {"mb": 1}},
                          first) is None
    assert results.record(path, "frost bench sim --section taps", {"taps": [1, 2]},
                          first + dt.timedelta(days=2, hours=3)) is None
    text = path.read_text(encoding="utf-8")
    assert text.startswith("# Results: frost bench sim\n")
    assert text.index("# Results") < text.index("Each run") < text.index("## ")
    got = entries(text)
    assert [e["date"] for e in got] == ["2026-11-22 12:05 UTC", "2026-11-20 09:05 UTC"]
    assert [e["command"] for e in got] == ["`frost bench sim --section taps`",
                                           "`frost bench sim --section memory`"]
    assert [e["figures"] for e in got] == [{"taps": [1, 2]}, {"memory": {"mb": 1}}]
    for e in got:
        assert set(FIELDS) <= set(e), e
        assert re.fullmatch(r"[0-9a-f]{4,40}\+?|unknown", e["commit"]), e["commit"]
        assert e["machine"].startswith(f"{results.os.cpu_count()} cores, ")
        assert re.fullmatch(r"(\d+\.\d\d / ){2}\d+\.\d\d|unknown", e["load average (1, 5, 15 min)"])


def test_a_record_goes_above_entries_already_there(tmp_path):
    """A file kept by hand (its own introduction, entries moved from the docs) takes a new
    entry between its introduction and its first entry, the rest untouched."""
    path = tmp_path / "bench-render.md"
    kept = "## frost bench render\n\n- date: 2026-11-21\n\n| a | b |\n| --- | --- |\n| 1 | 2 |\n"
    old = "# Render\n\nWhat this holds.\n\n" + kept
    path.write_text(old, encoding="utf-8")
    assert results.record(path, "frost bench render", {"ticks": 3}) is None
    text = path.read_text(encoding="utf-8")
    assert text.startswith("# Render\n\nWhat this holds.\n\n## ")
    assert text.endswith("\n" + kept)
    assert [e["figures"] for e in entries(text)] == [{"ticks": 3}, None]


def test_the_commit_is_the_checkouts_or_unknown(monkeypatch, tmp_path):
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                          text=True)
    if head.returncode == 0:
        assert results.commit().rstrip("+") == head.stdout.strip()
    monkeypatch.setattr(results, "ROOT", tmp_path)  # no checkout there
    assert results.commit() == "unknown"


def test_the_load_is_unknown_where_the_system_gives_none(monkeypatch):
    monkeypatch.delattr(results.os, "getloadavg")
    assert results.load() == "unknown"


def test_frost_bench_sim_record_keeps_what_it_printed(monkeypatch, tmp_path):
    monkeypatch.setattr(results, "RESULTS", tmp_path)
    status, out, err = run(["bench", "sim", "--quick", "--section", "memory", "--record"])
    assert status == 0, err
    printed = json.loads([line for line in out.splitlines() if line.startswith("{")][-1])
    (kept,) = entries((tmp_path / "bench-sim.md").read_text(encoding="utf-8"))
    assert kept["figures"] == printed and printed["memory"]["crystals"] > 0
    assert kept["command"] == "`frost bench sim --quick --section memory`"  # gives them again


@pytest.mark.parametrize("argv", [["bench", "sim", "--record"], ["bench", "render", "--record"]])
def test_a_record_that_cannot_be_written_is_refused_before_the_run(monkeypatch, tmp_path, argv):
    ran = []
    monkeypatch.setattr(results, "RESULTS", tmp_path / "missing")
    monkeypatch.setattr(simulation, "SECTIONS", {"memory": lambda args: ran.append(args) or {}})
    monkeypatch.setattr("app.bench.render.make_context", lambda: ran.append("context"))
    status, _, err = run(argv)
    assert status == 2 and not ran
    assert err.count("\n") == 1 and f"--record: {tmp_path / 'missing'}: no such folder" in err, err


@pytest.mark.usefixtures("subprocesses")
def test_frost_bench_render_record_keeps_what_it_printed(tmp_path):
    """A short real run (its own process: an EGL context stays out of the test process)."""
    script = ("import sys\nfrom pathlib import Path\nfrom app.bench import results\n"
              "results.RESULTS = Path(sys.argv[1])\nfrom app.cli import main\n"
              "raise SystemExit(main(sys.argv[2:]))")
    argv = ["bench", "render", "--cover", "0.01", "--max-ticks", "3", "--frames", "2", "--record"]
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path), *argv], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    printed = json.loads([line for line in done.stdout.splitlines() if line.startswith("{")][-1])
    (kept,) = entries((tmp_path / "bench-render.md").read_text(encoding="utf-8"))
    assert kept["figures"] == printed and printed["ticks"] <= 3
    assert kept["command"] == ("`frost bench render --preset c-2 --seed 0 --frames 2 "
                               "--cover 0.01 --max-ticks 3`")


def test_the_commit_recorded_is_the_one_the_run_started_on(monkeypatch, tmp_path):
    """A commit made while a benchmark runs (minutes) is not the code that ran."""
    heads = iter(["1a2b3c4", "5d6e7f8"])  # at the start, then at the end
    monkeypatch.setattr(results, "commit", lambda: next(heads))
    monkeypatch.setattr(simulation, "commit", results.commit)
    monkeypatch.setattr(results, "RESULTS", tmp_path)
    monkeypatch.setattr(simulation, "SECTIONS", {"memory": lambda args: {"memory": {"mb": 1}}})
    status, _, err = run(["bench", "sim", "--section", "memory", "--record"])
    assert status == 0, err
    (kept,) = entries((tmp_path / "bench-sim.md").read_text(encoding="utf-8"))
    assert kept["commit"] == "1a2b3c4"


def a_bench(monkeypatch, main) -> None:
    """`python -m bench fake` runs `main(argv, prog=...)`: a benchmark written for the test."""
    module = types.ModuleType("fake_bench")
    module.main = main  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "fake_bench", module)
    monkeypatch.setitem(python_m_bench.BENCHES, "fake", ("fake_bench", "the test's"))


def test_python_m_bench_record_keeps_what_the_benchmark_printed(monkeypatch, tmp_path, capsys):
    """What the benchmark printed is shown as it comes and kept as the entry's text, headed
    by the command that prints it again (no --record), with the commit the run started on."""
    monkeypatch.setattr(results, "RESULTS", tmp_path)
    heads = iter(["1a2b3c4", "5d6e7f8"])  # at the start, then at the end
    monkeypatch.setattr(results, "commit", lambda: next(heads))

    def bench(argv, prog):
        print(f"{prog} with {argv}")
        print("taps: median 41 ms", flush=True)
        return 0

    a_bench(monkeypatch, bench)
    assert python_m_bench.main(["fake", "--taps", "3", "--record"]) == 0
    said = "python -m bench fake with ['--taps', '3']\ntaps: median 41 ms\n"
    assert capsys.readouterr().out == said + f"recorded in {tmp_path / 'bench-fake.md'}\n"
    text = (tmp_path / "bench-fake.md").read_text(encoding="utf-8")
    assert text.startswith("# Results: python -m bench fake\n\nEach run of "
                           "`python -m bench fake --record`")
    (kept,) = entries(text)
    assert kept["command"] == "`python -m bench fake --taps 3`"
    assert kept["printed"] == said.rstrip("\n") and kept["figures"] is None
    assert kept["commit"] == "1a2b3c4" and set(FIELDS) <= set(kept)


@pytest.mark.parametrize("ending", ["status 1", "its command line refused", "--help"])
def test_a_python_m_bench_run_that_fails_keeps_nothing(monkeypatch, tmp_path, ending):
    monkeypatch.setattr(results, "RESULTS", tmp_path)

    def bench(argv, prog):
        print("half a run")
        if ending == "status 1":
            return 1
        raise SystemExit(2 if ending.startswith("its") else 0)

    a_bench(monkeypatch, bench)
    try:
        status = python_m_bench.main(["fake", "--record"])
    except SystemExit as stop:
        status = stop.code
    assert status == {"status 1": 1, "--help": 0}.get(ending, 2)
    assert list(tmp_path.iterdir()) == []


def test_a_python_m_bench_record_that_cannot_be_written_is_refused_before_the_run(
        monkeypatch, tmp_path, capsys):
    ran = []
    monkeypatch.setattr(results, "RESULTS", tmp_path / "missing")
    a_bench(monkeypatch, lambda argv, prog: ran.append(argv) or 0)
    assert python_m_bench.main(["fake", "--record"]) == 2 and ran == []
    err = capsys.readouterr().err
    assert err == (f"python -m bench fake: error: --record: {tmp_path / 'missing'}: no such "
                   "folder (--record writes into a checkout's docs/results/)\n")


@pytest.mark.usefixtures("subprocesses")
def test_python_m_bench_tiles_record_keeps_what_it_printed(tmp_path):
    """A short real run of the tile benchmark, from the checkout as a maintainer runs it."""
    script = ("import sys\nfrom pathlib import Path\nfrom app.bench import results\n"
              "results.RESULTS = Path(sys.argv[1])\nfrom bench.__main__ import main\n"
              "raise SystemExit(main(sys.argv[2:]))")
    argv = ["tiles", "64", "--max-ticks", "40", "--record"]
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path), *argv], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    (kept,) = entries((tmp_path / "bench-tiles.md").read_text(encoding="utf-8"))
    assert kept["command"] == "`python -m bench tiles 64 --max-ticks 40`"
    assert "64x64 window tile: frosted end at tick None (ran 40)" in kept["printed"]
    assert done.stdout == kept["printed"] + f"\nrecorded in {tmp_path / 'bench-tiles.md'}\n"


# ---- the tables of current figures in docs/ against the newest entries -------------------
# A table of figures in docs/ follows a link to its entry in docs/results/
# (`[results](results/FILE.md#ANCHOR)`, in the paragraph before it). The anchor names the
# entry's heading; the newest entry with that heading (the first: entries stand newest
# first) is the one the table must agree with.

DOCS = ROOT / "docs"
RESULTS_LINK = re.compile(r"\]\((results/[\w.-]+\.md)#([^)\s]+)\)")


def anchor(heading: str) -> str:
    """GitHub's anchor of a heading (as tests/test_docs.py works it)."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def linked_tables() -> dict[tuple[str, str], tuple[list[str], list[str]]]:
    """{(the doc's name, the anchor of its results entry, e.g. "results/bench-sim.md#..."):
    (the table's rows, the paragraph's other links)} for every table of docs/*.md whose
    paragraph before links an entry (the first such link in it: others name older entries,
    "and before", which may hold figures the newest leaves out)."""
    found: dict[tuple[str, str], tuple[list[str], list[str]]] = {}
    for doc in sorted(DOCS.glob("*.md")):
        lines = doc.read_text(encoding="utf-8").splitlines()
        i = 0
        while i < len(lines):
            if not (lines[i].startswith("|") and i + 1 < len(lines)
                    and re.match(r"\|\s*-", lines[i + 1])):
                i += 1
                continue
            end = i
            while end < len(lines) and lines[end].startswith("|"):
                end += 1
            k = i - 1
            while k >= 0 and not lines[k].strip():
                k -= 1
            while k >= 0 and lines[k].strip() and not lines[k].startswith(("|", "#")):
                k -= 1
            links = RESULTS_LINK.findall("\n".join(lines[k + 1:i]))
            if links:
                found[(doc.name, "#".join(links[0]))] = (lines[i:end],
                                                         ["#".join(x) for x in links[1:]])
            i = end
    return found


def newest_entry(link: str) -> dict:
    """The newest entry of results file `link`'s heading: its text, and its figures where
    a record wrote them (its JSON block), else None."""
    path, wanted = link.split("#")
    text = (DOCS / path).read_text(encoding="utf-8")
    for block in re.split(r"^## ", text, flags=re.MULTILINE)[1:]:
        if anchor(block.partition("\n")[0]) == wanted:
            figures = re.search(r"```json\n(.*?)\n```", block, flags=re.DOTALL)
            return {"text": block, "figures": json.loads(figures.group(1)) if figures else None}
    raise AssertionError(f"no entry {link}")


def cells(row: str) -> list[str]:
    return [c.strip() for c in row.strip().strip("|").split("|")]


def spaced(n: int) -> str:
    """A whole number as the docs write it: groups of three apart (2 709, 12 345)."""
    return f"{n:,}".replace(",", " ")


def verbatim(rows: list[str], entry: dict, *_older: dict) -> None:
    """An entry kept by hand holds the text of the page then: the table's rows as they are."""
    kept = entry["text"].splitlines()
    assert [r for r in rows if r not in kept] == [], "rows not in the newest entry"


def memory_table(rows: list[str], entry: dict, *_older: dict) -> None:
    """`frost bench sim --section memory --record`'s figures: crystals, array bytes and
    tracemalloc's peak in MB (10^6 bytes, two decimals, as the bench prints them)."""
    m = entry["figures"]["memory"]
    assert cells(rows[2]) == [spaced(m["crystals"]), f"{m['array_bytes'] / 1e6:.2f} MB",
                              f"{m['tracemalloc_peak_bytes'] / 1e6:.2f} MB", "under 5 MB"]


def taps_table(rows: list[str], entry: dict, *_older: dict) -> None:
    """`frost bench sim --section taps --record`'s figures: a row per preset and version,
    one for both versions where they agree; ticks rounded to whole ticks."""
    taps = entry["figures"]["taps"]
    want = []
    for preset in dict.fromkeys(key.split("/")[0] for key in taps):
        v7, v8 = taps[f"{preset}/v7"], taps[f"{preset}/v8"]
        for version, t in ((["7 and 8"], v7),) if v7 == v8 else ((["7"], v7), (["8"], v8)):
            want.append([preset, *version, *(str(round(t[k])) for k in ("median", "p90", "p95",
                                                                          "max")),
                         f"{t['never']} / {t['taps']}"])
    assert [cells(r) for r in rows[2:]] == want


# Entries kept by hand state their figures in prose or in tables of their own; a doc's
# table gives the same figures, formatted its own way (columns dropped, rounds side by side).
NUMBER = re.compile(r"(?<![\w.])\d{1,3}(?: \d{3})+(?![\d.])|(?<![\w.])\d+(?:\.\d+)?")


def numbers(text: str) -> list[str]:
    """The numbers in `text` as written, groups of three joined (2 250 -> 2250)."""
    return [n.replace(" ", "") for n in NUMBER.findall(text)]


def figures(rows: list[str], entry: dict, *older: dict) -> None:
    """Every number in the table's figures (its cells but the first, which names what is
    measured) is one the newest entry states, or an older entry the paragraph links for
    the figures the newest leaves out."""
    stated = set(numbers("".join(e["text"] for e in (entry, *older))))
    missing = [(cells(r)[0], n) for r in rows[2:] for c in cells(r)[1:] for n in numbers(c)
               if n not in stated]
    assert missing == [], "figures in no linked entry"


def entry_rows(entry: dict) -> list[list[str]]:
    return [cells(line) for line in entry["text"].splitlines() if line.startswith("| ")]


def some_columns(rows: list[str], entry: dict, *_older: dict) -> None:
    """Each row is a row of the entry's tables with columns left out: the row whose first
    cell begins with the row's first cell holds the row's other cells, in order."""
    def within(row: list[str], full: list[str]) -> bool:
        rest = iter(full[1:])
        return full[0].startswith(row[0]) and all(c in rest for c in row[1:])
    kept = entry_rows(entry)
    assert [r for r in rows[2:] if not any(within(cells(r), k) for k in kept)] == []


def rounds_table(rows: list[str], entry: dict, *_older: dict) -> None:
    """`python -m bench serve --tick-budget ... --rounds 2`: a row per budget, its rounds
    side by side ("; "), one figure where they agree; p99 to one decimal, tap medians."""
    def each(runs: list[list[str]], f) -> str:
        return "; ".join(dict.fromkeys(f(r) for r in runs))

    def tick(r: list[str]) -> str:
        median, p99 = r[2].split(" / ")
        return f"{median} / {float(p99):.1f}"

    by_budget: dict[str, list[list[str]]] = {}
    for row in entry_rows(entry)[2:]:
        by_budget.setdefault(row[0], []).append(row)
    for row in rows[2:]:
        runs = by_budget[cells(row)[0].split(" (")[0]]
        taps = (each(runs, lambda r: r[6].split(", ")[0]) + ", "
                + each(runs, lambda r: r[6].split(", ")[1].split(" / ")[0]))
        assert cells(row)[1:] == [each(runs, tick), each(runs, lambda r: r[3]),
                                  each(runs, lambda r: r[4]), taps], row


CHECKED = {
    ("benchmarks.md", "results/bench-sim.md#"
     "frost-bench-sim---section-fig9---section-busy---repeats-7"): verbatim,
    ("benchmarks.md", "results/bench-sim.md#frost-bench-sim---section-memory"): memory_table,
    ("benchmarks.md", "results/bench-sim.md#frost-bench-sim---section-abuse"): verbatim,
    ("benchmarks.md", "results/bench-sim.md#frost-bench-sim---section-fern"): verbatim,
    ("benchmarks.md", "results/bench-sim.md#frost-bench-sim---section-taps"): taps_table,
    ("phone-design.md", "results/bench-page.md#frost-bench-page"): verbatim,
    ("benchmarks.md", "results/bench-sim.md#frost-bench-sim---section-growth"): figures,
    ("benchmarks.md", "results/bench-serve.md#"
     "python--m-bench-serve---attack-taps-15---tick-budget-10-7-5"): rounds_table,
    ("benchmarks.md", "results/bench-render.md#frost-bench-render"): figures,
    ("benchmarks.md", "results/bench-render.md#frost-bench-render-and-frost-bench-render---"
     "preset-window---cover-099---max-ticks-2200-quiet-machine"): figures,
    ("benchmarks.md", "results/bench-minute.md#"
     "python--m-bench-minute---samples-15-and-the-same-with---no-page"): some_columns,
    ("benchmarks.md", "results/window-panel.md#the-window-with-the-panel-shown-and-hidden-"
     "the-panels-redraw-part-by-part-the-old-in-window-panel"): figures,
    ("engine-maps.md", "results/bench-tiles.md#python--m-appbenchtiles-2048-and-python--m-"
     "appbenchtiles-4096-and-the-seams-of-the-2048-tile"): some_columns,
    ("looks.md", "results/bench-sim.md#frost-bench-sim---section-window"): figures,
    ("phone-design.md", "results/bench-serve.md#frost-bench-serve"): figures,
    ("phone-design.md", "results/bench-serve.md#frost-bench-serve---attack-all-over-15-and-"
     "--attack-sockets-turns-snapshots-off-the-thread"): some_columns,
    ("phone-design.md", "results/bench-page.md#frost-bench-page---join-8---network-wifi---"
     "taps-24---snapshot-work-7---scribble-60-run-9"): figures,
    ("phone-design.md", "results/bench-page.md#frost-bench-page---phone-app-again"): figures,
    ("phone-design.md", "results/bench-page.md#frost-bench-page---photo-4"): figures,
    ("phone-design.md",
     "results/bench-page.md#python--m-bench-page---local---preset-window---cpu-slowdown-4"): figures,
}
# Tables not yet held to their newest entry (issue 56, item 17), each with the reason.
UNCHECKED: dict[tuple[str, str], str] = {}


def test_every_table_of_figures_in_the_docs_is_checked_or_named():
    """A new table linked to its results entry is checked against it (CHECKED) or named
    (UNCHECKED): none goes unseen. And every link names an entry that is there."""
    tables = linked_tables()
    named = set(CHECKED) | set(UNCHECKED)
    assert set(tables) == named, set(tables) ^ named
    assert not set(CHECKED) & set(UNCHECKED)
    for (_doc, link), (_rows, older) in tables.items():
        for each in (link, *older):
            newest_entry(each)


@pytest.mark.parametrize("key", list(CHECKED), ids=[f"{d}:{a.split('#')[1][:40]}"
                                                   for d, a in CHECKED])
def test_a_table_of_current_figures_is_its_newest_entrys(key):
    rows, older = linked_tables()[key]
    CHECKED[key](rows, newest_entry(key[1]), *map(newest_entry, older))
