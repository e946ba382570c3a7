"""Atomic writes never destroy what is not a regular file: a symlink's target is written
and the link kept; a device, a FIFO or a folder in the way is refused, left as it was; every
error names the path the caller gave, never a temporary file."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from sim.io.files import not_regular, why, write_all_atomic, write_atomic


def new(f) -> None:
    f.write(b"new")


def test_a_symlink_is_kept_and_its_target_written(tmp_path):
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "x.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(target)
    assert write_atomic(link, new) == link
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_bytes() == b"new"
    # No temporary left beside the link or the target.
    assert sorted(os.listdir(tmp_path)) == ["link.png", "real"]
    assert os.listdir(tmp_path / "real") == ["x.png"]


def test_a_dangling_symlink_makes_its_target(tmp_path):
    link = tmp_path / "link.png"
    link.symlink_to(tmp_path / "made" / "x.png")
    write_atomic(link, new)
    assert link.is_symlink() and (tmp_path / "made" / "x.png").read_bytes() == b"new"


def fifo(path: Path) -> None:
    os.mkfifo(path)


def char_device(path: Path) -> None:
    if os.geteuid() != 0:
        pytest.skip("making a device node needs root")
    os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))  # a copy of /dev/null


NODES = {"a FIFO": (fifo, stat.S_ISFIFO), "a character device": (char_device, stat.S_ISCHR),
         "a folder": (Path.mkdir, stat.S_ISDIR)}


@pytest.mark.parametrize("kind", list(NODES))
@pytest.mark.parametrize("through_link", [False, True])
def test_what_is_not_a_regular_file_is_refused_and_left_as_it_was(tmp_path, kind, through_link):
    make, is_kind = NODES[kind]
    node = tmp_path / "node"
    make(node)
    path = node
    if through_link:
        path = tmp_path / "link"
        path.symlink_to(node)
    with pytest.raises(OSError) as refused:
        write_atomic(path, new)
    assert is_kind(os.lstat(node).st_mode)  # still there, not replaced by a file
    assert path.is_symlink() == through_link
    assert sorted(os.listdir(tmp_path)) == sorted({"node", path.name})  # no temporary left
    message = why(refused.value)
    assert message.startswith(f"{path}: ") and kind in message and "\n" not in message


def test_a_set_with_one_fifo_writes_none(tmp_path):
    os.mkfifo(tmp_path / "b.png")
    with pytest.raises(OSError, match="FIFO"):
        write_all_atomic({tmp_path / "a.png": new, tmp_path / "b.png": new})
    assert os.listdir(tmp_path) == ["b.png"]


def test_not_regular_names_each_kind(tmp_path):
    os.mkfifo(tmp_path / "f")
    (tmp_path / "r").write_text("", encoding="utf-8")
    (tmp_path / "l").symlink_to(tmp_path / "f")
    assert not_regular(tmp_path / "f") == not_regular(tmp_path / "l") == "a FIFO"
    assert not_regular(tmp_path / "r") is None and not_regular(tmp_path / "missing") is None
    assert not_regular(tmp_path) == "a folder"


def test_a_name_at_the_file_systems_limit_still_has_room_for_its_temporary(tmp_path):
    longest = os.pathconf(tmp_path, "PC_NAME_MAX")
    path = tmp_path / ("n" * (longest - 4) + ".png")
    write_atomic(path, new)
    assert path.read_bytes() == b"new" and os.listdir(tmp_path) == [path.name]


def test_a_name_too_long_is_an_oserror_naming_it(tmp_path):
    path = tmp_path / ("n" * 300 + ".png")
    with pytest.raises(OSError) as refused:
        write_atomic(path, new)
    assert refused.value.filename == str(path) and os.listdir(tmp_path) == []


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc")
def test_an_error_names_the_callers_path_not_the_temporary():
    path = "/proc/frost-test-x.png"  # /proc takes no new files
    with pytest.raises(OSError) as refused:
        write_atomic(path, new)
    assert refused.value.filename == path and refused.value.filename2 is None
    assert ".tmp" not in why(refused.value)


def test_a_file_another_program_holds_is_one_line_not_a_traceback(monkeypatch, capsys, tmp_path):
    """Windows refuses to replace a file another program holds open (PermissionError on
    os.replace): the command says so in one line."""
    import os

    from app.cli import main

    def held(_src, dst):
        raise PermissionError(13, "The process cannot access the file because it is being "
                                  "used by another process", str(dst))

    monkeypatch.setattr(os, "replace", held)
    status = main(["render", "--ticks", "2", "--touch", "380,640", "--out",
                   str(tmp_path / "held.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and "being used by another process" in err[0], err
    assert err[0].startswith("frost: error: cannot write ") and "Traceback" not in err[0]


@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002], ids=oct)
def test_a_file_is_written_without_fchmod_with_the_mode_open_gives(monkeypatch, tmp_path, umask):
    """Windows' Python before 3.13 has no os.fchmod: a write needs none, and the file gets
    what open() would give it under the umask of the moment (0o666 less it)."""
    monkeypatch.delattr(os, "fchmod")
    old = os.umask(umask)
    try:
        write_atomic(tmp_path / "w.png", new)
        with open(tmp_path / "by-open", "wb"):
            pass
    finally:
        os.umask(old)
    assert (tmp_path / "w.png").read_bytes() == b"new"
    modes = {p.name: oct(p.stat().st_mode & 0o777) for p in tmp_path.iterdir()}
    assert modes == {"w.png": oct(0o666 & ~umask), "by-open": oct(0o666 & ~umask)}
