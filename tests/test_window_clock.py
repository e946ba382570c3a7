"""The window's lock-screen minute drawn on a worker (app/window/clock_drawer.py): the box it
hands back is the one the renderer would draw itself, for the newest minute asked."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from app.backdrops import LIVE, read_backdrop
from app.lockscreen import clock_patch
from app.window.clock_drawer import ClockDrawer

STATIC = np.asarray(read_backdrop(LIVE))


def drawer(draw=lambda m, outside: clock_patch(STATIC, m, outside)):
    woken = threading.Event()
    return ClockDrawer(draw, woken.set), woken


def wait_ready(clock, woken):
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        assert woken.wait(60)
        woken.clear()
        ready = clock.ready()
        if ready is not None:
            return ready
    raise AssertionError("never ready")


def test_the_minute_asked_is_drawn_off_the_loop_and_handed_back_once():
    clock, woken = drawer()
    assert clock.ready() is None
    clock.ask("2026-11-26T09:42")
    minute, outside, box = wait_ready(clock, woken)
    assert (minute, outside) == ("2026-11-26T09:42", "")
    assert np.array_equal(box, clock_patch(STATIC, "2026-11-26T09:42"))
    assert clock.ready() is None  # (once)
    clock.ask("2026-11-26T09:42")  # the same again: nothing new to draw
    assert clock.ready() is None
    clock.close()


def test_the_temperature_outside_changing_in_a_minute_is_drawn_again():
    clock, woken = drawer()
    clock.ask("2026-11-26T09:42")
    wait_ready(clock, woken)
    clock.ask("2026-11-26T09:42", "-25 °C outside")
    minute, outside, box = wait_ready(clock, woken)
    assert (minute, outside) == ("2026-11-26T09:42", "-25 °C outside")
    assert np.array_equal(box, clock_patch(STATIC, "2026-11-26T09:42", "-25 °C outside"))
    clock.close()


def test_a_newer_minute_asked_meanwhile_is_the_one_handed_back():
    gate = threading.Event()

    def slow(minute, outside):
        gate.wait(30)
        return clock_patch(STATIC, minute, outside)

    clock, woken = drawer(slow)
    clock.ask("2026-11-26T09:42")
    clock.ask("2026-11-26T09:43")
    gate.set()
    minute, _, box = wait_ready(clock, woken)
    assert minute == "2026-11-26T09:43"
    assert np.array_equal(box, clock_patch(STATIC, "2026-11-26T09:43"))
    clock.close()


def test_a_drawing_that_failed_says_so_on_the_loop():
    def broken(_minute, _outside):
        raise ValueError("font missing")

    clock, woken = drawer(broken)
    clock.ask("2026-11-26T09:42")
    assert woken.wait(30)
    with pytest.raises(ValueError, match="font missing"):
        wait_ready(clock, woken)
    clock.close()
