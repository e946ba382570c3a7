"""Neighbour search (Sec. 3.4.3, Fig. 9): the walkers within hc of a crystal, and the nearest.

Two searches give the same answer, bit for bit (they share `nearest_listed`):
- `CandidateSearch`, the paper's: a walker looks only at the crystals listed in its own
  cell. Those are the candidate cells of Sec. 3.4.1, which list each crystal in every
  cell its freezing disc reaches. FrostSim keeps them for either search (water placement
  and the cell cap read them), so this search keeps nothing of its own.
- `Grid9Search`, Fig. 9's baseline: each crystal is listed in its own cell only, and a
  walker looks at the 3 x 3 cells around its own (cells are 2 hc wide, so they hold
  every crystal within hc).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ..core.buffers import CellLists
from .grid import HashGrid
from .periodic import nearest_image

# grid9 queries walkers in chunks of this many to bound the gather matrix.
_GRID9_CHUNK = 4096
_NO_ID = np.iinfo(np.int32).max  # above every crystal index (ties take the lowest)
_AROUND_X = np.array([-1, 0, 1, -1, 0, 1, -1, 0, 1])
_AROUND_Y = np.array([-1, -1, -1, 0, 0, 0, 1, 1, 1])


class NeighborSearch(Protocol):
    """What FrostSim asks of a neighbour search; ids are crystal indices, pts their positions."""

    def insert(self, pts: np.ndarray, ids: np.ndarray) -> None: ...

    def remove(self, pts: np.ndarray, ids: np.ndarray) -> None: ...

    def nearest(self, crystals: np.ndarray, x: np.ndarray, y: np.ndarray,
                keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(walkers, parents): the on-screen walkers (x[i], y[i]) within hc of a listed
        crystal, ascending, and the nearest one of each (lowest index among equals).
        `keys`: the walkers' cells (`HashGrid.keys`), where the caller has them."""
        ...

    def nbytes(self) -> int: ...


def make_search(kind: str, grid: HashGrid, candidates: CellLists, hc: float) -> NeighborSearch:
    """The search `Params.neighbor_search` names ("candidate" or "grid9")."""
    if kind == "grid9" and grid.period is not None:
        # The grid's last column and row may be cells narrower than hc, so the 3 x 3 cells
        # around a walker would miss ice across the edge; the candidate cells list it.
        raise ValueError("neighbor_search='grid9' cannot wrap: a tile needs 'candidate'")
    if kind == "grid9":
        return Grid9Search(grid, hc)
    if kind == "candidate":
        return CandidateSearch(grid, candidates, hc)
    raise ValueError(f"neighbor_search={kind!r}: expected 'candidate' or 'grid9'")


def nearest_listed(crystals: np.ndarray, hc2: np.float32, w: np.ndarray, counts: np.ndarray,
                   ids: np.ndarray, x: np.ndarray, y: np.ndarray, period=None,
                   starts=None, rows=None) -> tuple[np.ndarray, np.ndarray]:
    """Of walkers `w`, each with `counts[i] > 0` crystal ids listed back to back in `ids`,
    those within sqrt(hc2) of one, and the nearest (lowest index among equals). Both
    searches end here, so their distances are the same floats. `period` (a tile's size):
    offsets are taken over the wrap. `starts` and `rows` (`CellLists.listed`'s), where
    the caller has them."""
    if len(w) == 0:
        return w, np.empty(0, np.int32)
    if starts is None or rows is None:
        starts = np.cumsum(counts) - counts
        rows = np.repeat(np.arange(len(w)), counts)
    wr = w[rows]
    dx = crystals[:, 0].take(ids) - x[wr]
    dy = crystals[:, 1].take(ids) - y[wr]
    if period is not None:
        dx, dy = nearest_image(dx, period[0]), nearest_image(dy, period[1])
    d2 = dx * dx + dy * dy
    dmin = np.minimum.reduceat(d2, starts)
    tied = np.where(d2 == dmin[rows], ids, _NO_ID)
    parent = np.minimum.reduceat(tied, starts)
    hit = dmin < hc2
    return w[hit], parent[hit].astype(np.int32)


class CandidateSearch:
    """The paper's search over the simulation's candidate cells (read, never written here)."""

    def __init__(self, grid: HashGrid, candidates: CellLists, hc: float):
        self.grid, self.candidates = grid, candidates
        self._hc_squared = np.float32(hc) ** 2

    def insert(self, pts: np.ndarray, ids: np.ndarray) -> None:
        """Nothing to do: FrostSim lists new crystals in the candidate cells itself."""

    def remove(self, pts: np.ndarray, ids: np.ndarray) -> None:
        """Nothing to do: FrostSim takes melted crystals out of the candidate cells itself."""

    def nearest(self, crystals: np.ndarray, x: np.ndarray, y: np.ndarray,
                keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        keys = self.grid.keys(x, y) if keys is None else keys
        w = (self.candidates.count[keys] > 0).nonzero()[0]
        counts, starts, rows, ids = self.candidates.listed(keys[w])
        return nearest_listed(crystals, self._hc_squared, w, counts, ids, x, y, self.grid.period,
                              starts, rows)

    def nbytes(self) -> int:
        return 0  # the candidate cells are FrostSim's, counted there


class Grid9Search:
    """Fig. 9's baseline: crystals listed in their own cells, 3 x 3 cells searched."""

    def __init__(self, grid: HashGrid, hc: float):
        self.grid = grid
        self._hc_squared = np.float32(hc) ** 2
        self._own = CellLists(grid.size + 1)  # the extra cell stays empty: off-grid neighbours

    def insert(self, pts: np.ndarray, ids: np.ndarray) -> None:
        self._own.insert(self.grid.keys(pts[:, 0], pts[:, 1]), ids)

    def remove(self, pts: np.ndarray, ids: np.ndarray) -> None:
        self._own.remove(self.grid.keys(pts[:, 0], pts[:, 1]), ids)

    def nearest(self, crystals: np.ndarray, x: np.ndarray, y: np.ndarray,
                keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        keys = self.grid.keys(x, y) if keys is None else keys
        hits, parents = [np.empty(0, np.int64)], [np.empty(0, np.int32)]
        for lo in range(0, len(keys), _GRID9_CHUNK):
            counts, ids = self._own.gather_flat(self._around(keys[lo:lo + _GRID9_CHUNK]))
            per_walker = counts.reshape(-1, 9).sum(axis=1)
            some = per_walker > 0
            w = lo + np.flatnonzero(some)
            h, p = nearest_listed(crystals, self._hc_squared, w, per_walker[some], ids, x, y)
            hits.append(h)
            parents.append(p)
        return np.concatenate(hits), np.concatenate(parents)

    def nbytes(self) -> int:
        return self._own.nbytes()

    def _around(self, keys: np.ndarray) -> np.ndarray:
        """The 3 x 3 cells around each key, walker-major (the empty extra cell off the grid)."""
        cols, rows = self.grid.cols, self.grid.rows
        nx = (keys % cols)[:, None] + _AROUND_X
        ny = (keys // cols)[:, None] + _AROUND_Y
        inside = (nx >= 0) & (nx < cols) & (ny >= 0) & (ny < rows)
        return np.where(inside, ny * cols + nx, self.grid.size).ravel()
