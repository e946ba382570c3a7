"""The hash grid of Sec. 3.3: cell keys (Eq. 1) and the cells a freezing area covers."""

from __future__ import annotations

import math

import numpy as np

# A crystal is listed in every cell its freezing disc reaches, widened by this many
# px so float32 rounding of a walker's cell or distance can never hide a crystal that
# is within hc (the exact test `d^2 < hc^2` decides freezing; this only lists).
CELL_MARGIN = 1e-2
_OFF_3 = np.arange(3)


class HashGrid:
    """Cells of side 2*hc covering a w x h screen (Eq. 1, rounded up)."""

    def __init__(self, width: int, height: int, hc: float, wrap: bool = False):
        self.cell = 2.0 * hc
        # A tile: distances are taken over the wrap, and a crystal is also listed in the
        # cells its disc reaches across an edge (its images one size over).
        self.period = (np.float32(width), np.float32(height)) if wrap else None
        self._images = np.array([(sx, sy) for sx in (0, -width, width) for sy in (0, -height, height)]
                                if wrap else [(0, 0)], np.float64)
        self.cols = math.ceil(width / self.cell)   # N, Eq. 1a
        self.rows = math.ceil(height / self.cell)  # M, Eq. 1b
        self.size = self.cols * self.rows
        self._size = np.array([self.cols, self.rows])[None, :, None]  # (for disc_cells)
        self._inverse_cell = np.float32(1.0 / self.cell)
        self._cols = np.int32(self.cols)
        self._last = (np.int32(self.cols - 1), np.int32(self.rows - 1))  # (for keys)

    def keys(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Cell index (row-major) of on-screen points."""
        kx = (x * self._inverse_cell).astype(np.int32)
        ky = (y * self._inverse_cell).astype(np.int32)
        np.minimum(kx, self._last[0], out=kx)
        np.minimum(ky, self._last[1], out=ky)
        ky *= self._cols
        ky += kx
        return ky

    def span(self, x0: float, y0: float, x1: float, y1: float) -> tuple[np.ndarray, np.ndarray]:
        """(cols, rows): the column and row indices of the cells under a px box, clipped."""
        cols = np.arange(max(int(x0 // self.cell), 0), min(int(x1 // self.cell), self.cols - 1) + 1)
        rows = np.arange(max(int(y0 // self.cell), 0), min(int(y1 // self.cell), self.rows - 1) + 1)
        return cols, rows

    def disc_cells(self, pts: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
        """(cells, owner): every cell whose rectangle meets the open disc of `radius`
        around each point (at most 3x3 with the margin), owner indexing `pts`.
        Pairs come point-major, so each cell sees its owners in ascending order."""
        p = pts.astype(np.float64)
        if len(self._images) > 1:  # each point's images, point-major (ascending owners kept)
            p = (p[:, None, :] + self._images[None]).reshape(-1, 2)
        r = radius + CELL_MARGIN
        s = self.cell
        # The 3 columns and 3 rows from each disc's box corner: (point, x or y, 3).
        near = np.floor((p - r) / s).astype(np.int64)[:, :, None] + _OFF_3
        # Per axis, the gap from the disc's centre to each cell's span (0 inside it).
        c = p[:, :, None]
        gap = np.maximum(np.maximum(near * s - c, 0), c - (near + 1) * s)
        gap *= gap
        on = (near >= 0) & (near < self._size)
        # (point, row, column): the 3 x 3 cells, row-major as the cell keys.
        ok = gap[:, 1, :, None] + gap[:, 0, None, :] < r * r
        ok &= on[:, 1, :, None] & on[:, 0, None, :]
        cells = (near[:, 1, :, None] * self.cols + near[:, 0, None, :])[ok].astype(np.int32)
        owner = ok.nonzero()[0]  # (row-major: each point's cells in turn)
        return cells, owner // len(self._images) if len(self._images) > 1 else owner
