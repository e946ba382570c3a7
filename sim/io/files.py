"""Atomic file writes: the one place every writer of the project (sessions, screenshots,
recordings, frost maps) goes through.

Each file is written to a temporary name in its own folder and renamed over the final
name with os.replace, which is atomic on one file system: a reader (or a crash, a full
disk, Ctrl-C) sees the old file or the whole new one, never half of it.

A rename replaces whatever has the name, so what is not a regular file is refused, never
replaced: a symlink is followed (its target is written beside the target, the link kept);
a device, a FIFO, a socket or a folder in the way is an OSError naming the path. (Writing
through a FIFO could block forever, and through a device would not be atomic.) Every
error names the path the caller gave, never the temporary file.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import secrets
import stat
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

# What a writer returns is ignored (f.write's byte count, say).
Writer = Callable[[BinaryIO], object]


def write_atomic(path, write: Writer) -> Path:
    """`write(file)` fills `path`'s new content; the folder is made if missing."""
    return write_all_atomic({path: write})[0]


def write_all_atomic(writes: dict) -> list[Path]:
    """Several files that appear together: every one is written to a temporary file
    first, and only when all succeeded are they renamed into place. On failure the
    temporary files are removed and the error (OSError, KeyboardInterrupt...) raised."""
    done: list[tuple[str, Path, Path]] = []  # (temporary, target, the caller's path)
    try:
        for path, write in writes.items():
            target = writable_target(path)
            done.append((_write_temp(target, write, path), target, Path(path)))
        for temp, target, path in done:
            _blamed(os.replace, path, temp, target)
    except BaseException:
        for temp, _, _ in done:
            _remove(temp)
        raise
    return [path for _, _, path in done]


def not_regular(path) -> str | None:
    """What `path` is (a symlink: what it points to) when it exists and is not a regular
    file, e.g. "a FIFO"; None when it is one or does not exist."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return None
    if stat.S_ISREG(mode):
        return None
    kinds = {stat.S_ISDIR: "a folder", stat.S_ISCHR: "a character device",
             stat.S_ISBLK: "a block device", stat.S_ISFIFO: "a FIFO", stat.S_ISSOCK: "a socket"}
    return next((kind for test, kind in kinds.items() if test(mode)), "not a regular file")


def writable_target(path) -> Path:
    """The file a write to `path` replaces: `path`, or the file its symlinks lead to.
    OSError naming `path` when that exists and is not a regular file."""
    kind = _blamed(not_regular, path, path)
    if kind:
        raise OSError(errno.EINVAL, refusal(kind), str(path))
    return Path(os.path.realpath(path))


def refusal(kind: str) -> str:
    """Why a file is not written over `kind` (what not_regular said), for a message."""
    if kind == "a folder":
        return "is a folder, not a file"
    return f"is {kind}, not a regular file; frost writes only regular files"


# The most digits a whole number in a file may have: frost's largest (a seed, 2**63 - 1)
# has 19. A longer one is refused by its entry before Python converts it (which takes time
# quadratic in its length, and beyond 4300 digits refuses with a hint meant for programmers).
MOST_DIGITS = 64


class _LongNumber(str):
    """A whole number in a file with more than MOST_DIGITS digits, kept as its text."""


def read_json(path, error: type[Exception]):
    """The JSON held by the file at `path`; `error` (one line naming the file) when it
    cannot be read, is not JSON, or holds a whole number too long to be one of frost's
    (naming its entry)."""
    long_numbers: list[_LongNumber] = []

    def whole_number(text: str) -> int | _LongNumber:
        if len(text.lstrip("-")) <= MOST_DIGITS:
            return int(text)
        long_numbers.append(_LongNumber(text))
        return long_numbers[-1]

    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"), parse_int=whole_number)
    except OSError as err:
        raise error(f"{path}: cannot read: {err.strerror or err}") from None
    except (ValueError, UnicodeDecodeError, RecursionError) as err:  # JSONDecodeError too
        raise error(f"{path}: not JSON: {err}") from None
    found = _long_number(data, "") if long_numbers else None
    if found is not None:
        entry, digits = found
        raise error(f"{path}: entry {entry or 'at the top'}: a whole number of {digits} "
                    f"digits; frost's have at most {MOST_DIGITS}")
    return data


def _long_number(data, entry: str) -> tuple[str, int] | None:
    """(where, digits) of the first _LongNumber in `data` (e.g. "events[3].x"), or None.
    (A stack, not recursion: the file may nest as deep as the parser allows.)"""
    stack = [(entry, data)]
    while stack:
        entry, data = stack.pop()
        if isinstance(data, _LongNumber):
            return entry, len(data.lstrip("-"))
        items = (data.items() if isinstance(data, dict)
                 else enumerate(data) if isinstance(data, list) else ())
        stack.extend(reversed([(_entry(entry, key), value) for key, value in items]))
    return None


def _entry(entry: str, key) -> str:
    return f"{entry}[{key}]" if isinstance(key, int) else f"{entry}.{key}" if entry else key


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


def _write_temp(target: Path, write: Writer, path) -> str:
    """`write` into a new temporary file beside `target` (the caller's `path` resolved)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd, temp = temp_file(target.parent, target.name)
    except OSError as err:  # it names the temporary, which means nothing to the user
        raise _blame(err, path, err.filename) from None
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())  # the bytes are on disk before the rename makes them visible
    except OSError as err:
        _remove(temp)
        raise _blame(err, path, temp, target) from None
    except BaseException:
        _remove(temp)
        raise
    return temp


TEMP_TRIES = 100  # names tried for a temporary before giving up (each taken: 1 in 2**32)


def temp_file(folder, name: str) -> tuple[int, str]:
    """A new temporary file in `folder` for `name` (fd, path), made as open() makes a file:
    0o666 less the umask, the mode the final file keeps. (tempfile.mkstemp's are 0600, and
    changing that on the open file needs os.fchmod, which Windows' Python lacks before 3.13.)
    Its name is kept short: a name near the file system's limit (255 bytes) must still have
    room for a temporary."""
    # O_EXCL: never an existing file, nor a symlink planted under the name.
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(TEMP_TRIES):
        temp = os.path.join(folder, f".{name[:32]}.{secrets.token_hex(4)}.tmp")
        try:
            return os.open(temp, flags, 0o666), temp
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, f"no free temporary name in {TEMP_TRIES} tries", temp)


def _blamed(call, path, *args):
    """call(*args); an OSError it raises names the caller's `path` instead of a
    temporary or resolved name."""
    try:
        return call(*args)
    except OSError as err:
        raise _blame(err, path, *map(str, args)) from None


def _blame(err: OSError, path, *internal) -> OSError:
    if err.filename is None or str(err.filename) in map(str, internal):
        err.filename, err.filename2 = str(path), None
    return err


def _remove(temp: str) -> None:
    with contextlib.suppress(FileNotFoundError):
        os.unlink(temp)
