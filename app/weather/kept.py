"""The last good reading, kept in the user's config folder (`weather.json` beside the
serve authority's files: app/config.py's `config_dir`) with the place it was asked
for and the time it was read, so a run without a network goes on with it. The file holds
the rounded place and the reading, nothing else."""

from __future__ import annotations

import json
import logging
from datetime import datetime, timezone
from pathlib import Path

from app.config import config_dir
from sim.io.files import why, write_atomic
from sim.weather import Reading

log = logging.getLogger(__name__)
FILE = "weather.json"


def kept_path(folder: Path | None = None) -> Path:
    return (config_dir() if folder is None else Path(folder)) / FILE


def keep(asked: str, reading: Reading, folder: Path | None = None,
         now: datetime | None = None) -> None:
    """Keep `reading` as the last good one for the place `asked` (a failure to write is
    logged in one line: the run goes on without it)."""
    now = now or datetime.now(timezone.utc)
    data = {"asked": asked, "read_at": now.isoformat(timespec="seconds"),
            "reading": reading.as_json()}
    text = json.dumps(data, indent=1).encode("utf-8")
    try:
        write_atomic(kept_path(folder), lambda f: f.write(text))
    except OSError as err:
        log.warning("weather: cannot keep the reading: %s", why(err, kept_path(folder)))


def kept(asked: str, folder: Path | None = None) -> tuple[Reading, str] | None:
    """The reading kept for the place `asked` and when it was read (UTC, ISO 8601); None
    when none is kept for it, or the file cannot be read (said in one line)."""
    path = kept_path(folder)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as err:
        log.warning("weather: the kept reading %s cannot be read: %s", path,
                    why(err, path) if isinstance(err, OSError) else "not JSON")
        return None
    if not isinstance(data, dict) or data.get("asked") != asked:
        return None
    try:
        return Reading.from_json(data.get("reading")), str(data.get("read_at"))
    except ValueError as err:
        log.warning("weather: the kept reading %s is not a reading: %s", path, err)
        return None
