"""Long jumps (fern rule 3): how far a walker can jump without meeting ice.

A walker whose clearance rho (a lower bound of its distance to every freezing area, its
active area's rim and the screen edge) exceeds the walk step jumps to a uniformly random
point of the circle of radius rho around it. That is exact for Brownian motion: started at
the centre of a disc that holds no ice, it leaves the disc uniformly on its rim.

The bound comes from the hash grid: per cell, the Chebyshev distance in cells (capped) to
the nearest candidate cell. Every crystal's freezing disc lies inside candidate cells, so
a walker in a cell k rings away from them is at least (k - 1) cells plus its distance to
its own cell's border from any freezing area. The field is only lowered, where cells become
candidates; melting leaves it low, which stays a valid (smaller) bound.
"""

from __future__ import annotations

import numpy as np

from .grid import HashGrid

# Rings of cells looked at around a new candidate cell: beyond this the bound stays at
# CAP - 1 cells, and the area's rim or the screen usually bounds the jump anyway.
CAP = 8
# Jumps stop this many px short of the bound, so float32 rounding of the landing
# point can never bring a walker within hc of ice or off its area.
MARGIN = np.float32(1e-2)


class NoJumps:
    """The paper's walk: no walker jumps."""

    def lower(self, cells: np.ndarray) -> None:
        pass

    def radii(self, x, y, rim) -> None:
        return None

    def nbytes(self) -> int:
        return 0


class Clearance:
    """Per-cell lower bound of the distance to ice, in whole cells (see module doc)."""

    def __init__(self, grid: HashGrid, width: int, height: int, cap: int = CAP):
        self.grid, self.size = grid, (np.float32(width), np.float32(height))
        # The rings live on the grid padded by `cap` cells each side, so the rings around
        # any cell lie inside it: lowering them needs no bounds check. `_rings` is a flat
        # view from cell (0, 0), indexed by row * `_padded_cols` + column.
        self._cap, self._padded_cols = cap, grid.cols + 2 * cap
        self._padded = np.full((grid.rows + 2 * cap) * self._padded_cols, cap, np.int16)
        self._origin = cap * self._padded_cols + cap
        self._rings = self._padded[self._origin:]
        off = np.arange(-cap, cap + 1)
        ox, oy = np.meshgrid(off, off)
        self._offset_x, self._offset_y = ox.ravel(), oy.ravel()
        # the same cells, as offsets in the padded view
        self._padded_offsets = self._offset_y * self._padded_cols + self._offset_x
        self._ring = np.maximum(np.abs(self._offset_x), np.abs(self._offset_y)).astype(np.int16)
        self._cell = np.float32(grid.cell)
        # (k - 1) cells in px for each ring count k (float32 products, held as float64)
        self._beyond = ((np.arange(cap + 1) - 1).astype(np.float32) * self._cell).astype(np.float64)

    @property
    def rings(self) -> np.ndarray:
        """Each grid cell's ring count (row-major, a copy)."""
        g, cap = self.grid, self._cap
        return self._padded.reshape(-1, self._padded_cols)[cap:cap + g.rows, cap:cap + g.cols].ravel()

    def lower(self, cells: np.ndarray) -> None:
        """`cells` just became candidate cells: lower the rings around them (a cell
        given twice only costs more)."""
        if len(cells) == 0:
            return
        cy, cx = np.divmod(cells, self.grid.cols)
        if self.grid.period is None:
            # (the values as an array of the indices' shape: numpy 2.4's ufunc.at misreads
            # values it has to broadcast)
            at = (cy * self._padded_cols + cx + self._origin)[:, None] + self._padded_offsets
            np.minimum.at(self._padded, at, self._ring[None, :].repeat(len(cx), axis=0))
            return
        # A tile: the rings go on across the edges.
        tx, ty, ring = self._wrapped(cx[:, None] + self._offset_x, cy[:, None] + self._offset_y,
                                     self._ring[None, :].repeat(len(cx), axis=0))
        np.minimum.at(self._rings, ty * self._padded_cols + tx, ring)

    def _wrapped(self, tx, ty, ring):
        """Cells past an edge are the opposite edge's. The grid's last column and row may
        be narrower than a cell, so a ring counted across an edge may be up to a cell too
        far: each crossing counts one ring less (still a lower bound)."""
        cols, rows = self.grid.cols, self.grid.rows
        crossings = np.abs(np.floor_divide(tx, cols)) + np.abs(np.floor_divide(ty, rows))
        return tx % cols, ty % rows, np.maximum(ring - crossings, 0).astype(np.int16)

    def radii(self, x: np.ndarray, y: np.ndarray, rim: np.ndarray) -> np.ndarray:
        """Each walker's clearance rho in px (0 in and next to candidate cells), given its
        on-screen position and its distance `rim` to its area's rim."""
        s = self._cell
        qx, qy = np.trunc(x / s), np.trunc(y / s)  # its cell (Eq. 1), as whole numbers
        # Where it lies in its cell, and its distance to the cell's border: exact in the
        # walkers' own precision (q s is whole; Sterbenz's lemma covers x - q s, and s - f
        # wherever it is the nearer side), so float32 walkers need no float64 here.
        fx, fy = x - qx * s, y - qy * s
        border = np.minimum(np.minimum(fx, s - fx), np.minimum(fy, s - fy))
        k = self._rings[qy.astype(np.int32) * self._padded_cols + qx.astype(np.int32)]
        # (k - 1) s + border where k >= 1, else 0 (k = 0 gives -s + border < 0); float64,
        # where a float32 sum would round
        rho = np.maximum(self._beyond[k] + border, 0.0)
        if self.grid.period is not None:  # a tile has no edge: the rings wrap instead
            return np.minimum(rho, rim) - MARGIN
        w, h = self.size
        edge = np.minimum(np.minimum(x, w - x), np.minimum(y, h - y))
        return np.minimum(np.minimum(rho, rim), edge) - MARGIN

    def nbytes(self) -> int:
        return self._padded.nbytes


def make_clearance(grid: HashGrid, width: int, height: int, on: bool):
    return Clearance(grid, width, height) if on else NoJumps()
