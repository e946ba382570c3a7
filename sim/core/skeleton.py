"""The ice skeleton: crystals with parent links, upsample particles and chain segments.

Rows are only appended; a melt marks them dead, so indices stay stable. A link's rows are
appended together, in crystal order, so each row's crystal (`upsampled_link`, `segments_link`)
ascends, and a melt finds the rows of the links it cuts by binary search, without
scanning the whole skeleton.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .buffers import Growable


@dataclass(frozen=True)
class Added:
    """Index ranges appended since the previous tick (touches included)."""

    tick: int
    crystals: slice
    upsampled: slice
    segments: slice
    frozen: int  # water particles that froze in this tick


@dataclass(frozen=True)
class Melted:
    """What one `melt` removed (indices into crystals, upsampled, segments) and the
    crystals that lost their parent and became roots of their own trees."""

    crystals: np.ndarray
    upsampled: np.ndarray
    segments: np.ndarray
    orphans: np.ndarray


class Skeleton:
    """Crystals (positions, parents, alive flags, the area whose water became each) and
    their links' upsample particles and segments, each row with its link's crystal."""

    def __init__(self) -> None:
        self.crystals = Growable(np.float32, (2,))
        self.parents = Growable(np.int32)  # -1 for a seed
        self.area = Growable(np.int32)  # the area whose water became each crystal
        self.crystal_alive = Growable(bool)
        self.upsampled = Growable(np.float32, (2,))
        self.upsampled_link = Growable(np.int32)
        self.upsampled_alive = Growable(bool)
        self.segments = Growable(np.float32, (4,))
        self.segments_link = Growable(np.int32)
        self.segments_alive = Growable(bool)
        self.longest_link = 0.0  # a crystal's children lie within this of it

    def tips(self) -> np.ndarray:
        """The live crystals no live crystal grows from (the ice's thin edges), ascending."""
        alive, parents = self.crystal_alive.raw(), self.parents.raw()
        has_child = np.zeros(len(alive), bool)
        has_child[parents[alive & (parents >= 0)]] = True
        return np.flatnonzero(alive & ~has_child)

    def add(self, pts: np.ndarray, parents: np.ndarray, area: np.ndarray) -> slice:
        """Append live crystals with their parents and areas."""
        new = self.crystals.append(pts)
        self.parents.append(parents)
        self.area.append(area)
        self.crystal_alive.append_fill(len(pts), True)
        return new

    def link(self, first: int, tail: np.ndarray, pts: np.ndarray, spacing: float) -> None:
        """The links tail[i] -> pts[i] of crystals first, first + 1, ..., upsampled."""
        points, point_link, segments, segment_link = upsample(tail, pts, spacing)
        self.upsampled.append(points)
        self.upsampled_alive.append_fill(len(points), True)
        self.segments_alive.append_fill(len(segments), True)
        self.upsampled_link.append(point_link.astype(np.int32) + first)
        self.segments.append(segments)
        self.segments_link.append(segment_link.astype(np.int32) + first)
        if len(pts):
            d = pts - tail
            self.longest_link = max(self.longest_link, float(np.hypot(d[:, 0], d[:, 1]).max()))

    def cut(self, crystals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Kill the live segments and upsample particles of the links of `crystals`;
        returns (segments, upsample particles) killed."""
        segments = self.live_segments(crystals)
        points = rows(self.upsampled_link.raw(), crystals)
        points = points[self.upsampled_alive.raw()[points]]
        self.segments_alive.raw()[segments] = False
        self.upsampled_alive.raw()[points] = False
        return segments, points

    def live_segments(self, crystals: np.ndarray) -> np.ndarray:
        """The live segments of the links of `crystals`."""
        segments = rows(self.segments_link.raw(), crystals)
        return segments[self.segments_alive.raw()[segments]]

    def counts(self) -> tuple[int, int, int]:
        """Rows so far: crystals, upsample particles, segments."""
        return (self.crystals.n, self.upsampled.n, self.segments.n)

    def buffers(self) -> tuple[Growable, ...]:
        return (self.crystals, self.parents, self.upsampled, self.upsampled_link, self.segments,
                self.segments_link, self.area, self.crystal_alive, self.upsampled_alive,
                self.segments_alive)


def upsample(p: np.ndarray, q: np.ndarray, spacing: float) -> tuple[np.ndarray, ...]:
    """Eq. 3-4 for links p[i] -> q[i]: Nu = floor(|q - p| / D); if Nu >= 2 the Nu - 1
    points p + (k / Nu)(q - p), k = 1..Nu-1, split the link into a chain of Nu segments.

    Returns (points, point_link, segments, segment_link): points k x 2, segments
    s x 4 (x0, y0, x1, y1) in chain order, and the link index of each."""
    p64 = p.astype(np.float64)
    d = q.astype(np.float64) - p64
    nu = np.floor(np.hypot(d[:, 0], d[:, 1]) / spacing).astype(np.int64)
    if not (nu >= 2).any():  # no link long enough: each is one segment (the common case at c-2)
        links = np.arange(len(p))
        return np.empty((0, 2), np.float32), links[:0], np.hstack([p, q]).astype(np.float32), links
    nseg = np.where(nu >= 2, nu, 1)
    k = int(nseg[0])
    if (nseg == k).all():  # links alike (a fern's are one hc each): a grid of link x node
        nodes = p64[:, None, :] + (np.arange(k + 1) / k)[None, :, None] * d[:, None, :]
        chain = np.concatenate((nodes[:, :-1], nodes[:, 1:]), axis=2).reshape(-1, 4)
        links = np.arange(len(p))
        return (nodes[:, 1:-1].reshape(-1, 2).astype(np.float32), links.repeat(k - 1),
                chain.astype(np.float32), links.repeat(k))
    seg_link = np.arange(len(p)).repeat(nseg)
    j = np.arange(len(seg_link)) - (nseg.cumsum() - nseg)[seg_link]
    per = nseg[seg_link]
    t0 = (j / per)[:, None]
    t1 = ((j + 1) / per)[:, None]
    p_s, d_s = p64[seg_link], d[seg_link]
    a = p_s + t0 * d_s
    b = p_s + t1 * d_s
    segments = np.concatenate((a, b), axis=1).astype(np.float32)
    inner = j > 0  # a chain's inner nodes are the upsample particles
    return a[inner].astype(np.float32), seg_link[inner], segments, seg_link


def rows(link: np.ndarray, crystals: np.ndarray) -> np.ndarray:
    """The rows of the links of `crystals`, crystal by crystal, each one's ascending, given
    every row's crystal `link` (ascending: a link's rows are appended together)."""
    c = np.asarray(crystals).astype(link.dtype, copy=False)
    first = link.searchsorted(c)
    count = link.searchsorted(c, "right") - first
    total = int(count.sum())
    if total == 0:
        return np.empty(0, np.int64)
    return (first - (count.cumsum() - count)).repeat(count) + np.arange(total)
