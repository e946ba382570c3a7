"""The command line run in process: its status and what it said on stderr."""

from __future__ import annotations

import contextlib
import io

from app.cli import main


def run_main(argv: list[str]) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except SystemExit as stop:
            status = stop.code
    return status, err.getvalue()


def assert_refused_in_one_line(status, err: str, *words: str) -> None:
    assert status == 2, err
    assert err.count("\n") == 1 and err.startswith("frost: error: "), err
    assert "Traceback" not in err
    for word in words:
        assert word in err, err
