"""Before / after sheets of the glass look (docs/glass-*.webp): for a preset, the paper's
look and the glass look on the same frost, over each built-in backdrop, full frame and
3x crops. Usage: python -m app.tools.glass_sheet OUT_DIR [PRESET ...]"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from app.backdrops import BACKDROPS
from app.tools.offscreen import Offscreen, make_context
from sim import Params
from sim.io.timeline import touch_events

# preset: (ticks, touches, crop centre) - the crop where the ice is busiest.
RUNS = {"fern": (750, [(380.0, 640.0)], (380, 600)),
        "window": (1200, [], (380, 300)),
        "c-2": (250, [(380.0, 640.0)], (400, 640))}
FULL_SCALE, CROP, ZOOM = 0.4, 100, 3


def frames(ctx, preset: str, look: str) -> dict[str, np.ndarray]:
    """The preset grown with `look`, drawn over every built-in backdrop."""
    ticks, touches, _ = RUNS[preset]
    run = Offscreen(ctx, Params.preset(preset, look=look), 0)
    run.grow(ticks, touch_events(touches))
    shots = {}
    for name in BACKDROPS:
        run.renderer.set_backdrop(name)
        shots[name] = run.frame()
    run.release()
    return shots


def tile(frame: np.ndarray, centre, label: str) -> Image.Image:
    """The full frame scaled down beside a 3x crop, with a label."""
    full = Image.fromarray(frame).resize((round(760 * FULL_SCALE), round(1280 * FULL_SCALE)),
                                         Image.Resampling.LANCZOS)
    x, y = centre
    crop = Image.fromarray(frame[y - CROP // 2:y + CROP // 2, x - CROP // 2:x + CROP // 2])
    crop = crop.resize((CROP * ZOOM, CROP * ZOOM), Image.Resampling.NEAREST)
    out = Image.new("RGB", (full.width + crop.width + 8, max(full.height, crop.height) + 24),
                    (24, 24, 28))
    out.paste(full, (0, 24))
    out.paste(crop, (full.width + 8, 24))
    ImageDraw.Draw(out).text((4, 4), label, fill=(235, 235, 235))
    return out


def sheet(ctx, preset: str) -> Image.Image:
    looks = {look: frames(ctx, preset, look) for look in ("paper", "glass")}
    tiles = [[tile(looks[look][bg], RUNS[preset][2], f"{preset}, {look} look, {bg} "
                   f"(tick {RUNS[preset][0]}; right: 3x crop)") for look in looks]
             for bg in BACKDROPS]
    w, h = tiles[0][0].size
    out = Image.new("RGB", (2 * w + 8, len(tiles) * (h + 8)), (24, 24, 28))
    for r, row in enumerate(tiles):
        for c, t in enumerate(row):
            out.paste(t, (c * (w + 8), r * (h + 8)))
    return out


def main(argv: list[str]) -> int:
    folder = Path(argv[0])
    folder.mkdir(parents=True, exist_ok=True)
    ctx = make_context()
    for preset in argv[1:] or list(RUNS):
        path = folder / f"glass-{preset}.webp"
        sheet(ctx, preset).save(path, quality=82)
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
