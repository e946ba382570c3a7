"""Parameter sets: the Params of a run saved to a JSON file and read back.

The file holds the parameters as a session file does (`"params"`: every field by name, as
`Params.as_dict` gives it), so a session file is also a parameter set: its first
parameters. The window's panel saves and loads them; `--params FILE` reads one.

A set names every parameter: one left out is refused, never filled from a default (a set
means the frost it describes, whatever the defaults become). A session file's parameters
may lack those newer than the file: they replay with the rules of its time, off.
"""

from __future__ import annotations

import json
from dataclasses import fields
from pathlib import Path

from ..params import Params
from .files import read_json, write_atomic
from .session import FORMAT as SESSION_FORMAT
from .session import SessionError, _params

FORMAT = "frost-params"
VERSION = 1


class ParamsFileError(SessionError):
    """A parameter set that cannot be read; its message is one line naming the file."""


def save_params(path, params: Params) -> Path:
    """Write `params` to `path` atomically (the old file or the whole new one)."""
    data = {"format": FORMAT, "version": VERSION, "params": params.as_dict()}
    text = json.dumps(data, indent=1).encode()
    return write_atomic(path, lambda f: f.write(text))


def load_params(path) -> Params:
    """The Params in `path` (a parameter set or a session file); ParamsFileError naming the
    file and the first problem: unreadable, not JSON, no params, a bad or unknown value."""
    data = read_json(path, ParamsFileError)
    if not isinstance(data, dict) or "params" not in data:
        raise ParamsFileError(f"{path}: not a parameter set: no 'params' entry")
    try:
        params = _params(data["params"], "'params'")
    except SessionError as err:
        raise ParamsFileError(f"{path}: not a parameter set: {err}") from None
    missing = [f.name for f in fields(Params) if f.name not in data["params"]]
    if missing and data.get("format") != SESSION_FORMAT:
        more = f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""
        raise ParamsFileError(f"{path}: not a parameter set: 'params' has no {missing[0]!r} "
                              f"entry{more}; a set names every parameter (the panel's Save "
                              "set writes one)")
    return params
