"""Make assets/background.png: a soft, slightly blurred winter view through a window.

Origin: drawn entirely by this script (numpy + Pillow) for the frost project; no
photograph or third-party image is involved. It is deterministic (fixed seed), so
running it again reproduces the committed PNG. Usage: python3 assets/make_background.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image, ImageFilter

WIDTH, HEIGHT = 760, 1280
SEED = 2018
OUT = Path(__file__).resolve().parent / "background.png"


def sky(h: int, w: int) -> np.ndarray:
    """Dusk: deep blue overhead fading to a pale peach glow at the horizon."""
    t = np.linspace(0.0, 1.0, h)[:, None, None] ** 1.6
    top, glow = np.array([0.10, 0.14, 0.30]), np.array([0.93, 0.70, 0.55])
    return np.broadcast_to(top + (glow - top) * t, (h, w, 3)).copy()


def ridge(w: int, base: float, rng: np.random.Generator, amp: float) -> np.ndarray:
    """A hill line: y in px for every column, a sum of a few random sines."""
    x = np.arange(w)
    y = np.full(w, base)
    for k in range(1, 5):
        y += amp / k * np.sin(2 * np.pi * k * x / w * rng.uniform(0.6, 1.4) + rng.uniform(0, 6.3))
    return y


def paint_below(img: np.ndarray, line: np.ndarray, color) -> None:
    """Fill everything below a per-column line with a flat colour (a silhouette)."""
    rows = np.arange(img.shape[0])[:, None]
    img[rows >= line[None, :]] = color


def trees(img: np.ndarray, ground: np.ndarray, rng: np.random.Generator, color) -> None:
    """Fir silhouettes: narrow triangles standing on the ground line."""
    h, w, _ = img.shape
    yy, xx = np.mgrid[0:h, 0:w]
    for _ in range(18):
        cx = rng.uniform(0, w)
        tall = rng.uniform(60, 170)
        foot = ground[int(np.clip(cx, 0, w - 1))] + 6
        half = tall * 0.22 * (yy - (foot - tall)) / tall
        inside = (yy > foot - tall) & (yy < foot) & (np.abs(xx - cx) < half)
        img[inside] = color


def bokeh(img: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Warm out-of-focus lights of distant houses: soft discs added on top."""
    h, w, _ = img.shape
    yy, xx = np.mgrid[0:h, 0:w]
    glow = np.zeros_like(img)
    for _ in range(26):
        cx, cy = rng.uniform(0, w), rng.uniform(h * 0.62, h * 0.86)
        r = rng.uniform(6, 22)
        color = np.array([1.0, rng.uniform(0.65, 0.85), rng.uniform(0.35, 0.55)])
        disc = np.clip((r - np.hypot(xx - cx, yy - cy)) / 3.0, 0.0, 1.0)
        glow += disc[..., None] * color * rng.uniform(0.25, 0.6)
    return img + glow


def make() -> Image.Image:
    rng = np.random.default_rng(SEED)
    img = sky(HEIGHT, WIDTH)
    far = ridge(WIDTH, HEIGHT * 0.66, rng, 40)
    paint_below(img, far, (0.36, 0.33, 0.45))
    near = ridge(WIDTH, HEIGHT * 0.78, rng, 30)
    paint_below(img, near, (0.20, 0.20, 0.30))
    trees(img, near, rng, (0.10, 0.11, 0.18))
    snow = ridge(WIDTH, HEIGHT * 0.90, rng, 14)
    paint_below(img, snow, (0.55, 0.58, 0.72))
    img = np.clip(bokeh(img, rng), 0.0, 1.0)
    pic = Image.fromarray((img * 255 + 0.5).astype(np.uint8))
    # The view lies far beyond the glass, which the eye focuses on: blur it.
    return pic.filter(ImageFilter.GaussianBlur(radius=6))


if __name__ == "__main__":
    make().save(OUT)
    print(f"wrote {OUT}")
