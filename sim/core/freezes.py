"""Which walkers freeze in a tick: Sec. 3.4.3 within the tick's budgets, in three phases
(FrostSim.step calls them in order). Water in a cell
that already lists CELL_CAP crystals is dropped (it arrived at finished ice); the walkers
within hc of a crystal find their nearest; the tick admits those freezes within its
work and the cells' cap (`budget.admit`), the rest waiting as water or dropped."""

from __future__ import annotations

import numpy as np

from ..index.freezing import FreezingIndex
from . import budget
from .water import Water


def drop_in_full_cells(water: Water, index: FreezingIndex) -> tuple[np.ndarray, int]:
    """Drop the walkers in cells that list CELL_CAP crystals: (the cells of the walkers
    kept, how many dropped)."""
    keys = index.grid.keys(water.x.raw(), water.y.raw())
    if index.candidates.count_bound < budget.CELL_CAP:  # (no cell can be full)
        return keys, 0
    full = index.candidates.count[keys] >= budget.CELL_CAP
    if not full.any():
        return keys, 0
    water.keep(~full)
    return keys[~full], int(full.sum())


def nearest_crystals(water: Water, index: FreezingIndex,
                     keys: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Sec. 3.4.3: the walkers within hc of a crystal, and their nearest crystal (`keys`:
    the walkers' cells, where known)."""
    if water.n == 0:
        return np.empty(0, np.int64), np.empty(0, np.int32)
    return index.nearest(water.x.raw(), water.y.raw(), keys)


def admitted(water: Water, index: FreezingIndex, hits: np.ndarray, parents: np.ndarray,
             hc: float, work_per_crystal: int) -> tuple[np.ndarray, np.ndarray, int]:
    """The freezes (walkers `hits` onto crystals `parents`) this tick takes
    (`budget.admit`): (walkers, crystals, walkers dropped). The water of those over the
    cells' cap leaves `water`, and the kept walkers' indices move down to match."""
    candidates = index.candidates
    frozen, parents, over = budget.admit(hits, parents, candidates.count, index.grid, water.at,
                                         hc, work_per_crystal, candidates.count_bound)
    if len(over):
        frozen = water.drop_before(over, frozen)
    return frozen, parents, len(over)
