"""The rules of each session version, in one place. A session file names the version of
the rules it was grown by, and replays by them bit for bit; a run without a file takes
the newest. What each version changed:

1. The first rules: a rebuild replants every touch at tick 0.
2. A rebuild replants the touches at their own pace, each pause kept up to REGROW_GAP
   ticks (sim/io/timeline.py).
3. Where an area's disc draws fail, walkers are placed from all areas' cells in one pass
   (sim/core/placement.py, CELL_WORK).
4. Window water draws its later tries in one batch (sim/rules/openglass.py).
5. A touch into an area whose pool is short brings new walkers (sim/core/supply.py), and
   a ringed seed's hits count together until its first child (sim/rules/fern.py).
6. A tick's melts given together (a warm finger's drag) apply as one melt, each recorded
   with its "group" (sim/io/timeline.py).
7. Each part draws from a random stream of its own (`random_streams`), so a change in
   one part's draws leaves the others' unchanged. Up to version 6 they share one.
8. A touch that opens an area brings its ring of water too (sim/core/frost.py `plant`).
9. A touch obeys the cells' cap as a freeze does (sim/core/budget.py CELL_CAP): a touch
   whose seed would list a cell past it plants nothing (no seed, no water). Before, a page
   tapping one spot piled thousands of seeds into one cell, and every walker near it
   searched them all.
10. The lock screen's clock: "clock" events name the minute (local time, as
   "YYYY-MM-DDTHH:MM") the lock screen showed from their tick on, so a replay or a render
   of the session shows the minutes it showed. The frost itself grows as in version 9.
11. The backdrop: "backdrop" events name the backdrop shown from their tick on (a
   built-in's name, or a photo's, `photo-` and 32 hex digits: app/photos.py), so a replay
   or a render shows what the session showed, a photo brought from a phone included. A
   session starts on the default backdrop (dusk) unless one at tick 0 says otherwise. The
   frost itself grows as in version 9.
12. The weather: "weather" events hold a reading of the weather outside and the glass it
   acts on (sim/weather); from their tick on the frost grows as that glass makes it (the
   window's temperature and supply), or thaws (nothing grows, the ice melts back from its
   thin edges). Without weather events the frost grows as in version 9.
13. A file may say where it was grown: "source": "phone" is a phone's own session, grown by
   the page's simulation in JavaScript (app/web/local/) with its own random numbers. It
   replays here by this version's rules, with the same touches, parameters and backdrops,
   but not bit for bit; a file without "source" was grown by this simulation. The frost
   itself grows as in version 12.
14. Water is never lost to the tick's budget (sim/core/supply.py, docs/method.md 4.4):
   walkers whose placement the tick's cell work (CELL_WORK) cut are owed to their area
   and placed first in the next tick; a kept pool (replenish, growth mode) is topped up
   to `humidity` every tick wherever its area has ice and the water budget has room; and
   an area whose launch circle lies wholly beyond the screen places its water on the
   free glass of its disc, as a full annulus does. Before, a storm of touches could make
   one area whose launch circle left the screen: every draw missed, hundreds of walkers a
   tick were dropped, and the pool, topped up only by touches, drained for good.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NEWEST = 14
# The first version whose files may say where they were grown ("source", above).
PHONE_VERSION = 13
# Longest pause a rebuild keeps between two touches it replants: 12 ticks, about 0.5 s.
REGROW_GAP = 12
# The parts that draw random numbers, in the order their streams are spawned.
PARTS = ("walk", "placement", "supply", "growth", "pane")


@dataclass(frozen=True)
class Rules:
    """What the frost of one version does, rule by rule (see the module doc)."""

    version: int
    regrow_gap: int  # 2: the longest pause kept between replanted touches (0: all at once)
    batched_placement: bool  # 3
    tries_at_once: bool  # 4
    touch_creates: bool  # 5: a touch into a short pool brings new walkers
    pooled_first_hits: bool  # 5
    grouped_melts: bool  # 6
    own_streams: bool  # 7
    opening_rings: bool  # 8: a touch that opens an area brings its ring of water too
    capped_touches: bool  # 9: a touch into a full cell plants nothing
    clock_events: bool  # 10: "clock" events (the lock screen's minutes) may be recorded
    backdrop_events: bool  # 11: "backdrop" events (the backdrop shown) may be recorded
    weather_events: bool  # 12: "weather" events (the weather outside) may be recorded
    kept_water: bool  # 14: water owed, not dropped, when the tick's cell work runs out; kept pools topped up


def rules_of(version: int) -> Rules:
    """The rules of session `version` (1 .. NEWEST)."""
    if isinstance(version, bool) or not isinstance(version, (int, np.integer)) \
            or not 1 <= version <= NEWEST:
        raise ValueError(f"version={version!r} must be a whole number in [1, {NEWEST}]")
    v = int(version)
    return Rules(v, REGROW_GAP if v >= 2 else 0, v >= 3, v >= 4, v >= 5, v >= 5, v >= 6, v >= 7,
                 v >= 8, v >= 9, v >= 10, v >= 11, v >= 12, v >= 14)


@dataclass(frozen=True)
class Streams:
    """The random generator each part draws from (one object for all up to version 6)."""

    walk: np.random.Generator
    placement: np.random.Generator
    supply: np.random.Generator
    growth: np.random.Generator
    pane: np.random.Generator


def random_streams(seed: int, rules: Rules) -> Streams:
    """Each part's generator for `seed`: its own child of the seed's SeedSequence (in
    PARTS' order, so adding a part at the end leaves the others' streams as they were),
    or before version 7 the one generator all parts shared."""
    if not rules.own_streams:
        shared = np.random.default_rng(seed)
        return Streams(*(shared,) * len(PARTS))
    children = np.random.SeedSequence(seed).spawn(len(PARTS))
    return Streams(*(np.random.default_rng(child) for child in children))
