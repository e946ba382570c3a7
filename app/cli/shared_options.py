"""Options several `frost` commands share, each defined once and attached to the
parsers (or argument groups: the `p` of each add_*) that need it, and the Params a
parsed command line asks for."""

from __future__ import annotations

import argparse
import functools
import os

from app.backdrops import BACKDROPS, DEFAULT_BACKDROP
from app.cli import values
from app.keys import DEFAULT_PRESET
from app.lockscreen import DEFAULT_MINUTE
from app.weather import EVERY_MIN, FORECAST_API, GEOCODING_API, LEAST_EVERY_MIN
from app.window.view import SCALES
from sim import PRESETS, Params, all_presets
from sim.io.paramsets import load_params
from sim.screen import HEIGHT, MAX_MELT_RADIUS, MELT_RADIUS, WIDTH
from sim.weather import GLAZINGS
from sim.weather.glass import ROOM_C, ROOM_C_RANGE, ROOM_HUMIDITY, ROOM_HUMIDITY_RANGE

DEFAULT_TICKS = 250
# The window's options and their defaults; a replay told to render headless refuses them.
WINDOW_DEFAULTS = {"melt_radius": MELT_RADIUS, "session_dir": "sessions", "screenshot_dir": "screenshots",
                   "scale": None, "max_seconds": None}
# `--window-frost` turns the window preset on; an override of the same name would shadow it.
NOT_OVERRIDES = ("window_frost",)
PLANT = "plant a seed crystal at tick 0 (repeatable)"


def add_preset(p) -> None:
    p.add_argument("--preset", choices=list(all_presets()), metavar="NAME",
                   help=f"parameter set: Table 1's a-1 ... c-3, fern or window (default "
                        f"{DEFAULT_PRESET}: window frost's fronds)")
    p.add_argument("--window-frost", dest="window_mode", action="store_true",
                   help="the frosted window: frost nucleates on the screen's frame and a few pane "
                        "sites and grows over the whole pane, no touch needed (preset window, or "
                        "window mode on top of --preset, whose grains it turns on; default off)")
    add_params(p, "used instead of a preset")


# What each command does with --params FILE (a set saved from the panel, or a session).
SET_FILE = ("a parameter set, a JSON file saved from the window's panel (or a session file: "
            "its first parameters)")
FIGURE8_SET = ("its fields other than Table 1's D, hc and humidity (and step, which each preset "
               "fits to its hc) apply on top of each of the nine presets: Fig. 8 under the "
               "set's walkers, rules and look")
REPLAY_SET = ("a what-if replay: the session's touches, melts and clears under the set's "
              "parameters; each parameter change of the session becomes the set again (with the "
              "change's look), so its rebuilds fall where they fell; the log says so")


def add_params(p, what: str, overrides: bool = True) -> None:
    on_top = "; the overrides apply on top" if overrides else ""
    p.add_argument("--params", dest="params_file", metavar="FILE.json",
                   help=f"{SET_FILE}: {what}{on_top} (default none)")


def add_background(p) -> None:
    p.add_argument("--background", type=values.backdrop, metavar="NAME|FILE",
                   help=f"the view behind the glass: {' or '.join(BACKDROPS)} (built in), or a PNG "
                        f"or JPEG file, scaled to cover {WIDTH}x{HEIGHT} and centre-cropped "
                        f"(default {DEFAULT_BACKDROP}; a replay: the session's)")


def add_seed(p) -> None:
    p.add_argument("--seed", type=values.seed, default=0, metavar="N",
                   help="random seed, a whole number (default 0)")


def add_touch(p, what: str, default: str, kind=values.touch, where: str = "") -> None:
    where = where or f"0 <= X < {WIDTH}, 0 <= Y < {HEIGHT}"
    p.add_argument("--touch", type=kind, action="append", default=[], metavar="X,Y",
                   help=f"{what}: X,Y in px, {where} (default {default})")


def add_out(p, demo: bool = False) -> None:
    also = ("; the scripted demo writes its stages' PNGs beside it, by default "
            "frost-out/frost-demo-TIME-pPID-tickNNNN.png") if demo else ""
    p.add_argument("--out", metavar="FILE.png",
                   help="write the final frame here, PNG or JPEG by the suffix (.png, .jpg, .jpeg; "
                        "default frost-out/frost-TIME-pPID.png, named by the time and the "
                        f"process{also})")


def add_ticks(p, default: int | None, what: str) -> None:
    shown = "as recorded" if default is None else default
    p.add_argument("--ticks", type=values.whole, default=default, metavar="N",
                   help=f"{what}, ticks at 25 a second (default {shown})")


def add_melt_radius(p, what: str) -> None:
    p.add_argument("--melt-radius", type=values.radius, default=WINDOW_DEFAULTS["melt_radius"],
                   metavar="PX", help=f"radius of the warm finger ({what}), px, at most "
                                      f"{MAX_MELT_RADIUS:g} (default 24)")


def add_melts(p) -> None:
    p.add_argument("--melt", type=values.melt, action="append", default=[], metavar="X,Y[,R]@TICK",
                   help="a warm finger melts the ice within R px (default --melt-radius) of X,Y px "
                        "just before step TICK + 1 (repeatable; default none)")
    p.add_argument("--melt-path", type=values.melt_path, action="append", default=[],
                   metavar="X1,Y1:X2,Y2[:...]@TICK",
                   help="melt along a polyline (px) at TICK, a melt every half radius "
                        "(repeatable; default none)")
    add_melt_radius(p, "--melt, --melt-path")


def add_window(p) -> None:
    """The window's folders, size and lifetime."""
    add_melt_radius(p, "right-button drag")
    p.add_argument("--session-dir", default=WINDOW_DEFAULTS["session_dir"], metavar="DIR",
                   help="folder for the session files written on exit (when there was an "
                        "event to replay) and with each screenshot (default sessions)")
    p.add_argument("--screenshot-dir", default=WINDOW_DEFAULTS["screenshot_dir"], metavar="DIR",
                   help="folder for screenshots (S, F12) and recordings (R) (default screenshots)")
    p.add_argument("--scale", type=values.scale, metavar="F",
                   help=f"window size as a fraction of {WIDTH}x{HEIGHT}, {SCALES[0]:g} to "
                        f"{SCALES[1]:g} (default: fit the monitor)")
    p.add_argument("--max-seconds", type=values.seconds, metavar="S",
                   help="close by itself after S seconds, exit status 0 (default: stay open)")


def add_clock_start(p) -> None:
    """The live clock's start (the window, frost serve): for demos and tests."""
    p.add_argument("--clock-start", type=values.clock, metavar="TIME",
                   help="for demos and tests: the lock screen's clock reads TIME (HH:MM[:SS] on "
                        f"{DEFAULT_MINUTE[:10]}, or YYYY-MM-DDTHH:MM[:SS]) at the start and runs "
                        "on in real time from there (default: this machine's local time)")


def add_clock(p) -> None:
    p.add_argument("--clock", type=values.clock, metavar="TIME",
                   help="the minute the lock screen's clock shows (--background lockscreen): "
                        f"HH:MM (on {DEFAULT_MINUTE[:10]}) or YYYY-MM-DDTHH:MM (default "
                        f"{DEFAULT_MINUTE[11:]} on {DEFAULT_MINUTE[:10]}, a Thursday: a render is "
                        "the same every time)")


def add_weather(p, what: str) -> None:
    """The weather outside (docs/method.md, section 12): where, from which APIs, how often,
    and the window it acts on. `what`: when the command reads it."""
    g = p.add_argument_group("the weather outside (docs/command-line.md)")
    g.add_argument("--weather", type=values.place, metavar="PLACE",
                   help="grow the frost by the weather at PLACE: LAT,LON or a place's name (looked "
                        f"up, first match); {what} (default off: the preset's temperature)")
    add_weather_apis(g)
    g.add_argument("--glazing", choices=GLAZINGS, default="single", metavar="|".join(GLAZINGS),
                   help="the window's glass: old single glazing (U 5.8 W/m2K) or double (2.8) "
                        "(default single)")
    lo, hi = ROOM_C_RANGE
    g.add_argument("--room-temperature", type=lambda t: values.within(t, lo, hi, "room temperature"),
                   default=ROOM_C, metavar="C",
                   help=f"the room's air behind the glass, degrees C, {lo:g} to {hi:g} (default {ROOM_C:g})")
    lo, hi = ROOM_HUMIDITY_RANGE
    g.add_argument("--room-humidity", type=lambda t: values.within(t, lo, hi, "room humidity"),
                   default=ROOM_HUMIDITY, metavar="PCT",
                   help=f"the room's relative humidity, %%, {lo:g} to {hi:g} (default "
                        f"{ROOM_HUMIDITY:g}: a dew point of 6 C)")


def add_weather_apis(g, whose: str = "") -> None:
    """--weather-api and --geocoding-api (`whose`: who asks them, said in the help)."""
    g.add_argument("--weather-api", type=values.url, default=FORECAST_API, metavar="URL",
                   help=f"the forecast API{whose} (Open-Meteo's or a mirror; default {FORECAST_API})")
    g.add_argument("--geocoding-api", type=values.url, default=GEOCODING_API, metavar="URL",
                   help=f"the geocoding API for a place's name{whose} (default {GEOCODING_API})")


def add_weather_every(p) -> None:
    """How often a run that goes on reads the weather again (the window, frost serve)."""
    p.add_argument("--weather-every", default=EVERY_MIN, metavar="MIN",
                   type=lambda t: values.within(t, LEAST_EVERY_MIN, 24 * 60.0, "--weather-every"),
                   help=f"with --weather: minutes between readings, at least {LEAST_EVERY_MIN:g} "
                        f"(default {EVERY_MIN:g})")


def add_overrides(p, looks: tuple[str, ...] = (DEFAULT_PRESET, "window")) -> None:
    """One option per simulation parameter (see docs/method.md), kebab-case; dest stays the
    parameter's name. Its help gives the value each preset the command can grow (the
    extra `looks`, then Table 1's) takes when the option is not given."""
    g = p.add_argument_group("parameter overrides (docs/method.md says what each does; "
                             "default: the preset's)")
    for name, default, doc in Params.describe():
        if name in NOT_OVERRIDES:
            continue
        flag = f"--{name.replace('_', '-')}"
        shown = preset_defaults(name, looks)
        if type(default) is bool:
            g.add_argument(flag, dest=name, type=values.on_off, metavar="on|off",
                           help=f"{doc} ({shown})")
        else:
            g.add_argument(flag, dest=name, type=type(default), metavar=_metavar(default),
                           help=f"{doc} ({shown})")


def preset_defaults(name: str, looks: tuple[str, ...]) -> str:
    """'default V' where every preset has parameter `name` at V, else each value and the
    presets that have it, e.g. 'default: fern, window 2.5; Table 1 1.0-10.0'."""
    groups: dict[str, list[str]] = {}
    for look in looks:
        groups.setdefault(_shown(getattr(_preset(look), name)), []).append(look)
    table = sorted({getattr(_preset(n), name) for n in PRESETS})
    span = _shown(table[0]) + (f"-{_shown(table[-1])}" if len(table) > 1 else "")
    groups.setdefault(span, []).append("Table 1")
    if len(groups) == 1 and len(table) == 1:
        return f"default {span}"
    return "default: " + "; ".join(f"{', '.join(names)} {v}" for v, names in groups.items())


@functools.cache
def _preset(name: str) -> Params:
    """A preset's Params (frozen), built once: the help texts of every command read each
    parameter of every preset, thousands of reads a parser, and every `frost` start builds
    one."""
    return Params.preset(name)


def _shown(value) -> str:
    return ("on" if value else "off") if type(value) is bool else str(value)


def _metavar(default) -> str:
    return {int: "N", float: "X", str: "NAME"}[type(default)]


def params_from(args: argparse.Namespace) -> Params:
    """The Params the command line asks for (the default preset where the command has
    none); a bad value raises ValueError naming it."""
    overrides = {n: getattr(args, n) for n, _, _ in Params.describe()
                 if getattr(args, n, None) is not None}
    preset = getattr(args, "preset", None)
    if getattr(args, "params_file", None):
        return _from_file(args, preset, overrides)
    if "step" not in overrides and "hc" in overrides and overrides["hc"] > 0:
        overrides["step"] = min(Params.step, overrides["hc"])  # a smaller hc takes step with it
    if getattr(args, "window_mode", False):
        overrides.setdefault("window_frost", True)
        overrides.setdefault("grains", True)  # window mode needs them; Table 1 has them off
        return Params.preset(preset or "window", **overrides)
    default: str = getattr(args, "default_preset", DEFAULT_PRESET)  # bench render: c-2
    return Params.preset(preset or default, **overrides)


def _from_file(args: argparse.Namespace, preset: str | None, overrides: dict) -> Params:
    """The parameter set of --params with the overrides on top; it replaces the preset, so
    naming one too is refused (as is --window-frost, a preset of its own)."""
    if preset or getattr(args, "window_mode", False):
        raise ValueError("--params replaces the preset: give --params or --preset/--window-frost, "
                         "not both")
    base = load_params(args.params_file)
    if "step" not in overrides and "hc" in overrides and overrides["hc"] > 0:
        overrides["step"] = min(base.step, overrides["hc"])  # a smaller hc takes step with it
    return base.replace(**overrides)


def has_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
