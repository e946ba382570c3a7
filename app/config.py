"""frost's folder of the user's configuration, where what is kept across runs lives (the
serve token and authority: app/serve/trust.py; the last weather reading: app/weather/kept.py)."""

from __future__ import annotations

import os
import sys
from pathlib import Path


def config_dir(env=None, platform: str | None = None, home: Path | None = None) -> Path:
    """frost's folder of the user's configuration: $XDG_CONFIG_HOME/frost (else
    ~/.config/frost) on Linux and other Unixes, ~/Library/Application Support/frost on
    macOS, %APPDATA%\\frost on Windows."""
    env = os.environ if env is None else env
    platform = sys.platform if platform is None else platform
    home = Path.home() if home is None else home
    if platform == "win32":
        base = env.get("APPDATA")
        return Path(base) / "frost" if base else home / "AppData" / "Roaming" / "frost"
    if platform == "darwin":
        return home / "Library" / "Application Support" / "frost"
    base = env.get("XDG_CONFIG_HOME", "")
    # The XDG rule: a relative path is to be ignored.
    return (Path(base) if base and os.path.isabs(base) else home / ".config") / "frost"
