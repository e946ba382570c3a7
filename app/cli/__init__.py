"""The `frost` command line (also `python -m app`): app.cli.parser says what can be typed,
app.cli.commands runs it."""

from app.cli.commands import main

__all__ = ["main"]
