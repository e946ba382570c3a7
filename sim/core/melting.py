"""A warm finger (docs/method.md): the crystals within discs melt, their links leave the
skeleton, and their children become roots. Costs O(the ice the discs cover)."""

from __future__ import annotations

import numpy as np

from ..index.freezing import FreezingIndex
from .skeleton import Melted, Skeleton


def checked_discs(discs) -> list[tuple[float, float, float]]:
    """`discs` ((x, y, radius) each) as floats; ValueError for a value not finite or a
    radius not above 0."""
    for x, y, radius in discs:
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(radius) and radius > 0):
            raise ValueError(f"melt at ({x!r}, {y!r}) with radius {radius!r}: need finite "
                             "values, radius > 0")
    return [(float(x), float(y), float(r)) for x, y, r in discs]


def melt_discs(discs, ice: Skeleton, index: FreezingIndex, growth, pane) -> Melted:
    """Melt the crystals within any of `discs` in one pass: they die in `ice` and leave
    `index`, `pane` and the growth rule's counters (`growth`); their links and those of
    their children (which become roots) are cut. The water they held is the caller's."""
    discs = checked_discs(discs)
    dead = _union([index.crystals_near(x, y, r) for x, y, r in discs])
    _kill(dead, ice, index, pane)
    # A child lies within one link of its parent: look no further than that.
    reach = ice.longest_link + 1.0
    near = _union([index.crystals_near(x, y, r + reach) for x, y, r in discs])
    parents = ice.parents.raw()
    orphans = near[np.isin(parents[near], dead)]
    growth.melted(dead, parents, orphans, near if len(dead) else dead)
    parents[orphans] = -1
    segments, upsampled = ice.cut(np.concatenate([dead, orphans]))
    return Melted(dead, upsampled, segments, orphans)


def melt_tips(ice: Skeleton, index: FreezingIndex, growth, pane) -> Melted:
    """The weather's thaw (sim/weather): the crystals no live crystal grows from (the
    ice's thin edges) melt as in `melt_discs`. None of them has a child to orphan, and
    their parents, the new tips, keep their slots as they were (no clearing is made for
    the frost to regrow across, as a finger's is)."""
    dead = ice.tips()
    _kill(dead, ice, index, pane)
    none = dead[:0]
    growth.melted(dead, ice.parents.raw(), none, none)
    segments, upsampled = ice.cut(dead)
    return Melted(dead, upsampled, segments, none)


def _kill(dead: np.ndarray, ice: Skeleton, index: FreezingIndex, pane) -> None:
    """The crystals `dead` die in `ice` and leave `index` and `pane`."""
    ice.crystal_alive.raw()[dead] = False
    pane.melted(dead)
    index.remove(dead)


def _union(ids: list[np.ndarray]) -> np.ndarray:
    """Ascending indices in any of `ids` (each ascending): one disc's own, as it is."""
    return ids[0] if len(ids) == 1 else np.unique(np.concatenate(ids))
