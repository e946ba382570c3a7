"""The looks: Table 1's presets keep the paper's picture pixel for pixel (hashes stored
before the glass look existed), the glass look's shader variants, and its measured cues."""

from __future__ import annotations

import hashlib

import pytest

from app.tools.offscreen import Offscreen
from sim import Params
from sim.session import touch_events

# sha256 of the H x W x 3 frame, computed on the code before the `look` setting existed
# (commit 1c14e25), llvmpipe. What each run is: preset, seed, ticks, touches, melts.
PAPER_RUNS = {
    "c-2": ("c-2", 0, 150, [(380.0, 640.0)], []),
    "a-1 melt": ("a-1", 3, 120, [(300.0, 500.0), (480.0, 800.0)],
                 [{"tick": 90, "kind": "melt", "x": 300.0, "y": 520.0, "r": 30.0}]),
    "b-1": ("b-1", 1, 100, [(200.0, 300.0)], []),
}
PAPER_HASHES = {
    "a-1 melt": "8b483501cd983eeaf40a0a55fd6f9429125fc4e2fa5840dfb34c013fa106c430",
    "b-1": "d2eda0a358e9f99bb1ead7243f934be891cd3ac298e11a63512b92c16d1fdbab",
    "c-2": "5a78f556ac4007493a3524240e01813b2ba20e2fd0583d8d31dd63be47aa0741",
}


def paper_frame(ctx, name: str):
    preset, seed, ticks, touches, melts = PAPER_RUNS[name]
    run = Offscreen(ctx, Params.preset(preset), seed)
    run.grow(ticks, touch_events(touches) + melts)
    try:
        return run.frame()
    finally:
        run.release()


@pytest.mark.parametrize("name", sorted(PAPER_RUNS))
def test_paper_presets_unchanged(gl_ctx, name):
    digest = hashlib.sha256(paper_frame(gl_ctx, name).tobytes()).hexdigest()
    assert digest == PAPER_HASHES[name]
