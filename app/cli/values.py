"""The command line's value types: each turns one option's text into its value or
raises argparse.ArgumentTypeError, which argparse reports as a one-line error naming
the option."""

from __future__ import annotations

import argparse
import math

from app.window.view import scale_problem
from sim.io.session import MAX_SEED, MAX_TICK
from sim.screen import MAX_MELT_RADIUS, melt_problem, radius_problem, touch_problem

MAPS_SIDE = (64, 4096)  # px: the sides frost maps --size takes


def backdrop(text: str) -> str:
    """A built-in backdrop's name or an image file that can be read."""
    from app.backdrops import load_backdrop  # PIL: only when the option is used

    try:
        load_backdrop(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return text


def clock(text: str):
    """A time for the lock screen's clock: HH:MM, YYYY-MM-DDTHH:MM or YYYY-MM-DDTHH:MM:SS."""
    from app.lockscreen import parse_clock  # PIL: only when the option is used

    try:
        return parse_clock(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def touch(text: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"touch {text!r} must be X,Y in px, e.g. 380,640") from None
    problem = touch_problem(x, y)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return x, y


def number(text: str) -> float:
    """`text` as a float; NaN (refused by every range) when it is not a number."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def positive(text: str, hi: float, what: str, zero: bool = False) -> float:
    v = number(text)
    if not (0 <= v <= hi if zero else 0 < v <= hi):
        lo = "[0" if zero else "(0"
        raise argparse.ArgumentTypeError(f"{text!r} must be {what} in {lo}, {hi:g}]")
    return v


def whole(text: str, hi: int = MAX_TICK) -> int:
    """A tick count: a whole number in [0, `hi`] (a session's rule for ticks)."""
    try:
        v = int(text)
    except ValueError:
        v = -1
    if not 0 <= v <= hi:
        raise argparse.ArgumentTypeError(f"{text!r} must be a whole number in [0, {hi}]")
    return v


def seed(text: str) -> int:
    """A random seed: what a session file keeps (sim.io.session.MAX_SEED)."""
    return whole(text, MAX_SEED)


def melt(text: str) -> dict:
    """X,Y[,R]@TICK -> a melt event (R None: --melt-radius); the spot and radius follow
    sim.screen's rules for melts, the tick a session's."""
    try:
        spot, tick = text.split("@")
        values = [float(v) for v in spot.split(",")]
        if len(values) not in (2, 3):
            raise ValueError
        at = whole(tick)
    except (ValueError, argparse.ArgumentTypeError):
        raise argparse.ArgumentTypeError(
            f"melt {text!r} must be X,Y[,R]@TICK (px, px, px, tick >= 0), e.g. 380,640,30@100") from None
    x, y, r = values[0], values[1], values[2] if len(values) == 3 else None
    problem = melt_problem(x, y, MAX_MELT_RADIUS if r is None else r)  # None: --melt-radius's
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return {"tick": at, "kind": "melt", "x": x, "y": y, "r": r}


def radius(text: str) -> float:
    """A melt radius in px (sim.screen's rule)."""
    v = number(text)
    problem = radius_problem(v)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return v


def melt_path(text: str) -> dict:
    """X1,Y1:X2,Y2[:...]@TICK -> the path's points and tick; each point is a melt's
    centre, so on the screen (the path between two of them is too)."""
    try:
        path, tick = text.split("@")
        points = [tuple(float(v) for v in p.split(",")) for p in path.split(":")]
        if len(points) < 2 or any(len(p) != 2 for p in points):
            raise ValueError
        at = whole(tick)
    except (ValueError, argparse.ArgumentTypeError):
        raise argparse.ArgumentTypeError(
            f"melt path {text!r} must be X1,Y1:X2,Y2[:...]@TICK, e.g. 100,600:600,600@150") from None
    for x, y in points:
        problem = touch_problem(x, y, what="melt path point")
        if problem:
            raise argparse.ArgumentTypeError(problem)
    return {"tick": at, "points": points}


def size(text: str) -> tuple[int, int]:
    """WxH in px, each side in [MAPS_SIDE[0], MAPS_SIDE[1]] (frost maps --size)."""
    lo, hi = MAPS_SIDE
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size {text!r} must be WxH in px, e.g. 2048x2048") from None
    if not (lo <= w <= hi and lo <= h <= hi):
        raise argparse.ArgumentTypeError(f"size {text!r}: each side must be {lo} ... {hi} px")
    return w, h


def point(text: str) -> tuple[float, float]:
    """X,Y of finite px; where it lands is checked against the size it goes with."""
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"touch {text!r} must be X,Y in px, e.g. 380,640") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise argparse.ArgumentTypeError(f"touch ({x:g}, {y:g}) must be finite")
    return x, y


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
    """The window's size: the window's own rule (app.window.view.scale_problem)."""
    v = number(text)
    problem = scale_problem(v)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return v


def seconds(text: str) -> float:
    return positive(text, 1e9, "seconds", zero=True)


def fraction(text: str) -> float:
    return positive(text, 1.0, "a fraction")


def place(text: str) -> str:
    """A place for --weather: LAT,LON (on the globe) or a name to look up."""
    from app.weather.client import coordinates  # (aiohttp: only when the option is used)

    try:
        coordinates(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    if not text.strip() or len(text) > 200 or not text.isprintable():
        raise argparse.ArgumentTypeError(f"place {text!r} must be LAT,LON or a place's name "
                                         "(1 to 200 characters)")
    return text.strip()


def url(text: str) -> str:
    """An API's address: http:// or https:// and a host."""
    from urllib.parse import urlsplit

    parts = urlsplit(text)
    if parts.scheme not in ("http", "https") or not parts.netloc or not text.isprintable():
        raise argparse.ArgumentTypeError(f"{text!r} must be an http:// or https:// URL with a host, "
                                         "e.g. https://api.open-meteo.com")
    return text.rstrip("/")


def within(text: str, lo: float, hi: float, what: str) -> float:
    """A number in [lo, hi], `what` naming it in the error."""
    v = number(text)
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"{what} {text!r} must be a number in [{lo:g}, {hi:g}]")
    return v
