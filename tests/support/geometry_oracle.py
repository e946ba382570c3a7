"""The Python side of the page's geometry tests (tests/web/geometry.test.mjs): a real
FrostSim grown, melted and redrawn, with `FrostGeometry`'s deltas and the `Encoder`'s
bytes of each, written as JSON for the Node test to hold app/web/local/ to.

Run as `python tests/support/geometry_oracle.py OUT.json` (the Node test does, with
FROST_PYTHON). Every event holds the simulation's arrays the geometry reads, as they were
when Python's geometry read them, so the test builds a stand-in for the page's `Frost`
from them; `near` holds each `segments_near` call the geometry made (its box, reach and
answer), which the stand-in answers in the same order.
"""

from __future__ import annotations

import base64
import dataclasses
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent))

from app.serve import protocol  # noqa: E402
from sim import Params  # noqa: E402
from sim.core.frost import FrostSim  # noqa: E402
from sim.look.geometry import FrostGeometry, live_features  # noqa: E402

# Snapshot parts this many vertices long, so a small frost's snapshot is cut in several.
SMALL_PART = 3 * 1000
SCENARIOS = (
    # name, preset, seed, touches, ticks, melts ((x, y, r) each), ticks after them. The
    # fern's first melt cuts an arm half way out (the links above it thin), its second
    # leaves orphans.
    ("fern", "fern", 1, ((380, 640), (300, 560), (470, 700)), 120,
     ((380, 668, 9.0), (380, 668, 13.0)), 10),
    ("paper", "a-1", 2, ((380, 640), (200, 300)), 30, ((390, 646, 15.0),), 5),
)


def packed(a: np.ndarray) -> dict:
    """An array as the Node test reads it: its dtype and little-endian bytes in base64."""
    a = np.ascontiguousarray(a)
    return {"dtype": a.dtype.str, "b64": base64.b64encode(a.tobytes()).decode("ascii")}


def state(sim: FrostSim) -> dict:
    """What the geometry reads of the simulation now (copies)."""
    return {"tick": int(sim.tick), "width": sim.width, "height": sim.height,
            **{name: packed(getattr(sim, name)) for name in (
                "crystals", "parents", "crystal_alive", "upsampled", "upsampled_link",
                "upsampled_alive", "segments", "segments_link", "segments_alive")}}


def delta_of(d) -> dict:
    return {"tick": int(d.tick), "rows": [d.rows.start, d.rows.stop], "heights": packed(d.heights),
            "features": packed(d.features), "reset": bool(d.reset),
            "clear_box": list(d.clear_box) if d.clear_box is not None else None,
            "look": d.look, "height_scale": float(d.height_scale)}


class Recorder:
    """Records the `segments_near` calls the geometry makes of a simulation."""

    def __init__(self, sim: FrostSim):
        self.calls: list[dict] = []
        near = sim.segments_near

        def recorded(box, reach):
            out = near(box, reach)
            self.calls.append({"box": [float(v) for v in box], "reach": float(reach),
                               "ids": packed(np.asarray(out, np.int32))})
            return out
        sim.segments_near = recorded  # type: ignore[method-assign]


def scenario(name: str, preset: str, seed: int, touches, ticks: int, melts, after: int) -> dict:
    params = Params.preset(preset)
    sim = FrostSim(params, seed=seed)
    geometry = FrostGeometry(params)
    encoder = protocol.Encoder(geometry.cols, geometry.rows)
    recorder = Recorder(sim)
    events: list[dict] = []

    def record(kind: str, delta, **more) -> None:
        events.append({"kind": kind, "state": state(sim), "delta": delta_of(delta),
                       "bytes": base64.b64encode(encoder.delta(delta)).decode("ascii"),
                       "near": recorder.calls[:], **more})
        recorder.calls.clear()

    record("reset", geometry.reset())
    for x, y in touches:
        sim.touch(x, y)

    def grow(n: int) -> None:
        for _ in range(n):
            added = sim.step()
            record("update", geometry.update(sim),
                   added=[added.crystals.start, added.crystals.stop])
    grow(ticks)
    for melt in melts:
        melted = sim.melt(*melt)
        record("melt", geometry.melt(sim, melted),
               melted={key: packed(getattr(melted, key).astype(np.int32))
                       for key in ("crystals", "upsampled", "segments", "orphans")})
    grow(after)
    redrawn = geometry.redraw(sim)
    record("redraw", redrawn)
    protocol.PART_VERTICES = SMALL_PART
    parts = encoder.snapshot(sim.tick, live_features(sim, params), params.look,
                             events[-1]["delta"]["height_scale"])
    # A tick with no change, a reset alone, then the redraw's heights again (not a reset):
    # all of them runs, against the grid the reset emptied.
    bare = [encoder.bare(sim.tick + 1, False), encoder.bare(sim.tick + 2, True),
            encoder.delta(dataclasses.replace(redrawn, reset=False))]
    return {"name": name, "params": dataclasses.asdict(params),
            "grid": [geometry.cols, geometry.rows], "events": events,
            "snapshot": {"part_vertices": SMALL_PART, "tick": int(sim.tick),
                         "parts": [base64.b64encode(p).decode("ascii") for p in parts]},
            "bare": [base64.b64encode(b).decode("ascii") for b in bare]}


def main(out: str) -> None:
    part = protocol.PART_VERTICES
    try:
        data = [scenario(*s) for s in SCENARIOS]
    finally:
        protocol.PART_VERTICES = part
    Path(out).write_text(json.dumps(data), encoding="utf-8")


if __name__ == "__main__":
    main(sys.argv[1])
