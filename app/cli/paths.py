"""Path options, checked before any work.

What a run writes at its end (a headless PNG, a figure, the maps) is refused at start-up
when it cannot be written, before the work it would lose; such files and folders may be
missing (they are made on writing) but must be creatable. The window's folders only get a
start-up warning: the window reports each failed write and runs on (a user may never press
S). The session to replay must be a readable file.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from sim.files import one_line

OUTPUT_FILES = ("out",)
OUTPUT_FOLDERS = ("out_dir",)
WINDOW_FOLDERS = ("screenshot_dir", "session_dir")


def check_paths(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[str]:
    """Refuse (ValueError naming the option) an output path of `parser`'s command that
    cannot be written or a replay that cannot be read; return warnings for the window's
    folders. Folders left at their defaults are the window's to report at run time."""
    warnings = []
    for action in parser._actions:  # this command's own options, not the root's defaults
        name, value = action.dest, getattr(args, action.dest, None)
        if name not in OUTPUT_FILES + OUTPUT_FOLDERS + WINDOW_FOLDERS or value is None \
                or value == action.default:
            continue
        problem = _output_problem(Path(value), folder=name not in OUTPUT_FILES)
        message = f"{_named(action, value)}: {problem}"
        if problem and name in WINDOW_FOLDERS:
            warnings.append(f"{message}; the window will say so at each write")
        elif problem:
            raise ValueError(message)
    if getattr(args, "replay", None) is not None:
        path = Path(args.replay)
        if not path.is_file() or not os.access(path, os.R_OK):
            what = "is a folder" if path.is_dir() else "cannot be read" if path.exists() else "no such file"
            raise ValueError(f"{one_line(args.replay)}: {what}")
    return warnings


def _named(action: argparse.Action, value) -> str:
    """An option and its value as typed (a positional: the value alone)."""
    return one_line(f"{action.option_strings[0]} {value}" if action.option_strings else value)


def _output_problem(path: Path, folder: bool) -> str | None:
    """Why `path` cannot be written (a folder, or a file when not `folder`), or None."""
    if path.exists():
        if folder and not path.is_dir():
            return "is a file, not a folder"
        if not folder and path.is_dir():
            return "is a folder, not a file"
        writable = os.access(path, os.W_OK | (os.X_OK if folder else 0))
        return None if writable else "is not writable"
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        return f"{parent} is a file, not a folder"
    if not os.access(parent, os.W_OK | os.X_OK):
        return f"cannot create it: {parent} is not writable"
    return None
