"""Command line of `python -m app`: one parser, shared by the window and headless modes."""

from __future__ import annotations

import argparse
import math
import os
import textwrap

from sim import Params, all_presets

from .keys import DEFAULT_PRESET, help_lines


def _touch(text: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"touch {text!r} must be X,Y in px, e.g. 380,640") from None
    return x, y


def _melt(text: str) -> dict:
    """X,Y[,R]@TICK -> a melt event (R None: --melt-radius)."""
    try:
        spot, tick = text.split("@")
        values = [float(v) for v in spot.split(",")]
        if len(values) not in (2, 3) or int(tick) < 0 or min(values[2:] or [1.0]) <= 0:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"melt {text!r} must be X,Y[,R]@TICK (px, px, px, tick >= 0), e.g. 380,640,30@100") from None
    return {"tick": int(tick), "kind": "melt", "x": values[0], "y": values[1],
            "r": values[2] if len(values) == 3 else None}


def _radius(text: str) -> float:
    try:
        r = float(text)
    except ValueError:
        r = math.nan
    if not 0 < r < 10_000:
        raise argparse.ArgumentTypeError(f"{text!r} must be a radius in px, above 0")
    return r


def _melt_path(text: str) -> dict:
    """X1,Y1:X2,Y2[:...]@TICK -> the path's points and tick."""
    try:
        path, tick = text.split("@")
        points = [tuple(float(v) for v in p.split(",")) for p in path.split(":")]
        if len(points) < 2 or any(len(p) != 2 for p in points) or int(tick) < 0:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"melt path {text!r} must be X1,Y1:X2,Y2[:...]@TICK, e.g. 100,600:600,600@150") from None
    return {"tick": int(tick), "points": points}


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m app",
        description=textwrap.fill(
            "Real-time window frost on a 760x1280 phone screen. Click (or drag) to plant seed "
            "crystals; drag with the right button to melt the ice (a warm finger). Each "
            "session is saved (--session-dir) and --replay plays it again bit for bit. "
            "With no display (or --headless) it grows the frost offscreen "
            "and writes PNG files instead."),
        epilog="keys in the window:\n  " + "\n  ".join(help_lines()),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--preset", choices=list(all_presets()),
                   help=f"Table 1 setting (a-1 ... c-3) or {DEFAULT_PRESET} (window frost's "
                        f"fronds, the default)")
    p.add_argument("--window-frost", dest="window_mode", action="store_true",
                   help="the frosted window: frost nucleates on the screen's frame and a few "
                        "pane sites and grows over the whole pane, no touch needed (preset "
                        "window, or window mode on top of --preset)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--headless", action="store_true", help="render offscreen (EGL), no window")
    p.add_argument("--touch", type=_touch, action="append", default=[], metavar="X,Y",
                   help="plant a seed at X,Y px at tick 0 (repeatable)")
    p.add_argument("--ticks", type=int,
                   help="ticks to grow in headless mode (default 250; with --replay: as recorded)")
    p.add_argument("--melt", type=_melt, action="append", default=[], metavar="X,Y[,R]@TICK",
                   help="headless: a warm finger melts the ice within R px (default "
                        "--melt-radius) of X,Y just before step TICK + 1 (repeatable)")
    p.add_argument("--melt-path", type=_melt_path, action="append", default=[],
                   metavar="X1,Y1:X2,Y2[:...]@TICK",
                   help="headless: melt along a polyline at TICK, a melt every half radius "
                        "(repeatable)")
    p.add_argument("--melt-radius", type=_radius, default=24.0, metavar="PX",
                   help="radius of the warm finger (right-button drag in the window; --melt, "
                        "--melt-path), px (default 24)")
    p.add_argument("--replay", metavar="FILE.json",
                   help="replay a recorded session (sessions/*.json): its seed, parameters, "
                        "touches, melts and changes at their ticks; windowed when a display "
                        "exists, else (or with --headless) writes --screenshot after --ticks")
    p.add_argument("--session-dir", default="sessions",
                   help="window: folder for the session files written on exit and with "
                        "each screenshot")
    p.add_argument("--screenshot", metavar="FILE.png", help="headless: write the final frame here")
    p.add_argument("--figure8", metavar="FILE.png",
                   help="render the nine Table 1 presets from one touch into a 3x3 sheet (Fig. 8), "
                        "print each preset's numbers, and exit")
    p.add_argument("--figure", nargs=2, metavar=("fern", "FILE.png"),
                   help="render a labelled sheet of fern growth (ticks 25 ... 750, one touch and "
                        "three touches) with the chosen parameters, and exit")
    p.add_argument("--export-maps", metavar="DIR",
                   help="headless: write height.png, normal.png and alpha.png of the final frost to DIR")
    p.add_argument("--screenshot-dir", default="screenshots",
                   help="folder for screenshots (S, F12) and recordings (R)")
    p.add_argument("--scale", type=float, metavar="F",
                   help="window: size as a fraction of 760x1280 (default: fit the monitor)")
    p.add_argument("--max-seconds", type=float, metavar="S",
                   help="window: close by itself after S seconds (exit status 0)")
    g = p.add_argument_group("parameter overrides (see SPEC.md)")
    for name, default, doc in Params.describe():
        kind = type(default)
        if kind is bool:
            g.add_argument(f"--{name}", type=_bool, metavar="on|off", help=doc)
        else:
            g.add_argument(f"--{name}", type=kind, help=f"{doc} (default {default})")
    return p


def _bool(text: str) -> bool:
    if text.lower() in ("1", "on", "true", "yes"):
        return True
    if text.lower() in ("0", "off", "false", "no"):
        return False
    raise argparse.ArgumentTypeError(f"{text!r} must be on or off")


def params_from(args: argparse.Namespace) -> Params:
    """The Params the command line asks for; a bad value raises ValueError naming it."""
    overrides = {n: getattr(args, n) for n, _, _ in Params.describe() if getattr(args, n) is not None}
    if "step" not in overrides and "hc" in overrides and overrides["hc"] > 0:
        overrides["step"] = min(Params.step, overrides["hc"])  # a smaller hc takes step with it
    if getattr(args, "window_mode", False):
        overrides.setdefault("window_frost", True)
        return Params.preset(args.preset or "window", **overrides)
    return Params.preset(args.preset or DEFAULT_PRESET, **overrides)


def has_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
