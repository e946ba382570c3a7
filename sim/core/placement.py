"""Where walkers are placed in their areas: disc draws, then free cells (Sec. 3.4.2).

`Placer.place` gives each walker a uniform spot of its area's annulus, on the screen and
outside candidate cells; the pure functions below draw the spots.
"""

from __future__ import annotations

import numpy as np

from ..index.periodic import wrap_into
from .areas import shell

TWO_PI = np.float32(2.0 * np.pi)
# A water particle that found no spot in its area's free cells after this many draws is
# dropped: an area filled with ice has no free spot left (its frost is complete).
CELL_TRIES = 8
# Walkers one tick may place from cells (`Placer.cell_spots_all`, where an area's disc
# draws failed); the rest find no spot and are dropped, as in an area with no glass left.
# In an area all ice (a fern look's pane after a storm of touches) nearly every walker hits
# ice and is placed again each tick: ~3 700 cell placements a tick took the tick past 50 ms
# (1 000 still ~30). One touch's growth needs at most 173 a tick (fern, seed 0), Table 1's
# at most 13.
CELL_WORK = 400
# Draws of an area's cells, all on ice, that show its disc has no glass left (version 14:
# its kept pool waits for a melt, not topped up every tick in vain).
BARE_DRAWS = 64
# Draws per walker among glass cells (`glass_spots`) before it is dropped.
GLASS_TRIES = 8
_NONE = np.empty(0, np.int64)


def first_good(good: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For tries x k flags: which of the k have a good try, and the flat index (into the
    tries x k draws) of the first good try of each of those."""
    if good[0].all():  # (often: every first try is good)
        return good[0], np.arange(good.shape[1])
    placed = np.logical_or.reduce(good, axis=0)
    which = placed.nonzero()[0]
    return placed, good.argmax(axis=0)[which] * good.shape[1] + which


def first_good_by_rounds(check, tries: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """`first_good` of tries x k draws whose flags `check(flat)` gives for the flat indices
    asked: every first try, then later tries only of those still without a good one, in
    runs of tries that double (1, 1, 2, 4, ...). The same answer as checking every draw,
    with a fraction of the checks where most first tries are good."""
    placed, pick = np.zeros(k, bool), np.zeros(k, np.int64)
    todo, start, size = np.arange(k), 0, 1
    while start < tries and len(todo):
        rounds = np.arange(start, min(tries, start + size))
        good = check((rounds[:, None] * k + todo[None, :]).ravel()).reshape(len(rounds), -1)
        hit = good.any(axis=0)
        mine = todo[hit]
        placed[mine] = True
        pick[mine] = rounds[good.argmax(axis=0)[hit]] * k + mine
        todo = todo[~hit]
        start, size = start + size, size * 2 if start else 1
    return placed, pick[placed]


def disc_spots(rng: np.random.Generator, a: np.ndarray, launch: float,
               wrap: tuple[int, int] | None, m: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A uniform point of the annulus of each area row of `a` (which may reach off the
    screen; on a tile, `wrap` = (width, height), wrapped onto it); or, given `m` and one
    row, m points of that row's annulus."""
    return annulus_points(rng.random((2, len(a) if m is None else m), dtype=np.float32), a,
                          launch, wrap)


def annulus_points(u: np.ndarray, a: np.ndarray, launch: float,
                   wrap: tuple[int, int] | None) -> tuple[np.ndarray, np.ndarray]:
    """`disc_spots` at its uniform draws `u` (2 x points)."""
    inner, outer = shell(a, launch)
    r = np.sqrt(inner ** 2 + u[0] * (outer ** 2 - inner ** 2))
    th = u[1] * TWO_PI
    x, y = a[:, 0] + r * np.cos(th), a[:, 1] + r * np.sin(th)
    if wrap:
        return wrap_into(x, wrap[0]), wrap_into(y, wrap[1])
    return x, y


def cell_points(u: np.ndarray, cells: np.ndarray, cols: int, size: float):
    """Points of `cells` (flat indices, `cols` a row, cells `size` px) at the uniform
    draws u[1], u[2] within each: (x, y)."""
    s = np.float32(size)
    return (cells % cols + u[1]) * s, (cells // cols + u[2]) * s


def ring_spots(rng: np.random.Generator, centre: tuple[float, float], hc: float,
               n: int) -> tuple[np.ndarray, np.ndarray]:
    """n uniform points of the ring from hc to 2 hc around `centre` (float32)."""
    u = rng.random((2, n))
    r = hc * np.sqrt(1.0 + 3.0 * u[0])  # uniform in the ring's area: hc .. 2 hc
    return ((centre[0] + r * np.cos(TWO_PI * u[1])).astype(np.float32),
            (centre[1] + r * np.sin(TWO_PI * u[1])).astype(np.float32))


class Placer:
    """Places walkers of given areas (see module doc); window mode hands it to the pane."""

    def __init__(self, rng: np.random.Generator, index, areas, pane, params, batched: bool,
                 owing: bool = False):
        self.rng, self.index, self.areas, self.pane = rng, index, areas, pane
        self.launch, self.grow = float(params.launch), params.grow
        self.batched = batched
        # Version 14: the walkers the cell work cut (not tried this tick) are kept, by
        # area, for `take_cut`: they are owed to their areas, not dropped; and a launch
        # circle wholly beyond the screen sends its area's water to its disc's glass.
        self.owing = owing
        self._cut: list[np.ndarray] = []
        self.first_cut = _NONE  # `place_both`: the areas of its first walkers the cut took
        # Version 14: areas whose disc was last seen with no glass left (BARE_DRAWS draws
        # of its cells all on ice), and the melt count then: a kept pool is not topped up
        # there until a melt makes glass (`bare`).
        self._bare: dict[int, int] = {}
        self.wrap = (index.width, index.height) if index.grid.period is not None else None
        self.cell_work = CELL_WORK  # cell placements left in this tick
        self._plans: dict[int, tuple[np.ndarray, float, bool, bool]] = {}
        self._plans_key: tuple[int, int] | None = None
        self._full: dict[int, bool] = {}  # areas whose annulus was last seen with no free cell

    def place(self, area: np.ndarray, ice: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, ok): uniform spots in each walker's area (its annulus), on screen and
        outside candidate cells; `ok` is False where there is no free spot. Sampling the
        disc places almost every walker in a round or two while an area is mostly glass;
        the few left (an area nearly full of ice) are placed from its free cells directly,
        so a full area costs one look at its cells, never a long rejection loop. `ice`
        says when the ice last changed (the cell lists follow it)."""
        return self._place(area, ice)

    def _place(self, area: np.ndarray, ice: tuple[int, int],
               drawn: tuple[np.ndarray, ...] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`place`; `drawn`: its first round already drawn and checked (`place_both`)."""
        if self.pane.on:
            return self.pane.place(len(area))
        n = len(area)
        x, y, ok = np.zeros(n, np.float32), np.zeros(n, np.float32), np.zeros(n, bool)
        # An area whose annulus has no free cell cannot place by disc draws: to its cells.
        direct = self.annulus_full(area) if self.batched else None
        todo = np.arange(n) if direct is None else np.flatnonzero(~direct)
        # A launch circle may cross other areas' ice: give it more tries before the cells.
        for tries in self.rounds(n):
            if len(todo) == 0:
                break
            if drawn is not None:
                (px, py, placed, pick), drawn = drawn, None
            else:
                px, py = disc_spots(self.rng, self._rows(area, todo, tries), self.launch,
                                    self.wrap, tries * len(todo))
                placed, pick = first_good(self.index.free(px, py).reshape(tries, len(todo)))
            if len(todo) == n and direct is None and placed.all():  # (the usual case)
                return px[pick], py[pick], placed
            there = todo[placed]
            x[there], y[there], ok[there] = px[pick], py[pick], True
            todo = todo[~placed]
        if len(todo) and not self.batched:  # session files before version 3
            for a in np.unique(area[todo]):
                mine = todo[area[todo] == a]
                x[mine], y[mine], ok[mine] = self.cell_spots(int(a), len(mine))
        elif self.batched and (len(todo) or (direct is not None and direct.any())):
            if direct is not None:
                todo = np.union1d(todo, np.flatnonzero(direct))
            if self.owing and len(todo) > self.cell_work:
                self._cut.append(area[todo[max(0, self.cell_work):]])
            todo = todo[:max(0, self.cell_work)]
            self.cell_work -= len(todo)
            x[todo], y[todo], ok[todo] = self.cell_spots_all(area[todo], ice)
        return x, y, ok

    def take_cut(self) -> np.ndarray:
        """The areas of the walkers the cell work cut, or whose draws of their area's
        cells missed while it may hold glass, since the last call (one entry each: they
        are owed; version 14, else none)."""
        if not self._cut:
            return _NONE
        cut, self._cut = np.concatenate(self._cut), []
        return cut

    def rounds(self, n: int) -> tuple[int, ...]:
        """The tries of each round of disc draws for n walkers."""
        return ((1, 2) if n > 1024 else (4,)) + ((16,) if self.launch else ())

    def _rows(self, area: np.ndarray, todo: np.ndarray, tries: int) -> np.ndarray:
        """The area rows of `tries` draws for each walker `todo` (todo ascends); one area
        (a lone touch's) is its one row, which broadcasts."""
        if self.areas.n == 1:
            return self.areas.rows.raw()
        mine = area if len(todo) == len(area) else area[todo]
        return self.areas.rows.raw()[np.concatenate((mine,) * tries)]

    def place_both(self, first: np.ndarray, second: np.ndarray, ice: tuple[int, int]):
        """(`place(first)`, `place(second)`): the answers of those two calls in turn, the
        same draws in the same order. While the first needs one round of draws (nearly
        always), both rounds are drawn at once and their spots placed and checked in one
        pass; else the draws are taken back and the calls made in turn."""
        n1, n2 = len(first), len(second)
        self.first_cut = _NONE
        if (self.pane.on or not self.batched or n1 == 0 or n2 == 0 or max(n1, n2) > 1024
                or self.annulus_full(first) is not None or self.annulus_full(second) is not None):
            return self._in_turn(first, second, ice)
        t1, t2 = self.rounds(n1)[0], self.rounds(n2)[0]
        m1 = t1 * n1
        before = self.rng.bit_generator.state
        u = np.concatenate((self.rng.random((2, m1), dtype=np.float32),
                            self.rng.random((2, t2 * n2), dtype=np.float32)), axis=1)
        if self.areas.n == 1:
            rows = self.areas.rows.raw()
        else:
            rows = self.areas.rows.raw()[np.concatenate((first,) * t1 + (second,) * t2)]
        px, py = annulus_points(u, rows, self.launch, self.wrap)
        good = self.index.free(px, py)
        placed, pick = first_good(good[:m1].reshape(t1, n1))
        if not placed.all():  # the first goes on to another round: draw as in turn
            self.rng.bit_generator.state = before
            return self._in_turn(first, second, ice)
        rest = first_good(good[m1:].reshape(t2, n2))
        return (px[pick], py[pick], placed), self._place(second, ice, (px[m1:], py[m1:], *rest))

    def _in_turn(self, first: np.ndarray, second: np.ndarray, ice: tuple[int, int]):
        """`place(first)`, then `place(second)`; the first's cut walkers in `first_cut`."""
        one = self._place(first, ice)
        self.first_cut = self.take_cut()
        return one, self._place(second, ice)

    def cell_spots(self, area: int, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """k uniform spots of `area`'s annulus outside candidate cells: a free cell that
        meets the annulus at random (cells are equal), a uniform point in it, kept if it
        lies in the annulus and on the screen; CELL_TRIES such draws each at most."""
        index = self.index
        cx, cy, r_out, r_in = (float(v) for v in self.areas.rows.raw()[area, :4])
        cells = index.annulus_cells(cx, cy, r_out, r_in)
        if len(cells) == 0 and self.grow:
            # Growth mode: a front ring all ice may enclose a melt's clearing, and an area
            # all ice may still hold glass between fronds; the water goes there, so a
            # wiped path refreezes.
            r_in, cells = 0.0, index.annulus_cells(cx, cy, r_out, 0.0)
            if len(cells) == 0:
                return glass_spots(self.rng, index, index.annulus_cells(cx, cy, r_out, 0.0,
                                                                        free=False), k)
        if len(cells) == 0:
            return np.zeros(k, np.float32), np.zeros(k, np.float32), np.zeros(k, bool)
        u = self.rng.random((3, CELL_TRIES * k), dtype=np.float32)
        cell = cells[np.minimum((u[0] * len(cells)).astype(np.int64), len(cells) - 1)]
        px, py = cell_points(u, cell, index.grid.cols, index.grid.cell)
        d2 = (px - cx) ** 2 + (py - cy) ** 2
        good = (d2 <= r_out * r_out) & (d2 >= r_in * r_in) & (px < index.width) & (py < index.height)
        placed, pick = first_good(good.reshape(CELL_TRIES, k))
        x, y = np.zeros(k, np.float32), np.zeros(k, np.float32)
        x[placed], y[placed] = px[pick], py[pick]
        return x, y, placed

    def cell_spots_all(self, area: np.ndarray, ice: tuple[int, int]):
        """`cell_spots` for walkers of any areas at once: each walker draws from its own
        area's cells (`area_cells`), CELL_TRIES rounds in all. The work is a few numpy
        passes over the walkers whatever the number of areas: one call per area cost
        ~1.5 ms, and a storm of touches made tens of areas (docs/method.md, 4.3)."""
        ua, inv = np.unique(area, return_inverse=True)
        plans = [self.area_cells(int(a), ice) for a in ua]
        cells = np.concatenate([p[0] for p in plans]) if plans else _NONE
        lens = np.array([len(p[0]) for p in plans], np.int64)
        off = np.cumsum(lens) - lens
        r_in = np.array([p[1] for p in plans], np.float32)
        glass = np.array([p[2] for p in plans], bool)
        cx, cy, r_out = (np.ascontiguousarray(self.areas.rows.raw()[ua, i]) for i in range(3))
        k = len(area)
        x, y, ok = np.zeros(k, np.float32), np.zeros(k, np.float32), np.zeros(k, bool)
        todo = np.flatnonzero(lens[inv] > 0)
        if len(todo) == 0:
            return x, y, ok
        # CELL_TRIES draws each, drawn at once as `cell_spots` draws them (one area's
        # walkers land where they did, area by area); a glass check on the first draws,
        # then on the later ones of the walkers still without a spot.
        g = np.tile(inv[todo], CELL_TRIES)
        u = self.rng.random((3, len(g)), dtype=np.float32)
        cell = cells[off[g] + np.minimum((u[0] * lens[g]).astype(np.int64), lens[g] - 1)]
        px, py = cell_points(u, cell, self.index.grid.cols, self.index.grid.cell)
        d2 = (px - cx[g]) ** 2 + (py - cy[g]) ** 2
        good = (d2 <= r_out[g] ** 2) & (glass[g] | (d2 >= r_in[g] ** 2))
        good &= (px < self.index.width) & (py < self.index.height)
        check = good & glass[g]  # glass between fronds: clear of every crystal
        first = np.arange(len(g)) < len(todo)
        self._on_glass(px, py, good, check & first)
        self._on_glass(px, py, good, check & ~first & ~np.tile(good[:len(todo)], CELL_TRIES))
        placed, pick = first_good(good.reshape(CELL_TRIES, len(todo)))
        x[todo[placed]], y[todo[placed]], ok[todo[placed]] = px[pick], py[pick], True
        if self.owing and not placed.all():
            self._missed(ua, glass, inv[todo], placed, ice)
        return x, y, ok

    def _missed(self, ua: np.ndarray, glass: np.ndarray, owner: np.ndarray,
                placed: np.ndarray, ice: tuple[int, int]) -> None:
        """Version 14: the walkers (`owner`: each one's row of `ua`) whose CELL_TRIES draws
        of their area's cells all missed are owed (`take_cut`), as the cut are, while
        their area may still hold glass; an area with no free cell (`glass`) whose
        walkers drew BARE_DRAWS or more spots and placed none has none left (`bare`)."""
        tried = np.bincount(owner, minlength=len(ua)) * CELL_TRIES
        hit = np.bincount(owner[placed], minlength=len(ua))
        bare = glass & (tried >= BARE_DRAWS) & (hit == 0)
        for a in ua[bare]:
            self._bare[int(a)] = ice[1]
        missed = owner[~placed]
        self._cut.append(ua[missed[~bare[missed]]])

    def bare(self, n: int, ice: tuple[int, int]) -> np.ndarray:
        """Per area (n): its disc was last seen with no glass, and nothing melted since."""
        out = np.zeros(n, bool)
        for a, melted in self._bare.items():
            out[a] = melted == ice[1]
        return out

    def _on_glass(self, px: np.ndarray, py: np.ndarray, good: np.ndarray, check: np.ndarray) -> None:
        """`good` stays True where `check` only if the point is at least hc / 2 from every
        live crystal."""
        d2 = self.index.nearest_d2(np.column_stack((px[check], py[check])))
        good[check] = d2 >= np.float32(self.index.hc / 2) ** 2

    def area_cells(self, area: int, ice: tuple[int, int]) -> tuple[np.ndarray, float, bool, bool]:
        """(cells, inner radius, glass, full) an area's water is drawn from when its disc
        draws failed: its annulus's free cells; in growth mode, else its whole disc's free
        cells, else any cell of its disc, where a spot must be glass (`glass` True).
        `full`: its annulus has no free cell. Kept until the ice changes (`ice`: a tick's
        growth, a touch, a melt)."""
        if ice != self._plans_key:
            self._plans, self._plans_key = {}, ice
        if area not in self._plans:
            cx, cy, r_out, r_in = (float(v) for v in self.areas.rows.raw()[area, :4])
            flat, near2, far2 = self.index.box_cells(cx, cy, r_out)
            disc = near2 <= r_out ** 2
            free = disc & (self.index.candidates.count[flat] == 0)
            cells, glass = flat[free & (far2 >= r_in ** 2)], False
            full = len(cells) == 0 or self.beyond_screen(cx, cy, float(self.areas.rows.raw()[area, 4]))
            if full and self.grow:
                r_in, cells = 0.0, flat[free]
                if len(cells) == 0:
                    cells, glass = flat[disc], True
            self._plans[area] = (cells, r_in, glass, full)
            self._full[area] = full
        return self._plans[area]

    def beyond_screen(self, cx: float, cy: float, reach: float) -> bool:
        """Version 14, growth mode: the launch circle of an area at (cx, cy) whose ice
        reaches `reach` lies wholly beyond the screen (past its farthest corner), so no
        draw on it can land on the screen (on a tile every circle meets it)."""
        if not (self.owing and self.grow and self.launch) or self.wrap:
            return False
        w, h = self.index.width, self.index.height
        far = max(cx, w - cx) ** 2 + max(cy, h - cy) ** 2
        return (reach + self.launch) ** 2 > far

    def annulus_full(self, area: np.ndarray) -> np.ndarray | None:
        """Per walker: its area's annulus held no free cell when its cells were last
        listed (`area_cells`; at most a tick old); None where no area's was. Listing every
        area's cells for every placement cost ~0.1 ms an area, though few areas ever
        fill; a stale answer only sends a walker the other way to a valid spot."""
        if not any(self._full.values()):  # (the usual case: no area has filled)
            return None
        ua, inv = np.unique(area, return_inverse=True)
        return np.array([self._full.get(int(a), False) for a in ua], bool)[inv]


def glass_spots(rng: np.random.Generator, index, cells: np.ndarray, n: int,
                tries: int = GLASS_TRIES):
    """(x, y, ok): n uniform spots of glass (on screen, at least hc / 2 from every live
    crystal) in uniformly drawn `cells`; `ok` False where `tries` draws found none. hc / 2
    is the fern rule's least crystal spacing: water placed only beyond hc (outside
    candidate cells) left a frosted pane with about 20 % of its cells holding no crystal,
    every point of them within hc of a neighbour's, and a wiped path half refrozen."""
    x, y, ok = np.zeros(n, np.float32), np.zeros(n, np.float32), np.zeros(n, bool)
    todo = np.arange(n)
    for _ in range(tries if len(cells) else 0):
        if len(todo) == 0:
            break
        u = rng.random((3, len(todo)), dtype=np.float32)
        cell = cells[np.minimum((u[0] * len(cells)).astype(np.int64), len(cells) - 1)]
        px, py = cell_points(u, cell, index.grid.cols, index.grid.cell)
        good = index.glass(px, py)
        x[todo[good]], y[todo[good]], ok[todo[good]] = px[good], py[good], True
        todo = todo[~good]
    return x, y, ok
