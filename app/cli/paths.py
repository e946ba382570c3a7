"""Path options, checked before any work.

What a run writes at its end (a headless PNG, a figure, the maps) is refused at start-up
when it cannot be written, before the work it would lose; such files and folders may be
missing (they are made on writing) but must be creatable: no name in the path longer
than the file system allows, a picture's name ends in a suffix frost writes (.png, .jpg,
.jpeg), a file may be created in the folder (a file system such as /proc or /sys takes
none: a temporary file is made and removed to know), and an output file that exists is a
regular file (sim.io.files refuses to replace a device, a FIFO or a socket; a symlink is
checked where it leads). The window's folders are checked the same way but only get a
start-up warning: the window reports each failed write and runs on, as the user chose
(tests/test_window_e2e.py runs it so). The session to replay must be a readable file.

A name Windows keeps for a device (CON, PRN, AUX, NUL, COM0-9, LPT0-9 and COM/LPT with a
superscript 1-3; any case, with any extension, with the trailing dots and spaces Windows
strips) anywhere in an output path, the window's folders too, is refused on every system:
a command line that works here must work there, where `CON.png` writes to the console.
"""

from __future__ import annotations

import argparse
import os
import re
from pathlib import Path

from app.cli.shared_options import has_display
from app.images import DEFAULT_FOLDER, suffix_problem
from app.tools.engine_maps import ENGINE_FILES
from sim.io.files import not_regular, one_line, refusal, temp_file

OUTPUT_FILES = ("out",)
OUTPUT_FOLDERS = ("out_dir", "site_dir")
# Files a folder option's command writes under fixed names: checked like an output file.
FOLDER_FILES = {"out_dir": ENGINE_FILES}
WINDOW_FOLDERS = ("screenshot_dir", "session_dir")
# Windows' device names (Microsoft, "Naming Files, Paths, and Namespaces"), in upper case.
RESERVED = frozenset(["CON", "PRN", "AUX", "NUL", *(f"{port}{n}" for port in ("COM", "LPT")
                                                    for n in [*"0123456789", *"\u00b9\u00b2\u00b3"])])
NAME_MAX = 255  # bytes in one name, where the file system does not say (Linux's limit;
# NTFS allows 255 characters)


def check_paths(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[str]:
    """Refuse (ValueError naming the option) an output path of `parser`'s command that
    cannot be written or a replay that cannot be read; return warnings for the window's
    folders (frost serve refuses its --session-dir: the pages it serves cannot show a write
    failing). Folders left at their defaults are the window's to report at run time."""
    warnings = []
    for action in parser._actions:  # this command's own options, not the root's defaults
        reserved = _reserved_option(args, action)
        if reserved:  # (a window's folder too: no system could take the command line then)
            raise ValueError(reserved)
        problem = _option_problem(args, action)
        if problem and action.dest in WINDOW_FOLDERS and not (
                args.command == "serve" and action.dest == "session_dir"):
            warnings.append(f"{problem}; the window will say so at each write")
        elif problem:
            raise ValueError(problem)
    if _writes_default_folder(args):
        problem = _output_problem(DEFAULT_FOLDER, folder=True)
        if problem:
            raise ValueError(f"{DEFAULT_FOLDER} (the PNGs' folder with no --out): {problem}")
    if getattr(args, "replay", None) is not None:
        problem = _replay_problem(Path(args.replay))
        if problem:
            raise ValueError(f"{one_line(args.replay)}: {problem}")
    return warnings


def _option_problem(args: argparse.Namespace, action: argparse.Action) -> str | None:
    """Why the path an output option was given cannot be written, naming the option; None
    if it can, or the option is no output path or was left at its default."""
    name, value = action.dest, getattr(args, action.dest, None)
    if name not in OUTPUT_FILES + OUTPUT_FOLDERS + WINDOW_FOLDERS or value is None \
            or value == action.default:
        return None
    is_file = name in OUTPUT_FILES
    problem = _output_problem(Path(value), folder=not is_file) or \
        (suffix_problem(value) if is_file else None) or \
        _files_problem(Path(value), FOLDER_FILES.get(name, ()))
    return problem and f"{_named(action, value)}: {problem}"


def _reserved_option(args: argparse.Namespace, action: argparse.Action) -> str | None:
    """Why the output path an option was given holds a name Windows keeps for a device,
    naming the option; None if it holds none, or is no output path."""
    value = getattr(args, action.dest, None)
    if action.dest not in OUTPUT_FILES + OUTPUT_FOLDERS + WINDOW_FOLDERS or value is None:
        return None
    problem = reserved_problem(str(value))
    return problem and f"{_named(action, value)}: {problem}"


def reserved_problem(path: str) -> str | None:
    """Why `path` cannot be written on Windows for a name in it that Windows keeps for a
    device (of any part: a folder named AUX cannot be made either), or None. Both slashes
    part a path (Windows takes either)."""
    for part in re.split(r"[\\/]", path):
        # Windows drops a name's trailing dots and spaces, then the device is the part
        # before the first dot (spaces before it dropped too): "nul .txt." is NUL.
        device = part.rstrip(" .").split(".", 1)[0].rstrip(" ").upper()
        if device in RESERVED:
            where = "" if part == path else f"{one_line(part)!r} in it: "
            return (f"{where}Windows keeps the name {device} for a device (in any case, with "
                    "any extension), so no file could be written there: choose another name")
    return None


def _writes_default_folder(args: argparse.Namespace) -> bool:
    """The command renders headless with no --out: render, a replay told to, and the
    window where no display is named (it renders instead)."""
    headless = args.command == "render" or args.command == "replay" and (
        args.headless or args.ticks is not None) or args.command is None and not has_display()
    return headless and args.out is None


def _named(action: argparse.Action, value) -> str:
    """An option and its value as typed (a positional: the value alone)."""
    return one_line(f"{action.option_strings[0]} {value}" if action.option_strings else value)


def _files_problem(folder: Path, files: tuple[str, ...]) -> str | None:
    """Why one of `files` in `folder` cannot be written, naming it; None if all can."""
    for file in files:
        problem = _output_problem(folder / file, folder=False)
        if problem:
            return f"{one_line(file)}: {problem}"
    return None


def _replay_problem(path: Path) -> str | None:
    try:
        kind = not_regular(path)
        if kind or not path.exists():
            return f"is {kind}, not a session file" if kind else "no such file"
        return None if os.access(path, os.R_OK) else "cannot be read"
    except OSError as err:  # a name too long, a loop of symlinks
        return err.strerror or str(err)


def _output_problem(path: Path, folder: bool) -> str | None:
    """Why `path` cannot be written (a folder, or a file when not `folder`), or None."""
    try:
        return _too_long(path) or _writable_problem(Path(os.path.realpath(path)), folder)
    except OSError as err:
        return err.strerror or str(err)


def _writable_problem(path: Path, folder: bool) -> str | None:
    """`path` (symlinks resolved) exists as what it must be and takes new files, or is
    missing and can be made; else why not."""
    if path.exists():
        kind = not_regular(path)
        if folder and kind != "a folder":
            return f"is {kind or 'a file'}, not a folder"
        if not folder and kind:
            return refusal(kind)  # what the write itself would say, before the work
        if not folder and not os.access(path, os.W_OK):
            return "is not writable"
        home = path if folder else path.parent
        problem = _permission_problem(home)
        if problem:
            return problem if folder else f"its folder {home} {problem}"
        return _creates_files(home)
    parent = _existing(path.parent)
    if not parent.is_dir():
        return f"{parent} is a file, not a folder"
    problem = _permission_problem(parent)
    if problem:
        return f"cannot create it: {parent} {problem}"
    return _creates_files(parent)


def _permission_problem(folder: Path) -> str | None:
    """Why the permissions of `folder` let no file be made in it, or None. Both are
    needed: writing it (w) adds the name, searching it (x) reaches the file; a folder
    with w alone (mode 0o200) passes a check of writing only."""
    if not os.access(folder, os.W_OK):
        return "is not writable"
    if not os.access(folder, os.X_OK):
        return "is not searchable (no x permission), so no file can be made in it"
    return None


def _existing(path: Path) -> Path:
    """`path` or the nearest folder above it that exists."""
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def _too_long(path: Path) -> str | None:
    """A name in `path` longer than its file system allows, said; None if none is."""
    try:
        limit = os.pathconf(_existing(path.absolute().parent), "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):  # (AttributeError: Windows has no pathconf)
        limit = NAME_MAX
    longest = max(path.parts, key=lambda part: len(os.fsencode(part)), default="")  # ("." has none)
    size = len(os.fsencode(longest))
    if size > limit:
        return f"a name in it is {size} bytes long; the file system allows {limit}"
    return None


def _creates_files(folder: Path) -> str | None:
    """None if a file can be made in `folder` (made and removed to know), else why not."""
    try:
        fd, probe = temp_file(folder, "frost-probe")
    except OSError as err:
        return f"cannot create files in {folder}: {err.strerror or err}"
    os.close(fd)
    os.unlink(probe)
    return None
