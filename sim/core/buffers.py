"""Growable numpy arrays and the per-cell index lists of the hash grid."""

from __future__ import annotations

import numpy as np


def runs(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(first, last, rank) of the runs of equal values of a sorted array: flags for the
    first and the last element of each run, and each element's place in its run. A few
    numpy passes, none of them a Python-level helper (np.diff with `append` or
    np.unique cost more than the rest of a small tick's counting)."""
    at = np.arange(len(s))
    lo = s.searchsorted(s)  # where each element's run starts
    return lo == at, s.searchsorted(s, "right") - 1 == at, at - lo


def distinct(a: np.ndarray) -> np.ndarray:
    """The distinct values of `a`, ascending (np.unique's answer, without its overhead)."""
    s = np.sort(a)
    keep = np.empty(len(s), bool)
    keep[:1] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


class Growable:
    """An append-only array of rows with amortised O(1) appends.

    `view()` is a read-only window on the filled rows, so callers may keep it
    without copying; it stays valid until the next append reallocates.
    """

    def __init__(self, dtype: np.dtype | type, row_shape: tuple[int, ...] = (), capacity: int = 64):
        self._data = np.zeros((max(capacity, 1), *row_shape), dtype=dtype)
        self.n = 0

    def append(self, rows: np.ndarray) -> slice:
        """Append `rows`; returns the slice of indices they received."""
        k = len(rows)
        if self.n + k > len(self._data):
            self._reserve(self.n + k)
        self._data[self.n:self.n + k] = rows
        self.n += k
        return slice(self.n - k, self.n)

    def append_fill(self, k: int, value) -> slice:
        """Append k rows that each hold `value`; returns their slice."""
        if self.n + k > len(self._data):
            self._reserve(self.n + k)
        self._data[self.n:self.n + k] = value
        self.n += k
        return slice(self.n - k, self.n)

    def keep(self, mask: np.ndarray) -> None:
        """Drop the rows where `mask` is False, preserving order."""
        kept = self._data[:self.n][mask]
        self._data[:len(kept)] = kept
        self.n = len(kept)

    def view(self) -> np.ndarray:
        v = self._data[:self.n]
        v.flags.writeable = False
        return v

    def raw(self) -> np.ndarray:
        """The filled rows, writable (for the owner only)."""
        return self._data[:self.n]

    def nbytes(self) -> int:
        return self._data.nbytes

    def _reserve(self, need: int) -> None:
        if need > len(self._data):
            cap = max(need, 2 * len(self._data))
            grown = np.zeros((cap, *self._data.shape[1:]), dtype=self._data.dtype)
            grown[:self.n] = self._data[:self.n]
            self._data = grown


class CellLists:
    """For every hash-grid cell, the ascending indices of the particles listed in it.

    Dense arrays: `count[cell]` and `items[cell, :count[cell]]`; the width of
    `items` doubles when a cell overflows. Insertion keeps each cell's list in
    ascending index order, so the first of equal distances is the lowest index.
    """

    def __init__(self, n_cells: int, width: int = 8):
        self.count = np.zeros(n_cells, dtype=np.int32)
        self.items = np.full((n_cells, width), -1, dtype=np.int32)
        self.count_bound = 0  # at least the largest count (removals leave it high)

    def insert(self, cells: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """Add `ids[j]` to cell `cells[j]`; ids of one cell must come in ascending order.
        Returns the cells that listed nothing before, ascending."""
        if len(cells) == 0:
            return cells
        order = cells.argsort(kind="stable")
        c, i = cells[order], ids[order]
        _, last, rank = runs(c)
        touched = c[last]
        opened = touched[self.count[touched] == 0]
        slot = self.count[c] + rank
        top = int(slot.max()) + 1
        self._widen(top)
        self.count_bound = max(self.count_bound, top)
        self.items[c, slot] = i
        self.count[touched] = slot[last] + 1
        return opened

    def remove(self, cells: np.ndarray, ids_to_drop: np.ndarray) -> None:
        """Remove every id in `ids_to_drop` from the lists of `cells` (order kept)."""
        cells = np.unique(cells)
        ids, valid = self.gather(cells)
        keep = valid & ~np.isin(ids, ids_to_drop)
        # A stable sort on "dropped" moves the kept ids to the front in their order.
        order = np.argsort(~keep, axis=1, kind="stable")
        kept = np.take_along_axis(ids, order, axis=1)
        count = keep.sum(axis=1)
        kept[np.arange(ids.shape[1]) >= count[:, None]] = -1
        self.items[cells, :ids.shape[1]] = kept
        self.count[cells] = count

    def gather(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ids, valid): the lists of `cells` as a padded matrix and its mask."""
        width = int(self.count[cells].max(initial=0))
        ids = self.items[cells, :width]
        valid = np.arange(width) < self.count[cells][:, None]
        return ids, valid

    def gather_flat(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(counts, ids): the lists of `cells` back to back, without padding."""
        counts, _, _, ids = self.listed(cells)
        return counts, ids

    def listed(self, cells: np.ndarray) -> tuple[np.ndarray, ...]:
        """(counts, starts, rows, ids): the lists of `cells` back to back (`ids`), where
        each starts in `ids`, and the index into `cells` of each id."""
        counts = self.count[cells]
        rows = np.arange(len(cells)).repeat(counts)
        starts = counts.cumsum() - counts
        # each id's flat place in `items`: its cell's row, plus its place in the list
        at = (cells * self.items.shape[1] - starts)[rows] + np.arange(len(rows))
        return counts, starts, rows, self.items.reshape(-1).take(at)

    def nbytes(self) -> int:
        return self.count.nbytes + self.items.nbytes

    def _widen(self, need: int) -> None:
        width = self.items.shape[1]
        if need > width:
            while width < need:
                width *= 2
            wide = np.full((len(self.count), width), -1, dtype=np.int32)
            wide[:, :self.items.shape[1]] = self.items
            self.items = wide
