"""The paper's Fig. 8 again: the nine Table 1 presets grown from one touch, on one sheet.

Rows a, b, c vary D, hc and humidity (Table 1); each cell is the 760x1280 frame
scaled down with its label above it. Beside the picture, `preset_stats` measures what
Sec. 4 claims (smaller hc grows slower and denser; more humidity grows faster and
denser at the centre) so the claims can be checked in numbers.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from app.backdrops import DEFAULT_BACKDROP, view_from
from app.images import frost_meta, save_image
from app.tools.offscreen import Offscreen, make_context
from app.tools.progress import Progress
from sim import PRESETS, FrostSim, Params
from sim.io.files import why
from sim.io.timeline import touch_events
from sim.screen import HEIGHT, WIDTH

CELL = (253, 427)  # a frame scaled by 1/3, px (width, height)
LABEL_H = 16  # band above each cell holding its label, px
GAP = 6  # px between cells and around the sheet
TITLE_H = 22  # band at the top of the sheet, px
ROWS, COLS = "abc", "123"
CORE_RADIUS = 25.0  # px around the touch in which the centre density is counted
GROWTH_MARK = 100.0  # px of extent whose first tick measures the growth speed
# A --params set's fields that Fig. 8 leaves to each preset: Table 1's, and step (at most hc).
SET_SKIPS = ("D", "hc", "humidity", "step")


@dataclass(frozen=True)
class PresetStats:
    """What one preset grew, measured from its skeleton (touch at `centre`)."""

    name: str
    crystals: int
    upsampled: int
    extent: float  # px: farthest skeleton node from the touch
    density: float  # crystals per px^2 of the disc of radius `extent`
    core_density: float  # crystals per px^2 within CORE_RADIUS of the touch
    reach_tick: int | None  # first tick with extent >= GROWTH_MARK, None if never


def label(name: str) -> str:
    p = PRESETS[name]
    return f"{name}  D={p['D']:g} hc={p['hc']:g} H={p['humidity']}"


def cell_box(row: int, col: int, cell=CELL) -> tuple[int, int, int, int]:
    """(left, top, right, bottom) of the image of cell (row, col) on the sheet."""
    x = GAP + col * (cell[0] + GAP)
    y = TITLE_H + row * (LABEL_H + cell[1] + GAP) + LABEL_H
    return x, y, x + cell[0], y + cell[1]


def label_box(row: int, col: int, cell=CELL) -> tuple[int, int, int, int]:
    """(left, top, right, bottom) of the label band above cell (row, col)."""
    x0, y0, x1, _ = cell_box(row, col, cell)
    return x0, y0 - LABEL_H, x1, y0


def sheet_size(cols: int = len(COLS), rows: int = len(ROWS), cell=CELL) -> tuple[int, int]:
    return GAP + cols * (cell[0] + GAP), TITLE_H + rows * (LABEL_H + cell[1] + GAP)


def preset_stats(name: str, sim: FrostSim, centre, reach_tick: int | None) -> PresetStats:
    nodes = np.concatenate((sim.crystals, sim.upsampled))
    d = np.hypot(*(nodes - np.asarray(centre, np.float32)).T)
    extent = float(d.max(initial=0.0))
    dc = np.hypot(*(sim.crystals - np.asarray(centre, np.float32)).T)
    n = len(sim.crystals)
    density = n / (np.pi * extent ** 2) if extent > 0 else 0.0
    core = int((dc <= CORE_RADIUS).sum()) / (np.pi * CORE_RADIUS ** 2)
    return PresetStats(name, n, len(sim.upsampled), extent, density, core, reach_tick)


def grow_preset(ctx, name: str, seed: int, ticks: int, touch, overrides: dict | None = None,
                progress: Progress | None = None,
                view: dict | None = None) -> tuple[np.ndarray, PresetStats]:
    """Grow preset `name` from `touch` for `ticks` ticks: its frame and its numbers."""
    offscreen = Offscreen(ctx, Params.preset(name, **(overrides or {})), seed, view)
    offscreen.progress = progress
    reached: list[int] = []  # the first tick whose new crystals lie GROWTH_MARK px out

    def watch(sim) -> None:
        new = sim.crystals[sim.added.crystals]
        if not reached and len(new) and \
                np.hypot(*(new - np.asarray(touch, np.float32)).T).max() >= GROWTH_MARK:
            reached.append(sim.tick)
    offscreen.grow(ticks, touch_events([touch]), watch)
    frame = offscreen.frame()
    offscreen.release()
    return frame, preset_stats(name, offscreen.sim, touch, reached[0] if reached else None)


def compose(frames: dict[str, np.ndarray], title: str) -> np.ndarray:
    """The 3 x 3 sheet: frames keyed by preset name, each scaled into its cell."""
    names = [[f"{row}-{col}" for col in COLS] for row in ROWS]
    return compose_grid([[(label(n), frames[n]) for n in row] for row in names], title)


def compose_grid(cells: list[list[tuple[str, np.ndarray]]], title: str, cell=CELL) -> np.ndarray:
    """A sheet of rows of (label, frame), each frame scaled into a `cell` with its label above."""
    sheet = Image.new("RGB", sheet_size(len(cells[0]), len(cells), cell), (24, 26, 30))
    draw = ImageDraw.Draw(sheet)
    font = ImageFont.load_default()
    draw.text((GAP, 5), title, fill=(235, 235, 235), font=font)
    for r, row in enumerate(cells):
        for c, (text, frame) in enumerate(row):
            x0, y0, _, _ = cell_box(r, c, cell)
            sheet.paste(Image.fromarray(frame).resize(cell, Image.Resampling.BOX), (x0, y0))
            lx, ly, _, _ = label_box(r, c, cell)
            draw.text((lx + 2, ly + 2), text, fill=(235, 235, 235), font=font)
    return np.asarray(sheet)


def format_table(stats: list[PresetStats]) -> str:
    head = (f"{'preset':<26}{'crystals':>9}{'upsample':>9}{'extent px':>10}"
            f"{'density/1e3px2':>15}{'core/1e3px2':>12}{'t(100px)':>9}")
    lines = [head]
    for s in stats:
        reach = "-" if s.reach_tick is None else str(s.reach_tick)
        lines.append(f"{label(s.name):<26}{s.crystals:>9}{s.upsampled:>9}{s.extent:>10.1f}"
                     f"{1e3 * s.density:>15.3f}{1e3 * s.core_density:>12.3f}{reach:>9}")
    return "\n".join(lines)


def make_figure8(ctx, seed: int = 0, ticks: int = 250, touch=(380.0, 640.0),
                 overrides: dict | None = None,
                 view: dict | None = None) -> tuple[np.ndarray, list[PresetStats]]:
    """The sheet (H x W x 3 uint8) and every preset's numbers, a-1 ... c-3."""
    frames, stats = {}, []
    progress = Progress(len(PRESETS) * ticks)  # all nine presets' ticks
    for name in PRESETS:
        progress.begin(f"preset {name}")
        frames[name], s = grow_preset(ctx, name, seed, ticks, touch, overrides, progress, view)
        stats.append(s)
    title = f"Table 1 presets, seed {seed}, {ticks} ticks, touch {touch[0]:g},{touch[1]:g}"
    return compose(frames, title), stats


def set_overrides(params: Params) -> dict:
    """What a parameter set changes in each Table 1 preset: every field but those Table 1
    sets (and step, which a preset fits to its own hc)."""
    return {k: v for k, v in params.as_dict().items() if k not in SET_SKIPS}


def preset_overrides(args, on_top: Params | None = None) -> dict:
    """What changes in each of Table 1's presets: the set's fields (SET_SKIPS aside), then
    the command line's overrides; an hc given without step takes step with it, as each
    preset fits its step to its own hc."""
    overrides = {n: getattr(args, n) for n, _, _ in Params.describe()
                 if getattr(args, n, None) is not None}
    if on_top is not None:
        overrides = {**set_overrides(on_top), **overrides}
    if "hc" in overrides and "step" not in overrides:
        overrides["step"] = min(Params.step, overrides["hc"])
    return overrides


def run(args, on_top: Params | None = None) -> int:
    """`frost figure8 FILE.png [--params FILE] [--seed N] [--ticks N] [--touch X,Y]` (checked
    by the command line: one touch at most, on the screen). `on_top`: the --params set,
    whose fields but Table 1's (SET_SKIPS) apply to every preset, the overrides after."""
    touch = args.touch[0] if args.touch else (WIDTH / 2, HEIGHT / 2)
    overrides = preset_overrides(args, on_top)
    for name in PRESETS:  # each preset with them is valid, or nothing is drawn
        try:
            Params.preset(name, **overrides)
        except ValueError as err:
            print(f"frost: error: preset {name} with these options: {err}", file=sys.stderr)
            return 2
    try:
        ctx = make_context()
        sheet, stats = make_figure8(ctx, args.seed, args.ticks, touch, overrides,
                                    view_from(args))
    except (RuntimeError, ValueError) as err:
        print(f"frost: error: {err}", file=sys.stderr)
        return 1
    meta = frost_meta("frost figure8", None, args.seed, args.ticks, [(0, *touch)],
                      presets={s.name: PRESETS[s.name] for s in stats}, overrides=overrides,
                      stats=[s.__dict__ for s in stats],
                      background=getattr(args, "background", None) or DEFAULT_BACKDROP)
    try:
        path = save_image(sheet, Path(args.out), meta)
    except OSError as err:
        print(f"frost: error: cannot write {why(err, args.out)}", file=sys.stderr)
        return 2
    print(format_table(stats))
    print(f"wrote {path}")
    return 0
