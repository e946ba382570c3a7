"""Both neighbour searches (sim.search) against a brute-force nearest crystal."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim.core.buffers import CellLists, runs
from sim.index.grid import HashGrid
from sim.index.search import CandidateSearch, Grid9Search, make_search

# Positions on a quarter-px lattice: equal distances (ties) and walkers exactly hc away
# from a crystal come up often, and both must be decided as the brute force decides them.
QUARTERS = st.integers(0, 4 * 90 - 1).map(lambda q: q / 4)
POINTS = st.lists(st.tuples(QUARTERS, QUARTERS), max_size=60)
HC = st.one_of(st.integers(1, 20).map(float), st.floats(1.0, 30.0))


def on_the_rim(crystal_xy, hc):
    """Walkers exactly hc beside a crystal (on the screen): they must not freeze."""
    if not crystal_xy:
        return st.just([])
    sides = st.sampled_from([(1, 0), (-1, 0), (0, 1), (0, -1)])
    spots = st.tuples(st.sampled_from(crystal_xy), sides).map(
        lambda c: (c[0][0] + hc * c[1][0], c[0][1] + hc * c[1][1]))
    return st.lists(spots.filter(lambda p: 0 <= p[0] < 90 and 0 <= p[1] < 90), max_size=8)


def brute_nearest(crystals, live, x, y, hc):
    """Every walker against every live crystal, in the simulation's float32 arithmetic."""
    hc2 = np.float32(hc) ** 2
    walkers, parents = [], []
    for i in range(len(x)):
        best, parent = None, None
        for j in live:
            dx, dy = crystals[j, 0] - x[i], crystals[j, 1] - y[i]
            d2 = dx * dx + dy * dy
            if best is None or d2 < best:  # live is ascending: the first of equals stays
                best, parent = d2, j
        if best is not None and best < hc2:
            walkers.append(i)
            parents.append(parent)
    return walkers, parents


def listed_in(kind, grid, crystals, hc, batches, melted):
    """A search of `kind` told, as FrostSim tells it, of crystals added in `batches` (of
    ascending ids) and then of the `melted` ones leaving."""
    candidates = CellLists(grid.size)
    search = make_search(kind, grid, candidates, hc)
    for ids in batches:
        cells, owner = grid.disc_cells(crystals[ids], hc)
        candidates.insert(cells, ids[owner])
        search.insert(crystals[ids], ids)
    cells, _ = grid.disc_cells(crystals[melted], hc)
    candidates.remove(cells, melted)
    search.remove(crystals[melted], melted)
    return search


@pytest.mark.parametrize("kind", ["candidate", "grid9"])
@given(crystal_xy=POINTS, walker_xy=POINTS, hc=HC, data=st.data())
def test_search_finds_the_nearest_crystal_within_hc(kind, crystal_xy, walker_xy, hc, data):
    grid = HashGrid(90, 90, hc)
    crystals = np.array(crystal_xy, np.float32).reshape(-1, 2)
    ids = np.arange(len(crystals), dtype=np.int32)
    split = data.draw(st.integers(0, len(ids)), label="split")
    gone = data.draw(st.lists(st.sampled_from(ids), unique=True) if len(ids) else st.just([]),
                     label="melted")
    melted = np.array(sorted(gone), np.int32)
    search = listed_in(kind, grid, crystals, hc, (ids[:split], ids[split:]), melted)
    walkers = np.array(walker_xy + data.draw(on_the_rim(crystal_xy, hc), label="rim"),
                       np.float32).reshape(-1, 2)
    x, y = walkers[:, 0].copy(), walkers[:, 1].copy()
    hits, parents = search.nearest(crystals, x, y)
    live = np.setdiff1d(ids, melted)
    assert (hits.tolist(), parents.tolist()) == brute_nearest(crystals, live, x, y, hc)


def test_make_search_picks_the_named_search():
    grid = HashGrid(90, 90, 5.0)
    for kind, cls in (("candidate", CandidateSearch), ("grid9", Grid9Search)):
        assert type(make_search(kind, grid, CellLists(grid.size), 5.0)) is cls
    with pytest.raises(ValueError, match="octree"):
        make_search("octree", grid, CellLists(grid.size), 5.0)


@given(st.lists(st.integers(-3, 6), max_size=40))
def test_runs_of_a_sorted_array_match_a_loop(values):
    s = np.sort(np.array(values, np.int64))
    first, last, rank = runs(s)
    n = len(s)
    assert first.tolist() == [i == 0 or s[i] != s[i - 1] for i in range(n)]
    assert last.tolist() == [i == n - 1 or s[i] != s[i + 1] for i in range(n)]
    assert rank.tolist() == [sum(1 for j in range(i) if s[j] == s[i]) for i in range(n)]


@given(st.lists(st.tuples(st.integers(0, 7), st.integers(0, 10**6)), max_size=60),
       st.integers(1, 4))
def test_cell_lists_hold_each_cells_ids_in_the_order_given(pairs, batches):
    """Inserting in batches lists each cell's ids in ascending order with the right count,
    as a dict of lists does (ids of one cell ascend across and within the batches)."""
    pairs = sorted(pairs, key=lambda p: p[1])
    lists, slow = CellLists(8, width=2), {c: [] for c in range(8)}
    for part in np.array_split(np.arange(len(pairs)), batches):
        cells = np.array([pairs[i][0] for i in part], np.int64)
        ids = np.array([pairs[i][1] for i in part], np.int32)
        lists.insert(cells, ids)
        for c, i in zip(cells, ids, strict=True):
            slow[int(c)].append(int(i))
    assert lists.count.tolist() == [len(slow[c]) for c in range(8)]
    counts, flat = lists.gather_flat(np.arange(8))
    assert flat.tolist() == [i for c in range(8) for i in slow[c]]
