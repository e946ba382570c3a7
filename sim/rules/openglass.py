"""Fronds (docs/method.md, section 8): where window water lands under frond rules 2 and 3.

- Water on open glass (rule 2): the pane's water lands in hash cells at least `water_far`
  cell rings (Chebyshev, in cells of 2 hc) from every candidate cell; nearer free glass
  (outside candidate cells) is drawn with weight `near_water` of a far cell. Diffusing in
  from afar, water meets what sticks out first, which screens the rest (Couder et al.,
  Phys. Rev. E 2005); water placed right beside the ice removed that screening. The cells
  are recomputed whenever the candidate cells change, so a melt's clearing counts at once.
  The pool holds FAR_DENSITY walkers per far cell (a near one counting `near_water`), at
  most `humidity`: glass counted by area, so a wipe in a dry region still gets water.
- Humidity field (rule 3): a smooth random log-normal weight over the pane (blobs of about
  BLOB_PX, variance of the log `vapour_var`, drawn from the simulation's random stream
  before the seeds) multiplies the far cells' weights: denser and more open regions.
"""

from __future__ import annotations

import numpy as np

from ..core.placement import first_good
from ..params import Params
from .fronds import FRAME_PX, edge_distance
from .window_mode import REFERENCE_C, TRIES, Pane

# Walkers per far cell of glass. At 2.5 (the band's density without the fronds) a 40 px
# wipe was 38 % back after 300 ticks in a prototype; 8 refroze it.
FAR_DENSITY = 8.0
# Where the frame's chill is this share of its most or more (within 150 ln(1 / 0.7) = 53 px
# of the edge), water lands beside the ice. At 0.5 (104 px) the frame's short dense stems
# pulled stem_lw under 75 px (72, seeds 0-2) and a wipe came back 121-143 %; at 0.7
# frame/mid is 1.5 with stem_lw 77 px.
FRAME_NEAR = 0.7
# Size of the humidity field's blobs, px: the Gaussian blur's sigma is half of it.
BLOB_PX = 200.0


class OpenGlass(Pane):
    """The pane's pool placed on open glass (see module doc)."""

    def __init__(self, params: Params, rng: np.random.Generator, index, ice,
                 tries_at_once: bool):
        super().__init__(params, rng, index, ice)
        self.tries_at_once = tries_at_once
        p, grid = params, index.grid
        self.far_rings, self.near_weight = p.water_far, float(p.near_water)
        self.vapour = np.ones(grid.size)
        self.chill = np.ones(grid.size)
        self.rings = np.full(grid.size, p.water_far)  # far enough, per cell
        # Colder glass takes more vapour: the supply follows the temperature, so colder is
        # faster as well as denser (with the hits at their floor of 1 it was not).
        self.supply = p.temperature / REFERENCE_C
        self._key: tuple[int, int] | None = None
        self._cells = np.empty(0, np.int64)
        self._cumulative_weight = np.empty(0)
        self._area = 0.0
        self.wet = np.zeros(grid.size, bool)

    def start(self) -> tuple[np.ndarray, np.ndarray] | None:
        p, grid = self.params, self.index.grid
        if p.vapour_var:
            self.vapour = humidity_field(self.rng, grid.rows, grid.cols, grid.cell, p.vapour_var)
        if p.frame_chill:
            self.chill = frame_weight(grid, self.index.width, self.index.height, p.frame_chill)
            # By the colder frame water freezes beside the ice (as without the fronds).
            near_frame = (self.chill - 1.0) / p.frame_chill >= FRAME_NEAR
            self.rings = np.where(near_frame, 0, self.far_rings).astype(np.int16)
        return super().start()

    def chilled(self, temperature: float, supply: float) -> None:
        """The weather's glass: the supply follows its `temperature`, times `supply`."""
        self.supply = temperature / REFERENCE_C * supply

    def melted(self, dead: np.ndarray) -> None:
        """The cells whose crystals melted stay wet until they hold a crystal again."""
        super().melted(dead)
        c = self.ice.crystals.raw()[dead]
        self.wet[self.index.grid.keys(c[:, 0], c[:, 1])] = True

    def pool(self, humidity: int) -> int:
        self._update()
        return int(self.supply * min(humidity, FAR_DENSITY * self._area))

    def place(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """n spots of glass in cells drawn by weight; `ok` False where TRIES draws found
        none. The first try of every walker is drawn and checked at once; then (from
        session version 4) all the later tries of those left, in one batch: each walker
        takes its first good try, as if drawn one round at a time, for two passes over the
        ice instead of up to TRIES (half the window's tick was these passes)."""
        self._update()
        x, y, ok = np.zeros(n, np.float32), np.zeros(n, np.float32), np.zeros(n, bool)
        if not len(self._cells):
            return x, y, ok
        if not self.tries_at_once:
            return self._place_by_rounds(x, y, ok)
        px, py = self._draw(n)
        good = self.index.glass(px, py)
        x[good], y[good], ok[good] = px[good], py[good], True
        todo = np.flatnonzero(~good)
        if len(todo) and TRIES > 1:
            px, py = self._draw((TRIES - 1) * len(todo))
            placed, pick = first_good(self.index.glass(px, py).reshape(TRIES - 1, len(todo)))
            x[todo[placed]], y[todo[placed]], ok[todo[placed]] = px[pick], py[pick], True
        return x, y, ok

    def _draw(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """k points, each uniform in a cell drawn by weight."""
        grid = self.index.grid
        u = self.rng.random((3, k))
        weights = self._cumulative_weight
        pick = np.minimum(np.searchsorted(weights, u[0] * weights[-1], side="right"),
                          len(self._cells) - 1)
        cell = self._cells[pick]
        s = grid.cell
        return (((cell % grid.cols + u[1]) * s).astype(np.float32),
                ((cell // grid.cols + u[2]) * s).astype(np.float32))

    def _place_by_rounds(self, x, y, ok) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Session files before version 4: TRIES rounds, one try each of those left."""
        todo = np.arange(len(x))
        for _ in range(TRIES):
            if len(todo) == 0:
                break
            px, py = self._draw(len(todo))
            good = self.index.glass(px, py)
            x[todo[good]], y[todo[good]], ok[todo[good]] = px[good], py[good], True
            todo = todo[~good]
        return x, y, ok

    def _own_counts(self) -> np.ndarray:
        """Live crystals whose own cell each cell is."""
        self.band()  # (brings the counts up to date)
        return self._own

    def _update(self) -> None:
        """Far and near cells and their cumulative weights, when the ice changed."""
        key = self.ice_key()  # (what the cells follow: the ice)
        if key == self._key:
            return
        self._key = key
        grid = self.index.grid
        dist = ring_distance(self.index.candidates.count > 0, grid.rows, grid.cols,
                             self.far_rings)
        far = (dist >= self.rings) & ((dist > 0) | (self._own_counts() == 0))
        near = (dist > 0) & ~far
        if self.wet.any():
            self.wet &= self._own_counts() == 0
            near |= self.wet & ~far
        w = self.chill * np.where(far, self.vapour, np.where(near, self.near_weight, 0.0))
        self._cells = np.flatnonzero(w > 0)
        self._cumulative_weight = np.cumsum(w[self._cells])
        self._area = float(far.sum() + self.near_weight * near.sum())


def ring_distance(candidate: np.ndarray, rows: int, cols: int, cap: int) -> np.ndarray:
    """Per flat cell the Chebyshev distance in cells to the nearest candidate cell (0 for
    one), at most `cap`."""
    grown = candidate.reshape(rows, cols)
    dist = np.zeros((rows, cols), np.int16)
    for _ in range(cap):
        dist += ~grown
        grown = _dilate(grown)
    return dist.ravel()


def _dilate(mask: np.ndarray) -> np.ndarray:
    """A 2-D mask grown by one cell in every direction (8 neighbours)."""
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    wide = out.copy()
    out[:, 1:] |= wide[:, :-1]
    out[:, :-1] |= wide[:, 1:]
    return out


def frame_weight(grid, width: int, height: int, chill: float) -> np.ndarray:
    """Per cell 1 + chill x e^(-d / FRAME_PX), d its centre's distance to the screen's edge:
    the colder frame draws more of the water (rule 4)."""
    cy, cx = np.divmod(np.arange(grid.size), grid.cols)
    centres = np.column_stack(((cx + 0.5) * grid.cell, (cy + 0.5) * grid.cell))
    d = edge_distance(np.minimum(centres, [width, height]), (width, height))
    return 1.0 + chill * np.exp(-d / FRAME_PX)


def humidity_field(rng: np.random.Generator, rows: int, cols: int, cell: float,
                   var: float) -> np.ndarray:
    """A flat per-cell log-normal weight of mean about 1: white noise blurred to blobs of
    about BLOB_PX, standardised, exp(sqrt(var) z - var / 2)."""
    z = rng.standard_normal((rows, cols))
    sigma = BLOB_PX / 2.0 / cell
    z = _blur(rows, sigma) @ z @ _blur(cols, sigma).T
    z = (z - z.mean()) / max(float(z.std()), 1e-12)
    return np.exp(np.sqrt(var) * z - var / 2.0).ravel()


def _blur(n: int, sigma: float) -> np.ndarray:
    """n x n Gaussian smoothing matrix, rows normalised (the edges renormalised)."""
    i = np.arange(n)
    k = np.exp(-0.5 * ((i[:, None] - i[None, :]) / sigma) ** 2)
    return k / k.sum(axis=1, keepdims=True)
