"""Key bindings: one table drives the window's key handler, its help overlay (H) and
`frost --help`, and what a page's keys do (`app.serve.controls`), so it lies outside both.

Keys are GLFW key names without the `KEY_` prefix, so this module needs no GLFW;
`app.window.actions` resolves them to key codes. An action is a name in the window's
action dispatch table; `arg` is passed to it unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sim import PRESETS
from sim.screen import HEIGHT, WIDTH
from sim.tuning import BUMP_STEP, HUMIDITY_FACTOR, LENGTH_STEP, TEMPERATURE_STEP


@dataclass(frozen=True)
class Binding:
    keys: tuple[str, ...]  # GLFW key names, e.g. ("SPACE",) or ("N", "PERIOD")
    label: str  # how the help overlay names the keys
    description: str
    action: str
    arg: Any = None


# The light's direction moves this far on the screen plane per key press.
LIGHT_STEP = 0.1


# The demo's default look (window frost's fronds, docs/method.md), one key from Table 1.
DEFAULT_PRESET = "fern"


def _preset_bindings() -> tuple[Binding, ...]:
    table = tuple(Binding((str(i),), str(i), f"preset {name} (Table 1)", "preset", name)
                  for i, name in enumerate(PRESETS, start=1))
    return (*table, Binding(("0",), "0", "preset fern (window frost: fronds; the default)",
                            "preset", DEFAULT_PRESET))


BINDINGS: tuple[Binding, ...] = (
    Binding(("SPACE",), "Space", "pause / resume the simulation", "pause"),
    Binding(("N", "PERIOD"), "N .", "one tick while paused", "single_step"),
    Binding(("C",), "C", "clear the frost (and the touches)", "clear"),
    Binding(("S", "F12"), "S F12", f"screenshot ({WIDTH}x{HEIGHT} PNG)", "screenshot"),
    # (the recording's own figures are docs/window.md's: the window's, not the page's)
    Binding(("R",), "R", "record on / off (animated WebP, written when R stops it)", "record"),
    Binding(("E",), "E", "export frost maps (height, normal, alpha PNGs)", "export_maps"),
    Binding(("EQUAL", "KP_ADD"), "=", f"humidity up (x{HUMIDITY_FACTOR})", "scale",
            ("humidity", HUMIDITY_FACTOR)),
    Binding(("MINUS", "KP_SUBTRACT"), "-", f"humidity down (/{HUMIDITY_FACTOR})", "scale",
            ("humidity", 1.0 / HUMIDITY_FACTOR)),
    Binding(("RIGHT_BRACKET",), "]", f"hc up ({LENGTH_STEP} px)", "shift", ("hc", LENGTH_STEP)),
    Binding(("LEFT_BRACKET",), "[", f"hc down ({LENGTH_STEP} px)", "shift", ("hc", -LENGTH_STEP)),
    Binding(("APOSTROPHE",), "'", f"D up ({LENGTH_STEP} px)", "shift", ("D", LENGTH_STEP)),
    Binding(("SEMICOLON",), ";", f"D down ({LENGTH_STEP} px)", "shift", ("D", -LENGTH_STEP)),
    Binding(("P",), "P", f"step up ({LENGTH_STEP} px)", "shift", ("step", LENGTH_STEP)),
    Binding(("O",), "O", f"step down ({LENGTH_STEP} px)", "shift", ("step", -LENGTH_STEP)),
    Binding(("L",), "L", f"bump up ({BUMP_STEP} px)", "shift", ("bump", BUMP_STEP)),
    Binding(("K",), "K", f"bump down ({BUMP_STEP} px)", "shift", ("bump", -BUMP_STEP)),
    *_preset_bindings(),
    Binding(("G",), "G", "growth mode on / off (frost keeps spreading)", "toggle_param", "grow"),
    Binding(("W",), "W", "preset window (frost grows in from the frame; 0 goes back)", "preset",
            "window"),
    Binding(("T",), "T", f"window: colder ({TEMPERATURE_STEP:g} C): faster, denser frost", "shift",
            ("temperature", TEMPERATURE_STEP)),
    Binding(("Y",), "Y", f"window: warmer ({TEMPERATURE_STEP:g} C)", "shift",
            ("temperature", -TEMPERATURE_STEP)),
    Binding(("V",), "V", "look: paper / glass (ridges, film, glints, refraction)", "cycle_param",
            "look"),
    Binding(("X",), "X", "backdrop: dusk, lockscreen (then the --background file)", "backdrop"),
    Binding(("F",), "F", "sharp features on / off", "toggle_view", "show_features"),
    Binding(("B",), "B", "bumpy surfaces on / off", "toggle_view", "show_bumps"),
    Binding(("LEFT",), "Left", "light from further left", "light", (-LIGHT_STEP, 0.0)),
    Binding(("RIGHT",), "Right", "light from further right", "light", (LIGHT_STEP, 0.0)),
    Binding(("UP",), "Up", "light from further up", "light", (0.0, -LIGHT_STEP)),
    Binding(("DOWN",), "Down", "light from further down", "light", (0.0, LIGHT_STEP)),
    Binding(("M", "F1"), "M F1", "tuning panel on / off, a window beside the phone (sliders, "
            "presets, sets; off at start)", "toggle_panel"),
    Binding(("TAB", "U"), "Tab U", "HUD on / off", "toggle_hud"),
    Binding(("H",), "H", "this help on / off", "toggle_help"),
    Binding(("ESCAPE",), "Esc", "quit", "quit"),
)


def key_table(resolve) -> dict[int, Binding]:
    """{key code: binding}; `resolve` maps a key name to its code (e.g. GLFW's)."""
    table: dict[int, Binding] = {}
    for binding in BINDINGS:
        for name in binding.keys:
            code = resolve(name)
            if code in table:
                raise ValueError(f"key {name} is bound twice")
            table[code] = binding
    return table


def help_lines(sep: str | None = None) -> list[str]:
    """The help text, one line per binding; `sep` (e.g. a tab) instead of padding."""
    width = max(len(b.label) for b in BINDINGS)
    if sep is not None:
        return [f"{b.label}{sep}{b.description}" for b in BINDINGS]
    return [f"{b.label:<{width}}  {b.description}" for b in BINDINGS]
