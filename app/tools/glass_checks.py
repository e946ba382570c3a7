"""What the glass look is for, measured on a drawn frame (the tests and the README use
these): the ice's colour along a link, the ridge's mass across a link by the seed and at
a leaf, and whether the view through the ice is displaced (not a blend of the view) while
clear glass stays exactly the background."""

from __future__ import annotations

import numpy as np

from app.gl.renderer import Renderer
from app.tools.offscreen import Offscreen
from sim import Params
from sim.maps import bump_field
from sim.material import film
from sim.screen import HEIGHT, WIDTH
from sim.session import touch_events

CENTRE = (WIDTH / 2, HEIGHT / 2)
TICKS = 750
NEAR_SEED = 50.0  # px: the links "by the seed"
CHECKER = 8  # px: side of the checkerboard's squares
MEDIUM = (0.3, 0.7)  # what the ice lets through of the view: "medium opacity"


def grown(ctx, look: str, preset: str = "fern", ticks: int = TICKS, seed: int = 0) -> Offscreen:
    """One touch at the centre grown `ticks` ticks with `look`."""
    run = Offscreen(ctx, Params.preset(preset, look=look), seed)
    run.grow(ticks, touch_events([CENTRE]))
    return run


def thickness(renderer: Renderer) -> tuple[np.ndarray, np.ndarray]:
    """The ice's thickness as the ice pass sees it, H x W px, in two parts: the bumps
    (through the film in the glass look) and the ridges (the feature surface read back
    from its texture)."""
    w, h = renderer.size
    bumps = bump_field(renderer.heights_grid(), renderer.params.grid_spacing, w, h)
    if renderer.look == "glass":
        bumps = film(bumps)
    renderer.features.draw_queued()
    tex = np.frombuffer(renderer.features.texture.read(), np.uint8).reshape(h, w, 4)[::-1]
    ridges = tex[..., 2] / 255.0 * renderer.height_scale * (tex[..., 3] / 255.0)
    return bumps.astype(np.float32), ridges.astype(np.float32)


def links(sim) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Live links as (parent xy, child xy, child index)."""
    child = np.flatnonzero((sim.parents >= 0) & sim.crystal_alive)
    return sim.crystals[sim.parents[child]], sim.crystals[child], child


def colour_variation(frame: np.ndarray, sim, least: float = 5.0) -> float:
    """Median over links at least `least` px long of the coefficient of variation of the
    frame's brightness along the link's middle 70 % (1 px steps)."""
    p, q, _ = links(sim)
    cvs = []
    for a, b in zip(p, q, strict=True):
        length = float(np.hypot(*(b - a)))
        if length < least:
            continue
        t = np.linspace(0.15, 0.85, max(int(0.7 * length), 3))
        xy = np.rint(a + t[:, None] * (b - a)).astype(int)
        v = frame[np.clip(xy[:, 1], 0, frame.shape[0] - 1),
                  np.clip(xy[:, 0], 0, frame.shape[1] - 1)].mean(axis=1)
        cvs.append(v.std() / max(v.mean(), 1e-9))
    return float(np.median(cvs))


def ridge_mass(thick: np.ndarray, sim, reach: float) -> tuple[float, float]:
    """Median over links of the thickness `thick` (the ridges, say) summed across the
    link's midpoint (within
    `reach` px each side, 0.5 px steps): for links whose midpoint lies within NEAR_SEED px
    of the centre, and for leaf links (whose crystal has no children)."""
    p, q, child = links(sim)
    has_children = np.bincount(sim.parents[sim.parents >= 0], minlength=len(sim.parents)) > 0
    mid = 0.5 * (p + q)
    d = q - p
    n = np.column_stack((-d[:, 1], d[:, 0])) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)[:, None]
    s = np.arange(-reach, reach + 0.25, 0.5)
    xy = np.rint(mid[:, None, :] + s[None, :, None] * n[:, None, :]).astype(int)
    xs = np.clip(xy[..., 0], 0, thick.shape[1] - 1)
    ys = np.clip(xy[..., 1], 0, thick.shape[0] - 1)
    mass = thick[ys, xs].sum(axis=1) * 0.5
    near = np.hypot(*(mid - np.asarray(CENTRE)).T) < NEAR_SEED
    return float(np.median(mass[near])), float(np.median(mass[~has_children[child]]))


def checkerboard(width: int = WIDTH, height: int = HEIGHT, side: int = CHECKER) -> np.ndarray:
    y, x = np.mgrid[0:height, 0:width]
    on = ((x // side + y // side) % 2).astype(np.uint8) * 255
    return np.repeat(on[:, :, None], 3, axis=2)


def view_through(run: Offscreen, thick: np.ndarray) -> dict:
    """The frame over black, white and a checkerboard. Over black and white the ice's own
    light and its transmission T = (white - black) / 255 follow exactly (a flat view shifts
    to itself); over the checkerboard the view seen through it is (checker - black) / T.
    Where T is medium, `displaced` is the share of pixels whose view differs from the
    checkerboard under them by over a quarter of its contrast (a blend: none);
    `clear_exact` says every pixel with no ice shows the checkerboard exactly."""
    frames = {}
    for name, image in (("black", np.zeros((HEIGHT, WIDTH, 3), np.uint8)),
                        ("white", np.full((HEIGHT, WIDTH, 3), 255, np.uint8)),
                        ("checker", checkerboard())):
        run.renderer.set_background_image(image, name)
        frames[name] = run.frame().astype(np.float64)
    black, white, checker = frames["black"], frames["white"], frames["checker"]
    through = ((white - black) / 255.0).mean(axis=2)
    medium = (through >= MEDIUM[0]) & (through <= MEDIUM[1])
    seen = (checker - black).mean(axis=2) / np.maximum(through, 1e-6)
    under = checkerboard()[..., 0].astype(np.float64)
    clear = thick <= 0
    return {"medium_px": int(medium.sum()),
            "displaced": float((np.abs(seen - under) > 64)[medium].mean()) if medium.any() else 0.0,
            "clear_px": int(clear.sum()),
            "clear_exact": bool((checker[clear] == checkerboard()[clear]).all())}
