"""One freezing index over the crystals: the hash grid's candidate cells (Sec. 3.4.1), the
neighbour search and the clearance rings, with the queries the rules and placement ask."""

from __future__ import annotations

import numpy as np

from ..core.buffers import CellLists, Growable
from .clearance import make_clearance
from .grid import HashGrid
from .periodic import nearest_image
from .search import make_search


class FreezingIndex:
    """Where the live crystals of `crystals` (the skeleton's positions, read, never
    written) are: each is listed in every cell its freezing disc (radius hc) meets."""

    def __init__(self, crystals: Growable, width: int, height: int, hc: float,
                 search: str, wrap: bool, clearance: bool):
        self.crystals = crystals
        self.width, self.height, self.hc = width, height, hc
        self.grid = HashGrid(width, height, hc, wrap)
        self.candidates = CellLists(self.grid.size)  # Fig. 3d: state = count > 0
        self.search = make_search(search, self.grid, self.candidates, hc)
        self.clearance = make_clearance(self.grid, width, height, clearance)

    def register(self, new: slice) -> None:
        """Sec. 3.4.1: list crystals `new` in the cells their freezing discs reach."""
        if new.stop == new.start:
            return
        pts = self.crystals.raw()[new]
        ids = np.arange(new.start, new.stop, dtype=np.int32)
        cells, owner = self.grid.disc_cells(pts, self.hc)
        self.clearance.lower(self.candidates.insert(cells, ids[owner]))
        self.search.insert(pts, ids)

    def remove(self, dead: np.ndarray) -> None:
        """Melted crystals leave their cells and the search."""
        pts = self.crystals.raw()[dead]
        cells, _ = self.grid.disc_cells(pts, self.hc)
        self.candidates.remove(cells, dead)
        self.search.remove(pts, dead)

    def nearest(self, x: np.ndarray, y: np.ndarray,
                keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Sec. 3.4.3: the walkers at (x, y) within hc of a crystal, and their nearest
        crystal (`keys`: the walkers' cells, where known)."""
        return self.search.nearest(self.crystals.raw(), x, y, keys)

    def nearest_d2(self, pts: np.ndarray) -> np.ndarray:
        """Squared distance from each point to the nearest live crystal listed in its cell
        (inf if none). Any crystal within hc of a point is listed in the point's cell."""
        d2 = np.empty(len(pts), np.float32)
        d2.fill(np.inf)
        if len(pts) == 0:
            return d2
        counts, starts, rows, ids = self.candidates.listed(self.grid.keys(pts[:, 0], pts[:, 1]))
        if len(ids) == 0:
            return d2
        d = self.crystals.raw()[ids] - pts[rows]
        dx, dy = d[:, 0], d[:, 1]
        period = self.grid.period
        if period is not None:  # a tile: over the wrap
            dx, dy = nearest_image(dx, period[0]), nearest_image(dy, period[1])
        e = dx ** 2 + dy ** 2
        some = counts > 0
        if some.all():  # (the usual case for spots beside the ice)
            return np.minimum.reduceat(e, starts).astype(np.float32, copy=False)
        d2[some] = np.minimum.reduceat(e, starts[some])
        return d2

    def glass(self, px: np.ndarray, py: np.ndarray) -> np.ndarray:
        """On the screen's far edges and at least hc / 2 from every live crystal."""
        good = (px < self.width) & (py < self.height)
        d2 = self.nearest_d2(np.column_stack((px[good], py[good])))
        good[good] = d2 >= np.float32(self.hc / 2) ** 2
        return good

    def free(self, px: np.ndarray, py: np.ndarray) -> np.ndarray:
        """On the screen and in no candidate cell."""
        good = (px >= 0) & (px < self.width) & (py >= 0) & (py < self.height)
        if good.all():  # (the usual case)
            return self.candidates.count[self.grid.keys(px, py)] == 0
        good[good] = self.candidates.count[self.grid.keys(px[good], py[good])] == 0
        return good

    def crystals_in_box(self, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
        """Ascending indices of the live crystals listed in the cells under a px box (a
        superset of those inside it: every crystal is listed in its own cell)."""
        cols, rows = self.grid.span(x0, y0, x1, y1)
        cells = (rows[:, None] * self.grid.cols + cols[None, :]).ravel()
        ids, valid = self.candidates.gather(cells)
        return np.unique(ids[valid])

    def crystals_near(self, x: float, y: float, radius: float) -> np.ndarray:
        """Ascending indices of live crystals closer than `radius` to (x, y)."""
        ids = self.crystals_in_box(x - radius, y - radius, x + radius, y + radius)
        c = self.crystals.raw()[ids].astype(np.float64)
        return ids[np.hypot(c[:, 0] - x, c[:, 1] - y) < radius]

    def box_cells(self, cx: float, cy: float, r: float):
        """The flat indices of the cells under the disc's bounding box, with the squared
        distance from (cx, cy) to each cell's nearest and farthest point."""
        g = self.grid
        cols, rows = g.span(cx - r, cy - r, cx + r, cy + r)
        x0, y0 = cols[None, :] * g.cell, rows[:, None] * g.cell
        near_x, near_y = np.clip(cx, x0, x0 + g.cell) - cx, np.clip(cy, y0, y0 + g.cell) - cy
        far_x = np.maximum(np.abs(x0 - cx), np.abs(x0 + g.cell - cx))
        far_y = np.maximum(np.abs(y0 - cy), np.abs(y0 + g.cell - cy))
        flat = rows[:, None] * g.cols + cols[None, :]
        return flat.ravel(), (near_x ** 2 + near_y ** 2).ravel(), (far_x ** 2 + far_y ** 2).ravel()

    def annulus_cells(self, cx: float, cy: float, r_out: float, r_in: float,
                      free: bool = True) -> np.ndarray:
        """Flat indices of the cells with no crystal listed (any cell if not `free`) that
        meet the annulus."""
        flat, near2, far2 = self.box_cells(cx, cy, r_out)
        meets = (near2 <= r_out ** 2) & (far2 >= r_in ** 2)
        return flat[meets & ((self.candidates.count[flat] == 0) | (not free))]

    def nbytes(self) -> int:
        return self.candidates.nbytes() + self.search.nbytes() + self.clearance.nbytes()
