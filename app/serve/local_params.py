"""The parameters the page's own simulation (app/web/local/) runs by, from their one source:
the presets, defaults and limits of sim/params.py, the hello's fields of app/serve/hello.py,
the drag's spacing and the warm finger's radius of the window. They are written into
app/web/local/params.json, which the page's shell carries (the service worker caches it
with the rest); `python -m app.serve.local_params` writes it again, and
tests/test_local_params.py fails while the file is not what this module makes.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from typing import Any

from app.backdrops import BACKDROPS
from app.keys import BINDINGS, DEFAULT_PRESET
from app.resources import WEB_DIR
from app.serve.controls import KEY_COMMANDS
from app.serve.hello import hello_fields
from sim import Params, all_presets
from sim.io.gestures import DRAG_SPACING_HC, MELT_SPACING
from sim.io.session import FORMAT, VERSION
from sim.look.geometry import FrostGeometry
from sim.screen import MELT_RADIUS, SIZE

FILE = WEB_DIR / "local" / "params.json"
# Presets the page's simulation does not grow: the menu shows them as needing frost serve
# (none: app/web/local/ grows the frosted window too).
SERVER_ONLY: tuple[str, ...] = ()
# Backdrops a phone shows alone: the lock screen's clock is drawn by the server.
SERVER_BACKDROPS = ("lockscreen",)
TICK_RATE = 25  # ticks a second, as the window's and the server's simulation thread


def limits() -> dict[str, dict[str, Any]]:
    """Each parameter's default and allowed range (sim/params.py's field metadata)."""
    out = {}
    for f in dataclasses.fields(Params):
        meta = f.metadata
        choices = meta["choices"]
        out[f.name] = {"default": f.default, "lo": meta["lo"], "hi": meta["hi"],
                       "lo_open": meta["lo_open"],
                       "choices": list(choices) if choices is not None else None}
    return out


def local_params() -> dict[str, Any]:
    """What the page's simulation reads: see the module's doc."""
    default = Params.preset(DEFAULT_PRESET)
    grid = FrostGeometry(default, *SIZE)
    backdrops = [name for name in BACKDROPS if name not in SERVER_BACKDROPS]
    return {
        "default_preset": DEFAULT_PRESET,
        "presets": {name: Params.preset(name).as_dict() for name in all_presets()},
        "server_only": list(SERVER_ONLY),
        "limits": limits(),
        "hello": {**hello_fields(default, backdrops[0], (grid.cols, grid.rows)),
                  "presets": list(all_presets()), "melt_radius": MELT_RADIUS,
                  "backdrops": backdrops},
        "drag_spacing_hc": DRAG_SPACING_HC, "melt_spacing": MELT_SPACING,
        "tick_rate": TICK_RATE,
        # the window's keys that the page's own frost obeys, as frost serve does: name -> command
        "keys": {name: KEY_COMMANDS[b.action] for b in BINDINGS if b.action in KEY_COMMANDS
                 for name in b.keys},
        "session": {"format": FORMAT, "version": VERSION},  # the rules the page grows by
    }


def text() -> str:
    """The file's text: the JSON, indented as the session files are."""
    return json.dumps(local_params(), indent=1) + "\n"


def main() -> int:
    FILE.write_text(text(), encoding="utf-8")
    print(f"wrote {FILE}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

