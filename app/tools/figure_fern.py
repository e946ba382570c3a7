"""`frost figure fern FILE.png`: fern growth over time, one touch and three touches, on one sheet.

Row 1 grows one touch at the screen's centre, row 2 three touches (three grains with their
own orientations that meet); columns are ticks 25 ... 750 (1 to 30 s at 25 ticks per
second). Each cell is the whole 760x1280 frame scaled down, labelled with its tick, time
and crystal count. The layout is Fig. 8's (app.tools.figure8).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from app.backdrops import DEFAULT_BACKDROP, view_from
from app.images import frost_meta, save_image
from app.tools.figure8 import compose_grid
from app.tools.offscreen import Offscreen, make_context
from app.tools.progress import Progress
from sim import Params
from sim.io.files import why
from sim.io.timeline import touch_events
from sim.screen import TICKS_PER_SECOND

TICKS = (25, 50, 125, 250, 500, 750)
ROWS = {"one touch": [(380.0, 640.0)],
        "three touches": [(250.0, 400.0), (520.0, 560.0), (330.0, 930.0)]}
CELL = (190, 320)  # a frame scaled by 1/4, px


def grow_row(ctx, params: Params, seed: int, touches, ticks=TICKS,
             progress: Progress | None = None,
             view: dict | None = None) -> list[tuple[str, np.ndarray]]:
    """Frames of one growth at each of `ticks`, with their labels."""
    offscreen = Offscreen(ctx, params, seed, view)
    offscreen.progress = progress
    offscreen.grow(0, touch_events(touches))
    cells = []
    for tick in ticks:
        offscreen.grow(tick - offscreen.sim.tick)
        n = int(offscreen.sim.crystal_alive.sum())
        cells.append((f"tick {tick} ({tick / TICKS_PER_SECOND:g} s) {n} crystals",
                      offscreen.frame()))
    offscreen.release()
    return cells


def make_sheet(ctx, params: Params, seed: int = 0, view: dict | None = None) -> np.ndarray:
    progress = Progress(len(ROWS) * TICKS[-1])  # both rows' ticks: a minute or more
    rows = []
    for name, touches in ROWS.items():
        progress.begin(name)
        rows.append(grow_row(ctx, params, seed, touches, progress=progress, view=view))
    title = (f"fern growth, seed {seed}: row 1 {list(ROWS)[0]}, row 2 {list(ROWS)[1]}; "
             f"ticks {', '.join(map(str, TICKS))}")
    return compose_grid(rows, title, CELL)


def run(args, params: Params) -> int:
    """`frost figure fern FILE.png [--seed N] [--preset NAME] [parameter overrides]`."""
    path = args.out
    try:
        ctx = make_context()
        sheet = make_sheet(ctx, params, args.seed, view_from(args))
    except (RuntimeError, ValueError) as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 1
    meta = frost_meta("frost figure fern", params, args.seed, max(TICKS), [], ticks=list(TICKS),
                      rows={k: [list(t) for t in v] for k, v in ROWS.items()},
                      background=getattr(args, "background", None) or DEFAULT_BACKDROP)
    try:
        out = save_image(sheet, Path(path), meta)
    except OSError as err:
        print(f"frost: error: cannot write {why(err, path)}", file=sys.stderr)
        return 2
    print(f"wrote {out}")
    return 0
