"""The parameters the page's own simulation (app/web/local/) runs by, from their one source:
the presets, defaults and limits of sim/params.py, the hello's fields of app/serve/hello.py,
the drag's spacing and the warm finger's radius of the window. They are written into
app/web/local/params.json, which the page's shell carries (the service worker caches it
with the rest); `python -m app.serve.local_params` writes it again, and
tests/test_local_params.py fails while the file is not what this module makes.

The numbers the page's JavaScript shares with sim/ and frost serve (the budgets, the
supply's draws, the pending-touch bound, the tick rate, the glass model's constants) are
written beside it as app/web/local/shared.js, one `export const` each, from the Python
constants themselves: the page's modules import them from there, and no copy is typed by
hand (tests/test_local_params.py fails on one).
"""

from __future__ import annotations

import dataclasses
import json
import sys
from typing import Any

from app.backdrops import BACKDROPS
from app.keys import BINDINGS, DEFAULT_PRESET
from app.lockscreen import CLOCK_BOX, CLOCK_LINES
from app.resources import WEB_DIR
from app.serve.controls import KEY_COMMANDS
from app.serve.hello import hello_fields
from app.serve.turns import PAGE_WAITING
from sim import Params, all_presets
from sim.core import budget, placement, supply
from sim.core.versions import REGROW_GAP
from sim.io.gestures import DRAG_SPACING_HC, MELT_SPACING
from sim.io.session import FORMAT, VERSION
from sim.look.geometry import FrostGeometry
from sim.screen import MAX_MELT_RADIUS, MELT_RADIUS, SIZE, TICKS_PER_SECOND
from sim.weather import glass

FILE = WEB_DIR / "local" / "params.json"
SHARED = WEB_DIR / "local" / "shared.js"
# Presets the page's simulation does not grow: the menu shows them as needing frost serve
# (none: app/web/local/ grows the frosted window too).
SERVER_ONLY: tuple[str, ...] = ()
# Backdrops a phone cannot show alone (none: with no server the page draws the lock screen's
# clock box itself, app/web/lockclock.js).
SERVER_BACKDROPS: tuple[str, ...] = ()
TICK_RATE = TICKS_PER_SECOND  # ticks a second, as the window's and the server's simulation thread


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
        # the window's keys that the page's own frost obeys, as frost serve does: name -> command
        "keys": {name: KEY_COMMANDS[b.action] for b in BINDINGS if b.action in KEY_COMMANDS
                 for name in b.keys},
        "session": {"format": FORMAT, "version": VERSION},  # the rules the page grows by
    }


def text() -> str:
    """The file's text: the JSON, indented as the session files are."""
    return json.dumps(local_params(), indent=1) + "\n"


def shared_numbers() -> dict[str, tuple[Any, str]]:
    """The numbers shared.js exports: name -> (value, where it comes from)."""
    return {
        "CELL_CAP": (budget.CELL_CAP, "sim/core/budget.py: crystals a cell may list"),
        "FREEZE_WORK": (budget.FREEZE_WORK, "sim/core/budget.py: grid-vertex raises of freezes a tick"),
        "CELL_TRIES": (placement.CELL_TRIES, "sim/core/placement.py: draws among an area's free cells"),
        "CELL_WORK": (placement.CELL_WORK, "sim/core/placement.py: walkers placed from cells a tick"),
        "BARE_DRAWS": (placement.BARE_DRAWS, "sim/core/placement.py: draws that show a disc has no glass"),
        "GLASS_TRIES": (placement.GLASS_TRIES, "sim/core/placement.py: draws for a spot on open glass"),
        "TOUCH_TRIES": (supply.TOUCH_TRIES, "sim/core/supply.py: draws for each walker of a touch's ring"),
        "REGROW_GAP": (REGROW_GAP, "sim/core/versions.py: the longest pause a rebuild keeps"),
        "PENDING_MOST": (PAGE_WAITING, "app/serve/turns.py: a page's commands waiting their turn"),
        "MAX_MELT_RADIUS": (MAX_MELT_RADIUS, "sim/screen.py: px"),
        "TICK_RATE": (TICK_RATE, "sim/screen.py: ticks a second"),
        "TICK_MS": (1000 / TICK_RATE, "ms between two ticks"),
        "THAW_TICKS": (glass.THAW_TICKS, "sim/weather/glass.py: ticks between two thaw layers"),
        "R_SI": (glass.R_SI, "sim/weather/glass.py: the inner surface's resistance, m2K/W"),
        "U_VALUES": (glass.U_VALUES, "sim/weather/glass.py: W/m2K of each glazing"),
        "ROOM_C": (glass.ROOM_C, "sim/weather/glass.py: the room's air, C"),
        "ROOM_HUMIDITY": (glass.ROOM_HUMIDITY, "sim/weather/glass.py: the room's humidity, %"),
        "ROOM_C_RANGE": (glass.ROOM_C_RANGE, "sim/weather/glass.py"),
        "ROOM_HUMIDITY_RANGE": (glass.ROOM_HUMIDITY_RANGE, "sim/weather/glass.py"),
        "E0": (glass.E0, "sim/weather/glass.py: Magnus, hPa"),
        "WATER": (glass.WATER, "sim/weather/glass.py: Magnus's a, b over water"),
        "ICE": (glass.ICE, "sim/weather/glass.py: Magnus's a, b over ice"),
        "LEAST_UNDERCOOLING": (glass.LEAST_UNDERCOOLING, "sim/weather/glass.py"),
        "MOST_UNDERCOOLING": (glass.MOST_UNDERCOOLING, "sim/weather/glass.py"),
        "SUPPLY_RANGE": (glass.SUPPLY_RANGE, "sim/weather/glass.py: the supply's bounds"),
        "CLOCK_BOX": (CLOCK_BOX, "app/lockscreen.py: the lock screen's clock box, x0 y0 x1 y1 px"),
        "CLOCK_LINES": (CLOCK_LINES, "app/lockscreen.py: each line's centre and size, px"),
    }


def shared_text() -> str:
    """shared.js's text: a header saying it is generated, then one export a number."""
    lines = ["// GENERATED by app/serve/local_params.py (python -m app.serve.local_params): do not",
             "// edit. The numbers the page's own frost shares with sim/ and frost serve, each",
             "// from its Python constant (docs/local-sim.md); tests/test_local_params.py fails",
             "// while this file is not what that module writes, and on a copy typed elsewhere.",
             ""]
    for name, (value, source) in shared_numbers().items():
        lines.append(f"export const {name} = {_js(value)};  // {source}")
    return "\n".join(lines) + "\n"


def _js(value: Any) -> str:
    """`value` as a JS literal: tuples as frozen arrays, dicts as frozen objects."""
    if isinstance(value, tuple):
        return f"Object.freeze({json.dumps(list(value))})"
    if isinstance(value, dict):
        return f"Object.freeze({json.dumps(value)})"
    return json.dumps(value)


def main() -> int:
    FILE.write_text(text(), encoding="utf-8")
    SHARED.write_text(shared_text(), encoding="utf-8")
    print(f"wrote {FILE} and {SHARED}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

