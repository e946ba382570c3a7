"""The command line's value types: each turns one option's text into its value or
raises argparse.ArgumentTypeError, which argparse reports as a one-line error naming
the option."""

from __future__ import annotations

import argparse
import math

from sim.screen import touch_problem
from sim.session import check_event


def backdrop(text: str) -> str:
    """A built-in backdrop's name or an image file that can be read."""
    from app.backdrops import load_backdrop  # PIL: only when the option is used

    try:
        load_backdrop(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return text


def touch(text: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"touch {text!r} must be X,Y in px, e.g. 380,640") from None
    problem = touch_problem(x, y)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return x, y


def positive(text: str, hi: float, what: str, zero: bool = False) -> float:
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not (0 <= v <= hi if zero else 0 < v <= hi):
        lo = "[0" if zero else "(0"
        raise argparse.ArgumentTypeError(f"{text!r} must be {what} in {lo}, {hi:g}]")
    return v


def whole(text: str) -> int:
    """A tick count or seed: a whole number >= 0."""
    try:
        v = int(text)
    except ValueError:
        v = -1
    if v < 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be a whole number >= 0")
    return v


def melt(text: str) -> dict:
    """X,Y[,R]@TICK -> a melt event (R None: --melt-radius)."""
    try:
        spot, tick = text.split("@")
        values = [float(v) for v in spot.split(",")]
        if len(values) not in (2, 3):
            raise ValueError
        event = {"tick": int(tick), "kind": "melt", "x": values[0], "y": values[1],
                 "r": values[2] if len(values) == 3 else None}
        check_event({**event, "r": 1.0 if event["r"] is None else event["r"]})  # finite, r > 0
    except ValueError:  # SessionError is one
        raise argparse.ArgumentTypeError(
            f"melt {text!r} must be X,Y[,R]@TICK (px, px, px, tick >= 0), e.g. 380,640,30@100") from None
    return event


def radius(text: str) -> float:
    return positive(text, 10_000.0, "a radius in px")


def melt_path(text: str) -> dict:
    """X1,Y1:X2,Y2[:...]@TICK -> the path's points and tick."""
    try:
        path, tick = text.split("@")
        points = [tuple(float(v) for v in p.split(",")) for p in path.split(":")]
        if len(points) < 2 or any(len(p) != 2 for p in points):
            raise ValueError
        for x, y in points:
            check_event({"tick": int(tick), "kind": "melt", "x": x, "y": y, "r": 1.0})
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"melt path {text!r} must be X1,Y1:X2,Y2[:...]@TICK, e.g. 100,600:600,600@150") from None
    return {"tick": int(tick), "points": points}


def on_off(text: str) -> bool:
    if text.lower() in ("1", "on", "true", "yes"):
        return True
    if text.lower() in ("0", "off", "false", "no"):
        return False
    raise argparse.ArgumentTypeError(f"{text!r} must be on or off")


def count(text: str) -> int:
    """How many of something to do: a whole number >= 1."""
    v = whole(text)
    if v < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be a whole number >= 1")
    return v


def scale(text: str) -> float:
    return positive(text, 8.0, "a scale")


def seconds(text: str) -> float:
    return positive(text, 1e9, "seconds", zero=True)


def fraction(text: str) -> float:
    return positive(text, 1.0, "a fraction")
