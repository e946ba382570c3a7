"""The budgets a tick keeps: the water budget (fill, trim, level) and the freezing work
(FREEZE_WORK, CELL_CAP). Pure functions of counts; the orchestrator applies them."""

from __future__ import annotations

import math

import numpy as np

# Most crystals one hash cell may list. The paper's rule lets ice pile up without end
# where water keeps arriving (replenish, growth mode, touch after touch on one spot), and
# a walker's search costs the length of its cell's list; a full cell is finished ice, and
# water that would freeze into it is dropped instead. Table 1's single touches never
# list more than 58 (measured over seeds 0-2), so the paper's frost is unchanged.
CELL_CAP = 128
# Geometry work one tick's freezes may make, in grid-vertex raises (each new crystal brings
# its link's upsample particles, and each particle raises a stencil of grid vertices).
# Freezes beyond it wait a tick as water (in walker order). Table 1's single touches peak at
# 166 050 (a-1, seeds 0-2) and two a-1 touches at about 332 000, so the paper's frost is
# unchanged, and a fast chain reaction at a large hc cannot make one tick do seconds of work.
FREEZE_WORK = 400_000


def work_per_crystal(hc: float, grid_spacing: float, spacing: float) -> int:
    """Grid vertices one new crystal may raise: its link's particles (links reach hc,
    upsampled every `spacing` px) times the geometry stencil (vertices `grid_spacing` apart)."""
    reach = math.ceil(hc / grid_spacing) + 1
    per_link = 1 + max(0, math.floor(hc / spacing) - 1)
    return per_link * (2 * reach + 1) ** 2


def admit(frozen: np.ndarray, parents: np.ndarray, count: np.ndarray, grid, position_of,
          hc: float, work: int, count_bound: int | None = None,
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The freezes (walkers `frozen`, crystals `parents`) a tick takes: within FREEZE_WORK
    at `work` a crystal (the rest wait a tick), then those whose cells (`count` crystals
    listed; `position_of(frozen)`: the walkers' positions) all stay within CELL_CAP. In walker
    order, so both neighbour searches admit the same. Returns (frozen, parents, over):
    `over` the walkers whose freeze would overflow a cell. `count_bound`: at least the
    largest count, where known (`CellLists.count_bound`), which spares a pass over the counts."""
    take = max(1, FREEZE_WORK // work)
    frozen, parents = frozen[:take], parents[:take]
    no_one = frozen[:0]
    if (count_bound is not None and count_bound + len(frozen) <= CELL_CAP) or \
            count.max(initial=0) + len(frozen) <= CELL_CAP:
        return frozen, parents, no_one  # no cell can fill up this tick (cheap: one pass, no cells)
    cells, owner = grid.disc_cells(position_of(frozen), hc)
    if len(cells) == 0 or count[cells].max() + len(frozen) <= CELL_CAP:
        return frozen, parents, no_one
    ok = within_cap(count, cells, owner, len(frozen))
    return frozen[ok], parents[ok], frozen[~ok]


def room_for(candidates, grid, pts: np.ndarray, hc: float) -> np.ndarray:
    """Which new crystals at `pts` (in order) keep every cell their freezing disc lists
    them in (`grid`'s cells, `candidates`' lists) within CELL_CAP: a seed a touch plants,
    or a fern crystal, which grows one hc from its parent, away from the walker the cap
    was checked at."""
    if candidates.count_bound + len(pts) <= CELL_CAP:  # (no cell can fill up)
        return np.ones(len(pts), bool)
    cells, owner = grid.disc_cells(pts, hc)
    return within_cap(candidates.count, cells, owner, len(pts))


def within_cap(count: np.ndarray, cells: np.ndarray, owner: np.ndarray, n: int) -> np.ndarray:
    """Per freeze (n, in walker order): whether every cell its disc lists it in (`cells`,
    `owner`) stays within CELL_CAP after the earlier freezes."""
    order = np.argsort(cells, kind="stable")
    c = cells[order]
    first = np.concatenate(([0], np.flatnonzero(c[1:] != c[:-1]) + 1))
    rank = np.empty(len(c), np.int64)
    rank[order] = np.arange(len(c)) - np.repeat(first, np.diff(first, append=len(c)))
    over = count[cells] + rank >= CELL_CAP
    return np.bincount(owner[over], minlength=n) == 0


def wanted(counts: np.ndarray, areas: np.ndarray, pool: int, budget: int,
           room: int) -> tuple[np.ndarray, int | None]:
    """Walkers each of `areas` wants to reach `pool`, and (when they exceed the `room`
    left in the budget) the fair share each holding area may keep (else None)."""
    want = np.maximum(0, pool - counts[areas])
    if want.sum() <= room:
        return want, None
    holding = counts > 0
    holding[areas] = True
    share = budget // int(holding.sum())
    return np.minimum(want, np.maximum(0, share - counts[areas])), share


def given(want: np.ndarray, room: int) -> np.ndarray:
    """What each want gets, in order, until `room` runs out."""
    return np.minimum(want, np.maximum(0, room - (np.cumsum(want) - want)))


def trim(counts: np.ndarray, areas: np.ndarray, need: int, share: int,
         owner: np.ndarray) -> np.ndarray | None:
    """Which walkers (of areas `owner`) to keep so that up to `need` of the areas other
    than `areas` go, the largest pools cut to a common level no lower than `share`; each
    area keeps its oldest (first in array order). None: nothing to cut."""
    if need <= 0:
        return None
    others = counts.copy()
    others[areas] = 0  # (an area being topped up holds less than `share`: never cut)
    limit = np.minimum(counts, level(others, need, share))
    order = np.argsort(owner, kind="stable")
    rank = np.empty(len(owner), np.int64)
    rank[order] = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
    return rank < limit[owner]


def level(counts: np.ndarray, need: int, floor: int) -> int:
    """The highest level >= floor such that cutting every count down to it frees at least
    `need` (or `floor` itself if even that frees less): a water-filling cut."""
    lo, hi = floor, int(counts.max(initial=0))
    if np.maximum(counts - lo, 0).sum() < need:
        return lo
    while lo < hi:  # invariant: cutting to lo frees enough
        mid = (lo + hi + 1) // 2
        if np.maximum(counts - mid, 0).sum() >= need:
            lo = mid
        else:
            hi = mid - 1
    return lo
