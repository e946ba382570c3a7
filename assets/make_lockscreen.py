"""Make assets/lockscreen.png: a phone's lock screen, sharp, for the glass look's refraction.

A large clock, the date and a grid of app icons over a wallpaper of soft colour bands:
hard edges and flat colours everywhere, so the view bent through the ice shows (the dusk
view is blurred and hides it). Origin: drawn entirely by this script (numpy + Pillow,
Pillow's built-in font) for the frost project; no photograph or third-party image. It is
deterministic (fixed seed). Usage: python3 assets/make_lockscreen.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

WIDTH, HEIGHT = 760, 1280
SEED = 21
OUT = Path(__file__).resolve().parent / "lockscreen.png"
# Seven-segment digits: which of the segments a..g (top, top right, bottom right,
# bottom, bottom left, top left, middle) each digit lights.
SEGMENTS = {"0": "abcdef", "1": "bc", "2": "abdeg", "3": "abcdg", "4": "bcfg",
            "5": "acdfg", "6": "acdefg", "7": "abc", "8": "abcdefg", "9": "abcdfg"}
ICON_COLOURS = [(236, 84, 72), (250, 178, 52), (82, 196, 110), (64, 156, 240), (150, 98, 226),
                (240, 240, 244), (30, 36, 48), (244, 120, 180), (60, 200, 200), (120, 130, 150)]


def wallpaper() -> Image.Image:
    """Diagonal colour bands, teal to violet, with a few sharp-edged ribbons."""
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    t = (x * 0.45 + y) / (WIDTH * 0.45 + HEIGHT)
    base = np.array([18, 92, 120]) + np.array([110, -40, 80]) * t[..., None]
    band = np.sin((x * 0.8 - y) / 37.0) > 0.55
    base[band] += 28
    return Image.fromarray(np.clip(base, 0, 255).astype(np.uint8))


def segment_boxes(x: float, y: float, w: float, h: float, t: float) -> dict[str, tuple]:
    """The rectangle of each segment of a digit at (x, y), w x h, stroke t."""
    mid = y + h / 2
    return {"a": (x, y, x + w, y + t), "d": (x, y + h - t, x + w, y + h),
            "g": (x, mid - t / 2, x + w, mid + t / 2), "f": (x, y, x + t, mid),
            "b": (x + w - t, y, x + w, mid), "e": (x, mid, x + t, y + h),
            "c": (x + w - t, mid, x + w, y + h)}


def clock(draw: ImageDraw.ImageDraw, text: str, top: int) -> None:
    """The time in large seven-segment digits, centred."""
    w, h, t, gap = 110, 190, 22, 28
    total = len(text) * (w + gap) - gap
    x = (WIDTH - total) / 2
    for ch in text:
        if ch == ":":
            for dy in (h * 0.3, h * 0.7):
                draw.rectangle((x + w / 2 - t / 2, top + dy - t / 2, x + w / 2 + t / 2, top + dy + t / 2),
                               fill=(250, 250, 252))
        else:
            boxes = segment_boxes(x, top, w, h, t)
            for seg in SEGMENTS[ch]:
                draw.rectangle(boxes[seg], fill=(250, 250, 252))
        x += w + gap


def icons(draw: ImageDraw.ImageDraw, rng: np.random.Generator) -> None:
    """A 4 x 5 grid of rounded app icons, each with a white glyph."""
    side, cols, rows, top = 120, 4, 5, 600
    gap = (WIDTH - cols * side) / (cols + 1)
    for r in range(rows):
        for c in range(cols):
            x0, y0 = gap + c * (side + gap), top + r * (side + 18)
            colour = ICON_COLOURS[rng.integers(len(ICON_COLOURS))]
            draw.rounded_rectangle((x0, y0, x0 + side, y0 + side), radius=28, fill=colour)
            glyph(draw, x0 + side / 2, y0 + side / 2, int(rng.integers(3)))


def glyph(draw: ImageDraw.ImageDraw, cx: float, cy: float, kind: int) -> None:
    """A simple white mark on an icon: a ring, a bar chart or a cross."""
    white = (255, 255, 255)
    if kind == 0:
        draw.ellipse((cx - 32, cy - 32, cx + 32, cy + 32), outline=white, width=10)
    elif kind == 1:
        for i, hgt in enumerate((30, 55, 42)):
            draw.rectangle((cx - 36 + i * 26, cy + 30 - hgt, cx - 18 + i * 26, cy + 30), fill=white)
    else:
        draw.rectangle((cx - 8, cy - 36, cx + 8, cy + 36), fill=white)
        draw.rectangle((cx - 36, cy - 8, cx + 36, cy + 8), fill=white)


def main() -> None:
    rng = np.random.default_rng(SEED)
    img = wallpaper()
    draw = ImageDraw.Draw(img)
    clock(draw, "12:45", 150)
    font = ImageFont.load_default(size=44)
    draw.text((WIDTH / 2, 400), "Monday 23 November", font=font, fill=(245, 245, 250), anchor="mm")
    icons(draw, rng)
    img.save(OUT, optimize=True)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
