"""Make assets/lockscreen.png: a phone's lock screen, its static parts.

A night wallpaper that reads as a photograph (an aurora over a mountain lake: soft
gradients, glow, layers of mountains fading with distance, their reflection in the lake)
with sharp edges where the glass look's refraction shows (the ridgelines, stars, the
shore's firs, the notifications' cards, the buttons), then a lock screen's parts: the
status bar, the padlock, two notifications, the torch and camera buttons and the home bar.
The clock box (app/lockscreen.py CLOCK_BOX) is left as bare wallpaper: the app draws the
date and the time into it each minute (`app.lockscreen.clock_patch`, which this script
uses for the preview). Origin: drawn entirely by this script (numpy + Pillow, Pillow's
built-in font) for the frost project; no photograph or third-party image. Deterministic
(fixed seed). Usage: python3 assets/make_lockscreen.py [--preview FILE.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFilter

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.lockscreen import CLOCK_BOX, DEFAULT_MINUTE, font, with_clock  # noqa: E402

WIDTH, HEIGHT = 760, 1280
SEED = 38
SHORE = 720  # the lake's far shore, px from the top
OUT = Path(__file__).resolve().parent / "lockscreen.png"


def smooth_noise(n: int, scale: float, rng: np.random.Generator) -> np.ndarray:
    """1-D value noise over n samples: random values every `scale` px, cosine-blended."""
    knots = rng.uniform(-1.0, 1.0, int(n / scale) + 3)
    x = np.arange(n) / scale
    i = x.astype(int)
    t = (1 - np.cos((x - i) * np.pi)) / 2
    return knots[i] * (1 - t) + knots[i + 1] * t


def ridge(base: float, rng: np.random.Generator, amp: float, rough: float) -> np.ndarray:
    """A mountain line: y (px) for every column, big shapes plus finer, sharper detail."""
    y = np.full(WIDTH, float(base))
    for scale, weight in ((260, 1.0), (110, 0.5), (45, 0.25 * rough), (17, 0.1 * rough)):
        y -= amp * weight * smooth_noise(WIDTH, scale, rng)
    return y


def sky(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Night overhead, a green-teal glow toward the horizon, a warm afterglow low left."""
    t = np.clip(y / SHORE, 0, 1)[..., None]
    top, low = np.array([6, 10, 32.0]), np.array([24, 70, 92.0])
    colour = top + (low - top) * t ** 1.7
    glow = np.exp(-(((x - 170) / 420) ** 2 + ((y - SHORE) / 230) ** 2))[..., None]
    return colour + glow * np.array([120, 62, 40.0])


def aurora(y: np.ndarray, x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Curtains of light: a sharp-ish lower hem along a wavy line, rays fading upward,
    green at the hem turning violet at the top; blurred as a long exposure blurs it."""
    xs = np.arange(WIDTH)
    hem = 430 + 110 * np.sin(xs / 190 + 0.6) + 35 * np.sin(xs / 57 + 2.0) + 20 * smooth_noise(WIDTH, 40, rng)
    rays = 0.65 + 0.35 * np.clip(smooth_noise(WIDTH, 6, rng) + 0.5 * smooth_noise(WIDTH, 23, rng), -1, 1)
    strength = 0.5 + 0.5 * np.clip(smooth_noise(WIDTH, 150, rng) + 0.6, 0, 1)
    above = np.clip(hem[None, :] - y, 0, None)
    below = np.clip(y - hem[None, :], 0, None)
    light = np.exp(-above / 170) * np.exp(-below / 14) * rays[None, :] * strength[None, :]
    up = np.clip(above / 320, 0, 1)[..., None]
    colour = np.array([70, 255, 150.0]) * (1 - up) + np.array([170, 70, 230.0]) * up
    layer = Image.fromarray(np.clip(light * 255, 0, 255).astype(np.uint8))
    layer = layer.filter(ImageFilter.BoxBlur(3)).filter(ImageFilter.GaussianBlur(2))
    return np.asarray(layer, np.float64)[..., None] / 255 * colour * 0.85


def stars(img: np.ndarray, rng: np.random.Generator) -> None:
    """A few hundred sharp stars, brighter ones with a faint halo, fewer near the glow."""
    n = 420
    xs, ys = rng.integers(0, WIDTH, n), (rng.random(n) ** 1.5 * (SHORE - 180)).astype(int)
    bright = rng.random(n) ** 3
    for x, y, b in zip(xs, ys, bright, strict=True):
        img[y, x] = np.maximum(img[y, x], 150 + 105 * b)
        if b > 0.5 and 0 < x < WIDTH - 1 and y > 0:
            for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                img[y + dy, x + dx] = np.maximum(img[y + dy, x + dx], 70 + 80 * b)


def mountains(img: np.ndarray, y: np.ndarray, rng: np.random.Generator) -> None:
    """Three ranges, far to near: the far one pale with snow lit by the aurora, the near
    ones darker and sharper (air between the eye and a far range lightens it)."""
    ranges = ((SHORE - 150, 110, 1.4, np.array([46, 70, 104.0]), True),
              (SHORE - 80, 70, 1.0, np.array([24, 38, 60.0]), False),
              (SHORE - 25, 40, 0.7, np.array([10, 17, 28.0]), False))
    for base, amp, rough, colour, snow in ranges:
        line = ridge(base, rng, amp, rough)
        depth = np.clip(y - line[None, :], 0, None)
        inside = depth > 0
        shade = colour * (1 - 0.35 * np.clip(depth / 160, 0, 1))[..., None]
        if snow:
            cap = np.exp(-depth / 26)[..., None] * (0.6 + 0.4 * np.sin(np.arange(WIDTH) / 9.0))[None, :, None]
            shade = shade + cap * np.array([90, 140, 140.0])
        img[inside] = shade[inside]


def firs(img: np.ndarray, rng: np.random.Generator) -> None:
    """Dark fir silhouettes on the near shore, left and right, crisp against the lake."""
    draw_img = Image.fromarray(np.clip(img, 0, 255).astype(np.uint8))
    draw = ImageDraw.Draw(draw_img)
    for x in [*rng.uniform(-10, 190, 9), *rng.uniform(560, 770, 8)]:
        h = rng.uniform(60, 150)
        foot = SHORE + rng.uniform(-6, 4)
        for k in range(5):
            top, bottom = foot - h + k * h / 6, foot - h + (k + 2) * h / 6
            half = (k + 1.5) * h / 26
            draw.polygon([(x, top), (x - half, bottom), (x + half, bottom)], fill=(5, 9, 14))
    img[:] = np.asarray(draw_img, np.float64)


def lake(img: np.ndarray) -> None:
    """Below the shore: the scene mirrored, darker and bluer, broken by ripples that grow
    toward the eye, with a sharp line of light along the far shore."""
    rows = np.arange(SHORE, HEIGHT)
    src = np.clip(2 * SHORE - rows, 0, SHORE - 1)
    dist = (rows - SHORE) / (HEIGHT - SHORE)
    shift = (np.sin(rows * 0.9) * 2 + np.sin(rows * 0.37) * 3) * (0.3 + 3 * dist)
    water = np.empty((len(rows), WIDTH, 3))
    for i, (s, d) in enumerate(zip(src, shift, strict=True)):
        water[i] = np.roll(img[s], int(round(d)), axis=0)
    blurred = np.asarray(Image.fromarray(np.clip(water, 0, 255).astype(np.uint8))
                         .filter(ImageFilter.BoxBlur(2)), np.float64)
    fade = (0.62 - 0.25 * dist)[:, None, None]
    img[SHORE:] = blurred * fade + np.array([4, 10, 20.0]) * (1 - fade)
    img[SHORE:SHORE + 2] = np.maximum(img[SHORE:SHORE + 2], [60, 90, 110])


def wallpaper() -> np.ndarray:
    rng = np.random.default_rng(SEED)
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    img = sky(y, x) + aurora(y, x, rng)
    stars(img, rng)
    mountains(img, y, rng)
    firs(img, rng)
    lake(img)
    vignette = 1 - 0.35 * (((x - WIDTH / 2) / WIDTH) ** 2 + ((y - HEIGHT * 0.45) / HEIGHT) ** 2)
    return np.clip(img * vignette[..., None], 0, 255)


def frosted(img: Image.Image, box: tuple, tint: tuple, amount: float) -> Image.Image:
    """`box` of `img` blurred and tinted, as a lock screen's translucent cards are."""
    region = img.crop(box).filter(ImageFilter.GaussianBlur(14))
    return Image.blend(region, Image.new("RGB", region.size, tint), amount)


def rounded(img: Image.Image, box: tuple, radius: int, fill: Image.Image) -> None:
    mask = Image.new("L", (box[2] - box[0], box[3] - box[1]), 0)
    ImageDraw.Draw(mask).rounded_rectangle((0, 0, mask.width - 1, mask.height - 1), radius, fill=255)
    img.paste(fill, box[:2], mask)


def bubble(draw: ImageDraw.ImageDraw, ix: int, iy: int) -> None:
    draw.ellipse((ix + 9, iy + 11, ix + 35, iy + 31), fill=(255, 255, 255))
    draw.polygon([(ix + 13, iy + 27), (ix + 11, iy + 37), (ix + 21, iy + 30)], fill=(255, 255, 255))


def sun_cloud(draw: ImageDraw.ImageDraw, ix: int, iy: int) -> None:
    draw.ellipse((ix + 18, iy + 7, ix + 38, iy + 27), fill=(255, 214, 10))
    for box in ((ix + 6, iy + 20, ix + 26, iy + 36), (ix + 15, iy + 14, ix + 33, iy + 34),
                (ix + 24, iy + 22, ix + 38, iy + 36)):
        draw.ellipse(box, fill=(255, 255, 255))


def notification(img: Image.Image, top: int, icon: tuple, glyph, app: str, when: str,
                 title: str, body: str) -> None:
    box = (28, top, WIDTH - 28, top + 138)
    rounded(img, box, 30, frosted(img, box, (235, 240, 250), 0.30))
    draw = ImageDraw.Draw(img)
    ix, iy = box[0] + 24, top + 24
    draw.rounded_rectangle((ix, iy, ix + 44, iy + 44), 11, fill=icon)
    glyph(draw, ix, iy)
    dim, white = (225, 230, 240), (255, 255, 255)
    draw.text((ix + 60, iy + 22), app.upper(), font=font(21), fill=dim, anchor="lm")
    draw.text((box[2] - 26, iy + 22), when, font=font(21), fill=dim, anchor="rm")
    draw.text((box[0] + 24, top + 88), title, font=font(27), fill=white, anchor="lm")
    draw.text((box[0] + 24, top + 119), body, font=font(24), fill=dim, anchor="lm")


def button(img: Image.Image, cx: int, cy: int, glyph) -> None:
    r = 50
    box = (cx - r, cy - r, cx + r, cy + r)
    mask = Image.new("L", (2 * r, 2 * r), 0)
    ImageDraw.Draw(mask).ellipse((0, 0, 2 * r - 1, 2 * r - 1), fill=255)
    img.paste(frosted(img, box, (20, 26, 40), 0.45), box[:2], mask)
    glyph(ImageDraw.Draw(img), cx, cy)


def torch(draw: ImageDraw.ImageDraw, cx: int, cy: int) -> None:
    white = (250, 250, 252)
    head = [(cx - 15, cy - 24), (cx + 15, cy - 24), (cx + 9, cy - 6), (cx - 9, cy - 6)]
    draw.polygon(head, outline=white, width=4)
    draw.rounded_rectangle((cx - 9, cy - 6, cx + 9, cy + 28), 4, outline=white, width=4)
    draw.ellipse((cx - 3, cy + 4, cx + 3, cy + 10), fill=white)


def camera(draw: ImageDraw.ImageDraw, cx: int, cy: int) -> None:
    white = (250, 250, 252)
    draw.rounded_rectangle((cx - 27, cy - 15, cx + 27, cy + 21), 7, outline=white, width=4)
    draw.rectangle((cx - 10, cy - 22, cx + 10, cy - 15), fill=white)
    draw.ellipse((cx - 11, cy - 8, cx + 11, cy + 14), outline=white, width=4)


def chrome(img: Image.Image) -> None:
    """The status bar, the padlock and the home bar."""
    draw = ImageDraw.Draw(img)
    white = (250, 250, 252)
    draw.text((40, 42), "frost", font=font(25), fill=white, anchor="lm")
    for i in range(4):  # signal bars
        draw.rounded_rectangle((574 + i * 11, 50 - 6 - i * 5, 581 + i * 11, 52), 2, fill=white)
    draw.rounded_rectangle((634, 32, 690, 53), 6, outline=white, width=3)  # battery
    draw.rounded_rectangle((639, 37, 673, 48), 3, fill=white)
    draw.rectangle((692, 38, 696, 47), fill=white)
    cx = WIDTH // 2  # the padlock
    draw.arc((cx - 13, 84, cx + 13, 116), 180, 360, fill=white, width=5)
    draw.line((cx - 11, 100, cx - 11, 106), fill=white, width=5)
    draw.line((cx + 11, 100, cx + 11, 106), fill=white, width=5)
    draw.rounded_rectangle((cx - 19, 104, cx + 19, 134), 6, fill=white)
    draw.rounded_rectangle((cx - 67, 1243, cx + 67, 1252), 5, fill=white)


def lockscreen() -> np.ndarray:
    """The lock screen's static parts over the wallpaper, the clock box left bare."""
    img = Image.fromarray(wallpaper().astype(np.uint8))
    chrome(img)
    notification(img, 800, (52, 199, 89), bubble, "Messages", "now", "Anna",
                 "Look at the window - it's all frost!")
    notification(img, 954, (10, 132, 255), sun_cloud, "Weather", "12m ago", "Frost tonight",
                 "-6 \N{DEGREE SIGN}C by dawn, clear skies, aurora likely")
    button(img, 112, 1166, torch)
    button(img, WIDTH - 112, 1166, camera)
    out = np.asarray(img)
    x0, y0, x1, y1 = CLOCK_BOX
    assert out[y0:y1, x0:x1].shape == (y1 - y0, x1 - x0, 3)
    return out


def main() -> None:
    static = lockscreen()
    Image.fromarray(static).save(OUT, optimize=True)
    print(f"wrote {OUT}")
    if len(sys.argv) == 3 and sys.argv[1] == "--preview":
        Image.fromarray(with_clock(static, DEFAULT_MINUTE)).save(sys.argv[2])
        print(f"wrote {sys.argv[2]} (the clock at {DEFAULT_MINUTE})")


if __name__ == "__main__":
    main()
