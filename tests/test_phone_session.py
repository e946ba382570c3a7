"""A phone's own session (issue 49, item 6): version 13's "source": "phone", checked when
read, kept when written, and replayed by `frost replay` with a line saying it is not bit for
bit."""

from __future__ import annotations

from argparse import Namespace

import pytest

from app.cli.commands import _windowed_replay
from sim import Params
from sim.core.versions import NEWEST, PHONE_VERSION
from sim.io.session import SessionError, SessionLog


def phone_file(version=PHONE_VERSION, **extra) -> dict:
    return {"format": "frost-session", "version": version, "seed": 1, "source": "phone",
            "params": Params.preset("fern").as_dict(), "steps": 100,
            "events": [{"kind": "touch", "tick": 3, "x": 380.0, "y": 640.0},
                       {"kind": "backdrop", "tick": 9, "name": "dusk"}], **extra}


def test_a_phone_file_says_so_and_keeps_it():
    log_ = SessionLog.from_json(phone_file())
    assert log_.source == "phone" and not log_.bit_for_bit()
    assert SessionLog.from_json(log_.as_json()).source == "phone"
    desktop = SessionLog.from_json({**phone_file(), "source": None})
    assert desktop.bit_for_bit() and "source" not in desktop.as_json()
    assert PHONE_VERSION <= NEWEST


@pytest.mark.parametrize("data, problem", [
    (phone_file(source="tablet"), "'source' 'tablet' must be one of phone"),
    (phone_file(source=7), "'source' '7' must be one of phone"),
    (phone_file(version=11), r"'source' needs version 13 or later \(this file is version 11\)"),
])
def test_a_wrong_source_is_refused_in_one_line(data, problem):
    with pytest.raises(SessionError, match=problem):
        SessionLog.from_json(data)


def test_replay_says_a_phone_session_is_not_bit_for_bit(tmp_path, capsys):
    path = SessionLog.from_json(phone_file()).save(tmp_path / "phone.json")
    _windowed_replay(Namespace(replay=str(path), background=None, session_dir=str(tmp_path / "s")))
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "phone" in err and "not bit for bit" in err, err
    desktop = SessionLog.from_json({**phone_file(), "source": None}).save(tmp_path / "desk.json")
    _windowed_replay(Namespace(replay=str(desktop), background=None, session_dir=str(tmp_path / "s")))
    assert capsys.readouterr().err == ""
