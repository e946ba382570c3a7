"""Parameter sets: the Params of a run saved to a JSON file and read back.

The file holds the parameters as a session file does (`"params"`: every field by name, as
`Params.as_dict` gives it), so a session file is also a parameter set: its first
parameters. The window's panel saves and loads them; `--params FILE` reads one.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..params import Params
from .files import read_json, write_atomic
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
        return _params(data["params"], "'params'")
    except SessionError as err:
        raise ParamsFileError(f"{path}: not a parameter set: {err}") from None
