"""The paper's looks drawn headless: a preset's run grown and its frame read back."""

from __future__ import annotations

from app.tools.offscreen import Offscreen
from sim import Params
from sim.io.timeline import touch_events

# The paper's runs (tests/test_look.py pins their frames): preset, seed, ticks, touches, melts.
PAPER_RUNS = {
    "c-2": ("c-2", 0, 150, [(380.0, 640.0)], []),
    "a-1 melt": ("a-1", 3, 120, [(300.0, 500.0), (480.0, 800.0)],
                 [{"tick": 90, "kind": "melt", "x": 300.0, "y": 520.0, "r": 30.0}]),
    "b-1": ("b-1", 1, 100, [(200.0, 300.0)], []),
}


def paper_frame(ctx, name: str):
    """The frame of PAPER_RUNS' run `name`, grown by version 6's rules (one random stream)
    and drawn in `ctx`."""
    preset, seed, ticks, touches, melts = PAPER_RUNS[name]
    run = Offscreen(ctx, Params.preset(preset), seed, version=6)
    run.grow(ticks, touch_events(touches) + melts)
    try:
        return run.frame()
    finally:
        run.release()
