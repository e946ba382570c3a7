"""Atomic file writes: the one place every writer of the project (sessions, screenshots,
recordings, frost maps) goes through.

Each file is written to a temporary name in its own folder and renamed over the final
name with os.replace, which is atomic on one file system: a reader (or a crash, a full
disk, Ctrl-C) sees the old file or the whole new one, never half of it.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

# What a writer returns is ignored (f.write's byte count, say).
Writer = Callable[[BinaryIO], object]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# mkstemp makes 0600 files; the final files get what open() would give them.
FILE_MODE = 0o666 & ~_umask()


def write_atomic(path, write: Writer) -> Path:
    """`write(file)` fills `path`'s new content; the folder is made if missing."""
    return write_all_atomic({path: write})[0]


def write_all_atomic(writes: dict) -> list[Path]:
    """Several files that appear together: every one is written to a temporary file
    first, and only when all succeeded are they renamed into place. On failure the
    temporary files are removed and the error (OSError, KeyboardInterrupt...) raised."""
    done: list[tuple[str, Path]] = []
    try:
        for path, write in writes.items():
            done.append((_write_temp(Path(path), write), Path(path)))
        for temp, path in done:
            os.replace(temp, path)
    except BaseException:
        for temp, _ in done:
            _remove(temp)
        raise
    return [path for _, path in done]


def one_line(text: str) -> str:
    """`text` as one line for a message: a character that is not printable (a newline, a
    carriage return, an escape) is written as its Python escape, everything else kept. A
    path or a key that a user typed may hold such characters; the message stays one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


def why(err: OSError, path=None) -> str:
    """An OSError in one line for the user: the path (the error's own, else `path`, the
    file being written) and the reason."""
    reason = err.strerror or str(err)
    if isinstance(err, (FileExistsError, NotADirectoryError)):
        reason = "a file is in the way where a folder must be"
    name = err.filename or path
    return one_line(f"{name}: {reason}" if name else reason)


def _write_temp(path: Path, write: Writer) -> str:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, temp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            os.fchmod(f.fileno(), FILE_MODE)
            write(f)
            f.flush()
            os.fsync(f.fileno())  # the bytes are on disk before the rename makes them visible
    except BaseException:
        _remove(temp)
        raise
    return temp


def _remove(temp: str) -> None:
    with contextlib.suppress(FileNotFoundError):
        os.unlink(temp)
