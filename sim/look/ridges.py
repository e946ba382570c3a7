"""The glass look's sharp features: one tapered ridge per crystal -> child link, with a
pipe-model thickness (docs/method.md, "The glass look").

A link's half-width grows with the cube root of the crystals it carries (the child and
everything grown from it), so trunks are thick, side branches thinner and tips pointed;
a pointed cap at each end merges consecutive links into one continuous ridge. Widths
are quantized in levels and a link is sent again only when its level rises (the higher
surface wins the renderer's depth test, so nothing needs erasing); a melt takes the
melted crystals out of every count above them and thins what it cut.
"""

from __future__ import annotations

import numpy as np

from ..index.periodic import image_near
from ..params import Params

VERTS_PER_LINK = 24  # 8 triangles: two body faces and a cap on each side at each end
MIN_HALF_WIDTH = 0.9  # px: a tip's ridge is about 2 px wide
# px the faces run on past a ridge's edge, below the glass: the feature pass anti-aliases
# the edge over the pixels it crosses (shaders/feature.frag, EDGE_AA), and a pixel whose
# centre lies within half its diagonal (0.71 px) of the edge is one of them.
EDGE_PAD = 0.75
MAX_HALF_WIDTH = 0.7  # x hc: a trunk never swells over its neighbours' freezing areas
LEVELS_PER_DOUBLING = 2  # width levels per doubling of the carried count (+12 % width each)
TILT = 0.18  # spread of the random tilt per ridge face (sparkle), normal x and y
PRUNE_EVERY = 8  # levels a climb goes between droppings of the paths that ended


def width_level(carried: np.ndarray, hc: float) -> np.ndarray:
    """Thickness level of links carrying `carried` crystals: floor(2 log2 n), 0 for a tip,
    no higher than the level whose width reaches the cap (thicker links look the same)."""
    top = np.ceil(3.0 * LEVELS_PER_DOUBLING * np.log2(widest(hc) / MIN_HALF_WIDTH))
    level = np.floor(LEVELS_PER_DOUBLING * np.log2(np.maximum(carried, 1)))
    return np.minimum(level, top).astype(np.int32)


def half_width(level: np.ndarray, hc: float) -> np.ndarray:
    """Half-width of a link at `level`, px: MIN_HALF_WIDTH * n^(1/3) at the level's
    lowest n, capped at MAX_HALF_WIDTH * hc."""
    w = MIN_HALF_WIDTH * np.exp2(level / (3.0 * LEVELS_PER_DOUBLING))
    return np.minimum(w, widest(hc))


def widest(hc: float) -> float:
    """The widest half-width a ridge can have, px."""
    return max(MAX_HALF_WIDTH * hc, MIN_HALF_WIDTH)


def ridge_height(params: Params) -> float:
    """Ridge height per px of half-width (the flanks' slope): twice feature_height."""
    return 2.0 * params.feature_height


def top_height(params: Params) -> float:
    """The highest a ridge can stand, px."""
    return ridge_height(params) * widest(params.hc)


# Corners of a ridge: 0 P top, 1 Q top, 2 Q+, 3 P+, 4 Q-, 5 P-, 6 Q tip, 7 P tip (+/-: the
# sides along n); its faces: two on each side of the body, a cap on each side at each end.
FACES = np.array([0, 1, 2, 0, 2, 3, 0, 1, 4, 0, 4, 5, 1, 2, 6, 1, 4, 6, 0, 3, 7, 0, 5, 7])
# Each face falls away from the ridge line with the flanks' slope s, toward +-n on the body
# and toward +-t and +-n on a cap, so its normal is (s (ft t + fn n), 1) whatever the width.
FACE_T = np.array([0, 0, 0, 0, 1, 1, -1, -1], np.float32)[None, :, None]
FACE_N = np.array([1, 1, -1, -1, 1, -1, 1, -1], np.float32)[None, :, None]


def ridge_triangles(p: np.ndarray, q: np.ndarray, w: np.ndarray, slope: float,
                    ids: np.ndarray) -> np.ndarray:
    """(24 k) x 6 float32 vertices (x, y, z, nx, ny, nz) of ridges from p to q (k x 2),
    half-width w; each face's normal tilted a little at random (seeded by `ids`). The
    faces reach EDGE_PAD past the edge, on the same planes (below the glass there)."""
    p, q = p.astype(np.float32), q.astype(np.float32)
    w = w.astype(np.float32)[:, None]
    d = q - p
    length = np.hypot(d[:, 0], d[:, 1])[:, None]
    t = np.where(length > 0, d / np.where(length > 0, length, 1.0),
                 np.array([1.0, 0.0], np.float32))
    n = np.column_stack((-t[:, 1], t[:, 0]))
    wt, wn = (w + EDGE_PAD) * t, (w + EDGE_PAD) * n
    pts = np.full((len(p), 8, 3), -slope * EDGE_PAD, np.float32)
    for i, corner in enumerate((p, q, q + wn, p + wn, q - wn, p - wn, q + wt, p - wt)):
        pts[:, i, :2] = corner
    pts[:, :2, 2] = slope * w
    nxy = slope * (FACE_T * t[:, None, :] + FACE_N * n[:, None, :])
    nxy += TILT * _jitter(ids[:, None] * 8 + np.arange(8)).reshape(nxy.shape)
    normal = np.concatenate((nxy, np.ones((len(p), 8, 1), np.float32)), axis=2)
    normal /= np.linalg.norm(normal, axis=2, keepdims=True)
    verts = np.empty((len(p), 8, 3, 6), np.float32)
    verts[..., :3] = pts[:, FACES].reshape(-1, 8, 3, 3)
    verts[..., 3:] = normal[:, :, None, :]
    return verts.reshape(-1, 6)


def _jitter(keys: np.ndarray) -> np.ndarray:
    """Two numbers in [-1, 1) per key, the same for the same key (a hash, no state), so a
    redrawn ridge keeps its glints."""
    h = (keys.ravel().astype(np.uint64) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(11)
    h2 = (h * np.uint64(0xBF58476D1CE4E5B9)) >> np.uint64(11)
    u = np.column_stack((h & np.uint64(0xFFFF), h2 & np.uint64(0xFFFF))).astype(np.float32)
    return u / np.float32(32768.0) - np.float32(1.0)


class PipeRidges:
    """The carried counts and drawn levels of every link; turns a tick's new crystals (or
    a melt) into the ridges to send."""

    def __init__(self, params: Params):
        self.params = params
        self.slope = ridge_height(params)
        self.carried = np.zeros(0, np.int64)  # crystals each crystal's link carries
        self.drawn = np.zeros(0, np.int32)  # level each link was last sent at (-1: never)

    def grow(self, sim, new: slice) -> np.ndarray:
        """Count the new crystals into every link above them; the ridges of the new links
        and of those that thickened."""
        self._extend(len(sim.crystals))
        idx = np.arange(new.start, new.stop)
        idx = idx[sim.crystal_alive[idx]]
        self.carried[idx] = 1
        touched = self._propagate(sim.parents, sim.parents[idx], 1)
        links = np.union1d(idx, touched)
        alive = sim.crystal_alive[links] & (sim.parents[links] >= 0)
        links = links[alive]
        level = width_level(self.carried[links], self.params.hc)
        return self.triangles(sim, links[level > self.drawn[links]])

    def melt(self, sim, dead: np.ndarray) -> np.ndarray:
        """Take the melted crystals out of the counts above them (sim.melt has cut their
        children loose already); the links whose level fell, which must be redrawn."""
        self._extend(len(sim.crystals))  # a melt may come before any growth was counted
        parents = sim.parents
        up = parents[dead]
        roots = dead[(up >= 0) & ~np.isin(up, dead)]  # melted, with a parent that survived
        touched = self._propagate(parents, parents[roots], -self.carried[roots])
        self.drawn[dead] = -1
        touched = touched[sim.crystal_alive[touched] & (parents[touched] >= 0)]
        return touched[width_level(self.carried[touched], self.params.hc) < self.drawn[touched]]

    def triangles(self, sim, links: np.ndarray) -> np.ndarray:
        """The ridges of `links` (child crystal indices) at their levels now, marked drawn."""
        level = width_level(self.carried[links], self.params.hc)
        self.drawn[links] = level
        w = half_width(level, self.params.hc)
        c = sim.crystals
        size = (sim.width, sim.height) if getattr(sim, "wrap", False) else None
        tail = image_near(c[sim.parents[links]], c[links], size)  # a tile: beside the child
        return ridge_triangles(tail, c[links], w, self.slope, links)

    def _extend(self, n: int) -> None:
        """Room for `n` crystals and the sentinel slot after them (`_propagate`)."""
        if n >= len(self.carried):
            grow = n + 1 - len(self.carried)
            self.carried = np.concatenate((self.carried, np.zeros(max(grow, n), np.int64)))
            self.drawn = np.concatenate((self.drawn, np.full(max(grow, n), -1, np.int32)))

    def _propagate(self, parents: np.ndarray, start: np.ndarray, amount) -> np.ndarray:
        """Add `amount` (a number, or one per start) to the count of every crystal from
        `start` up to its root; the crystals changed (unique). A climb takes one numpy
        pass per level of the deepest path (fronds run hundreds deep), so each level does
        the least: the roots step up to a sentinel slot past the last crystal, whose
        count is thrown away, instead of being filtered out at every level."""
        n = len(parents)
        up = np.append(np.where(parents >= 0, parents, n), n)
        carried = self.carried  # (_extend keeps a free slot past the last crystal)
        keep = start >= 0
        f = start[keep]
        a = np.asarray(amount)  # one number for all, or one per start
        a = a if a.ndim == 0 else a[keep]
        touched = [f]
        level = 0
        while len(f):
            np.add.at(carried, f, a)
            f = up[f]
            touched.append(f)
            level += 1
            if level % PRUNE_EVERY == 0:  # drop the climbs that reached the sentinel
                going = f != n
                f = f[going]
                a = a if a.ndim == 0 else a[going]
        carried[n] = 0
        out = np.unique(np.concatenate(touched))
        return out[:np.searchsorted(out, n)]
