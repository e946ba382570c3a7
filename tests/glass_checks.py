"""What the glass look is for, measured on a drawn frame (the tests and docs/looks.md use
these): the ice's colour along a link, the ridge's mass across a link by the seed and at
a leaf and how it grows with what the link carries, the ice's tint by thickness, and
whether the view through the ice is displaced (not a blend of the view) while clear
glass stays exactly the background."""

from __future__ import annotations

import numpy as np

from app.gl.renderer import Renderer
from app.tools.offscreen import Offscreen
from sim import Params
from sim.io.timeline import touch_events
from sim.look.maps import bump_field
from sim.look.material import film
from sim.screen import HEIGHT, WIDTH

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


def carried(sim) -> np.ndarray:
    """Live crystals each crystal's link carries (itself and all grown from it), summed
    from the leaves down: a parent is always older than its child."""
    n = sim.crystal_alive.astype(np.int64)
    for c in range(len(n) - 1, -1, -1):
        if sim.parents[c] >= 0:
            n[sim.parents[c]] += n[c]
    return n


def colour_variation(ice: np.ndarray, sim) -> float:
    """The ice colour's variation along a link, as the issue measures it: median over
    live links of the coefficient of variation of the ice's own colour (`ice`: the frame
    over a black backdrop, so the view behind adds nothing) sampled every px along the
    link's centre line, from the parent crystal to the child."""
    p, q, _ = links(sim)
    cvs = []
    for a, b in zip(p, q, strict=True):
        t = np.linspace(0.0, 1.0, max(int(np.hypot(*(b - a))) + 1, 3))
        xy = np.rint(a + t[:, None] * (b - a)).astype(int)
        v = ice[np.clip(xy[:, 1], 0, ice.shape[0] - 1),
                np.clip(xy[:, 0], 0, ice.shape[1] - 1)].astype(np.float64).mean(axis=1)
        cvs.append(v.std() / max(v.mean(), 1e-9))
    return float(np.median(cvs))


def cross_mass(thick: np.ndarray, sim, reach: float) -> np.ndarray:
    """Per live link (in `links` order), the thickness `thick` (the ridges, say) summed
    across the link's midpoint, within `reach` px each side, 0.5 px steps."""
    p, q, _ = links(sim)
    mid = 0.5 * (p + q)
    d = q - p
    n = np.column_stack((-d[:, 1], d[:, 0])) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)[:, None]
    s = np.arange(-reach, reach + 0.25, 0.5)
    xy = np.rint(mid[:, None, :] + s[None, :, None] * n[:, None, :]).astype(int)
    xs = np.clip(xy[..., 0], 0, thick.shape[1] - 1)
    ys = np.clip(xy[..., 1], 0, thick.shape[0] - 1)
    return thick[ys, xs].sum(axis=1) * 0.5


def ridge_mass(thick: np.ndarray, sim, reach: float) -> tuple[float, float]:
    """Median `cross_mass` of the links whose midpoint lies within NEAR_SEED px of the
    centre, and of leaf links (whose crystal has no children)."""
    p, q, child = links(sim)
    has_children = np.bincount(sim.parents[sim.parents >= 0], minlength=len(sim.parents)) > 0
    mass = cross_mass(thick, sim, reach)
    near = np.hypot(*(0.5 * (p + q) - np.asarray(CENTRE)).T) < NEAR_SEED
    return float(np.median(mass[near])), float(np.median(mass[~has_children[child]]))


def width_law(thick: np.ndarray, sim, reach: float, most: int = 32) -> float:
    """How a ridge's cross-section grows with what its link carries: the slope of log
    (median cross_mass) on log (median count) over octaves of the carried count n from
    1 to `most` (links at least 3 px long; octaves of fewer than 5 links left out).
    The pipe model (half-width ~ n^(1/3), a ridge's cross-section ~ width^2) says 2/3."""
    _, _, child = links(sim)
    n = carried(sim)[child]
    mass = cross_mass(thick, sim, reach)
    p, q, _ = links(sim)
    long = np.hypot(*(q - p).T) >= 3.0
    x, y = [], []
    for lo in 2 ** np.arange(int(np.log2(most)) + 1):
        pick = long & (n >= lo) & (n < 2 * lo)
        if pick.sum() >= 5:
            x.append(np.log(np.median(n[pick])))
            y.append(np.log(max(float(np.median(mass[pick])), 1e-9)))
    return float(np.polyfit(x, y, 1)[0])


def tint(ice: np.ndarray, alpha: np.ndarray, thick: np.ndarray) -> tuple[float, float]:
    """Median blue minus red of the ice's own colour (`ice` over black, divided by its
    opacity `alpha`, 0..1) in thin ice (thickness under 1 px, alpha over 0.1) and in
    thick ice (over 3 px): glass ice is clear with a cold tint when thin, white when thick."""
    colour = ice / np.maximum(alpha, 1e-3)[..., None] / 255.0
    cold = colour[..., 2] - colour[..., 0]
    thin = (thick > 0) & (thick < 1.0) & (alpha > 0.1)
    return float(np.median(cold[thin])), float(np.median(cold[thick > 3.0]))


def checkerboard(width: int = WIDTH, height: int = HEIGHT, side: int = CHECKER) -> np.ndarray:
    y, x = np.mgrid[0:height, 0:width]
    on = ((x // side + y // side) % 2).astype(np.uint8) * 255
    return np.repeat(on[:, :, None], 3, axis=2)


def frames_over(run: Offscreen) -> dict[str, np.ndarray]:
    """The frame over black, white and the checkerboard (float64); the renderer keeps
    the checkerboard as its backdrop."""
    frames = {}
    for name, image in (("black", np.zeros((HEIGHT, WIDTH, 3), np.uint8)),
                        ("white", np.full((HEIGHT, WIDTH, 3), 255, np.uint8)),
                        ("checker", checkerboard())):
        run.renderer.set_background_image(image, name)
        frames[name] = run.frame().astype(np.float64)
    return frames


def opacity(frames: dict[str, np.ndarray]) -> np.ndarray:
    """What the ice hides of the view, 1 - (white - black) / 255: H x W."""
    return 1.0 - ((frames["white"] - frames["black"]) / 255.0).mean(axis=2)


def view_through(frames: dict[str, np.ndarray], thick: np.ndarray) -> dict:
    """From `frames_over`: over black and white the ice's own light and its transmission
    T = (white - black) / 255 follow exactly (a flat view shifts to itself); over the
    checkerboard the view seen through it is (checker - black) / T.
    Where T is medium, `displaced` is the share of pixels whose view differs from the
    checkerboard under them by over a quarter of its contrast (a blend: none);
    `clear_exact` says every pixel with no ice shows the checkerboard exactly."""
    black, checker = frames["black"], frames["checker"]
    through = 1.0 - opacity(frames)
    medium = (through >= MEDIUM[0]) & (through <= MEDIUM[1])
    seen = (checker - black).mean(axis=2) / np.maximum(through, 1e-6)
    under = checkerboard()[..., 0].astype(np.float64)
    clear = thick <= 0
    return {"medium_px": int(medium.sum()),
            "displaced": float((np.abs(seen - under) > 64)[medium].mean()) if medium.any() else 0.0,
            "clear_px": int(clear.sum()),
            "clear_exact": bool((checker[clear] == checkerboard()[clear]).all())}
