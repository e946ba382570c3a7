"""Make the installed page's icons, app/web/icons/*.png: the six-armed flake of the page's
favicon (index.html's SVG), light on the night blue, for the home screen.

`icon-192.png`, `icon-512.png`: a rounded square, as the favicon (corners transparent);
`maskable-192.png`, `maskable-512.png`: the square filled to its edges (a launcher cuts it
to its own shape: circle, squircle, teardrop) with the whole flake inside the safe zone, the
centred circle of 40 % of the side in radius that every mask keeps.

Origin: drawn entirely by this script (numpy + Pillow) for the frost project: each arm and
branch is a stroke with round ends, its coverage of every pixel from the distance to the
stroke's segment (one pixel of antialiasing). Deterministic. Usage:
python3 assets/make_icons.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

OUT = Path(__file__).resolve().parent.parent / "app" / "web" / "icons"
NIGHT = (0x1C, 0x24, 0x50)  # the favicon's square
ICE = (0xE8, 0xF0, 0xFF)  # its flake
SIZES = (192, 512)
SAFE = 0.40  # the maskable safe zone's radius, a fraction of the side
# (purpose, size) -> file name; the manifest (app/serve/install.py) lists them.
FILES = {("any", n): f"icon-{n}.png" for n in SIZES} | {("maskable", n): f"maskable-{n}.png" for n in SIZES}


def flake_segments(reach: float) -> list[tuple[float, float, float, float]]:
    """The flake's strokes (x0, y0, x1, y1) about (0, 0), in units of the side: six arms
    `reach` long, each with two pairs of branches leaning out at 60 degrees."""
    segments = []
    for k in range(6):
        a = np.pi / 2 + k * np.pi / 3
        ux, uy = np.cos(a), -np.sin(a)
        segments.append((0.0, 0.0, reach * ux, reach * uy))
        for at, length in ((0.42, 0.21), (0.70, 0.16)):
            bx, by = at * reach * ux, at * reach * uy
            for side in (-1, 1):
                b = a + side * np.pi / 3
                segments.append((bx, by, bx + length * reach * np.cos(b), by - length * reach * np.sin(b)))
    return segments


def _distance(px: np.ndarray, py: np.ndarray, seg) -> np.ndarray:
    """Each pixel's distance to a segment."""
    x0, y0, x1, y1 = seg
    dx, dy = x1 - x0, y1 - y0
    t = np.clip(((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
    return np.hypot(px - x0 - t * dx, py - y0 - t * dy)


def flake_coverage(size: int, reach: float, width: float) -> np.ndarray:
    """How much of each pixel of a `size` square the flake covers, 0..1 (`reach` and the
    stroke's `width` in units of the side)."""
    centres = (np.arange(size) + 0.5) / size - 0.5
    px, py = np.meshgrid(centres, centres)
    d = np.min([_distance(px, py, s) for s in flake_segments(reach)], axis=0)
    return np.clip((width / 2 - d) * size + 0.5, 0.0, 1.0)


def square_coverage(size: int, radius: float) -> np.ndarray:
    """A rounded square filling the side, corners `radius` (units of the side), 0..1."""
    centres = np.abs((np.arange(size) + 0.5) / size - 0.5)
    qx, qy = np.meshgrid(centres, centres)
    inner = 0.5 - radius
    outside = np.hypot(np.maximum(qx - inner, 0), np.maximum(qy - inner, 0)) - radius
    return np.clip(0.5 - outside * size, 0.0, 1.0)


def make(purpose: str, size: int) -> Image.Image:
    """The icon of `purpose` ("any": RGBA rounded square; "maskable": opaque RGB)."""
    if purpose == "any":  # the favicon's proportions: arms about 6/16 of the side
        flake = flake_coverage(size, 0.37, 0.05)
        shape = square_coverage(size, 3 / 16)
    else:  # the flake's farthest point (arm and stroke) well inside the safe zone
        flake = flake_coverage(size, 0.30, 0.042)
        shape = np.ones((size, size))
    night, ice = np.array(NIGHT, float), np.array(ICE, float)
    rgb = night + (ice - night) * flake[..., None]
    if purpose == "maskable":
        return Image.fromarray((rgb + 0.5).astype(np.uint8), "RGB")
    rgba = np.dstack([rgb, 255 * shape])
    return Image.fromarray((rgba + 0.5).astype(np.uint8), "RGBA")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for (purpose, size), name in FILES.items():
        make(purpose, size).save(OUT / name, optimize=True)
        print(f"wrote {OUT / name}")


if __name__ == "__main__":
    main()
