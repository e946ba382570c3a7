"""Measures of a frosted pane (docs/method.md, section 8), shared by the benchmark and the
tests (what only the tests measure lives with them).

Stems: a link (a crystal and its parent) continues its parent's stem when it is the
parent's straightest child and turns less than STEM_TURN from the parent's own link; a
stem is a maximal chain of such links, its length the sum of its links', its order one
more than the stem it leaves (0 for a stem leaving a root).

- stem_lw: sum L^2 / sum L over stems, the length of the stem a random bit of ice lies on;
- main_frac: share of link length on stems of MAIN_PX or more;
- pinnate: median over those main stems of their length over the mean length of the stems
  leaving them;
- order: length-weighted mean stem order;
- clear21: share of BOX_PX boxes holding no live crystal or upsample particle;
- frame_mid: skeleton node density within FRAME_PX of the screen's edge over that beyond
  MID_PX from it;
- cells: share of the hash grid's cells holding a live crystal.
"""

from __future__ import annotations

import numpy as np

STEM_TURN = 30.0  # degrees
MAIN_PX = 70.0
BOX_PX = 21
FRAME_PX, MID_PX = 100.0, 200.0


def stems(crystals: np.ndarray, parents: np.ndarray, alive: np.ndarray):
    """(head, length, order) of the live links: each link's stem (the index of the stem's
    first crystal) and per link its length; order per stem head (-1 where no stem starts)."""
    n = len(crystals)
    c = crystals.astype(np.float64)
    link = alive & (parents >= 0)
    p = np.where(link, parents, np.arange(n))
    d = c - c[p]
    length = np.where(link, np.hypot(d[:, 0], d[:, 1]), 0.0)
    angle = np.arctan2(d[:, 1], d[:, 0])
    has_own = link & link[p]  # the parent has a link of its own to turn from
    turn = np.abs((angle - angle[p] + np.pi) % (2 * np.pi) - np.pi)
    turn = np.where(has_own, turn, np.inf)
    straightest = np.zeros(n, bool)
    kids = np.flatnonzero(link)
    if len(kids):
        by = kids[np.lexsort((turn[kids], p[kids]))]
        first = np.concatenate(([True], p[by][1:] != p[by][:-1]))
        straightest[by[first]] = True
    cont = straightest & (turn < np.deg2rad(STEM_TURN))
    head = np.where(cont, p, np.arange(n))
    while True:  # pointer jumping to each link's stem head
        nxt = head[head]
        if (nxt == head).all():
            break
        head = nxt
    starts = link & ~cont
    order = np.full(n, -1, np.int64)
    parent_stem = np.where(starts & link[p], head[p], -1)
    root = starts & (parent_stem < 0)
    order[root] = 0
    todo = np.flatnonzero(starts & ~root)
    while len(todo):  # stems in order of depth: each waits for the stem it leaves
        ready = order[parent_stem[todo]] >= 0
        if not ready.any():
            break
        order[todo[ready]] = order[parent_stem[todo[ready]]] + 1
        todo = todo[~ready]
    return head, length, order, parent_stem, link


def skeleton_measures(crystals, parents, alive) -> dict[str, float]:
    """stem_lw, main_frac, pinnate and order of a skeleton (see module doc)."""
    head, length, order, parent_stem, link = stems(crystals, parents, alive)
    if not link.any():
        return {"stem_lw": 0.0, "main_frac": 0.0, "pinnate": float("nan"), "order": float("nan")}
    n = len(crystals)
    L = np.bincount(head[link], weights=length[link], minlength=n)
    ids = np.flatnonzero(L > 0)
    total = L.sum()
    main = ids[L[ids] >= MAIN_PX]
    # stems leaving each stem: their count and summed length
    kid = ids[parent_stem[ids] >= 0]
    k_n = np.bincount(parent_stem[kid], minlength=n)
    k_L = np.bincount(parent_stem[kid], weights=L[kid], minlength=n)
    fed = main[k_n[main] > 0]
    pinnate = float(np.median(L[fed] / (k_L[fed] / k_n[fed]))) if len(fed) else float("nan")
    return {"stem_lw": float((L[ids] ** 2).sum() / total),
            "main_frac": float(L[main].sum() / total),
            "pinnate": pinnate,
            "order": float((L[ids] * order[ids]).sum() / total)}


def pane_measures(sim) -> dict[str, float]:
    """Every measure of the module doc for a simulation's live skeleton."""
    alive = sim.crystal_alive
    c = sim.crystals[alive]
    nodes = np.vstack((c, sim.upsampled[sim.upsampled_alive])).astype(np.float64)
    out = skeleton_measures(sim.crystals, sim.parents, alive)
    out["clear21"] = clear_boxes(nodes, sim.width, sim.height)
    out["frame_mid"] = frame_mid(nodes, sim.width, sim.height)
    held = np.zeros(sim.grid.size, bool)
    held[sim.grid.keys(c[:, 0], c[:, 1])] = True
    out["cells"] = float(held.mean())
    return out


def clear_boxes(nodes: np.ndarray, width: int, height: int, box: int = BOX_PX) -> float:
    """Share of the whole box x box px boxes tiling the screen that hold no node."""
    nx, ny = width // box, height // box
    bx, by = (nodes[:, 0] // box).astype(np.int64), (nodes[:, 1] // box).astype(np.int64)
    inside = (bx < nx) & (by < ny)
    held = np.zeros(nx * ny, bool)
    held[by[inside] * nx + bx[inside]] = True
    return float(1.0 - held.mean())


def frame_mid(nodes: np.ndarray, width: int, height: int) -> float:
    """Node density within FRAME_PX of the edge over that beyond MID_PX (areas exact)."""
    d = np.minimum(np.minimum(nodes[:, 0], width - nodes[:, 0]),
                   np.minimum(nodes[:, 1], height - nodes[:, 1]))
    a_frame = width * height - max(width - 2 * FRAME_PX, 0) * max(height - 2 * FRAME_PX, 0)
    a_mid = max(width - 2 * MID_PX, 0) * max(height - 2 * MID_PX, 0)
    if a_mid == 0 or a_frame == 0:
        return float("nan")
    mid = (d > MID_PX).sum() / a_mid
    return float(((d < FRAME_PX).sum() / a_frame) / mid) if mid else float("inf")


# The frosted end: the pane's cells holding a crystal grow by less than END_GAIN over
# END_TICKS ticks. Growth now stops with clear glass left by design (about 60-70 % of the
# cells), so a fixed coverage can no longer mark the end.
END_GAIN, END_TICKS = 0.01, 250


def frosted_end(cover) -> int | None:
    """The first tick t >= END_TICKS at which cover[t - 1] (the share of cells holding a
    crystal after tick t) exceeds cover[t - 1 - END_TICKS] by less than END_GAIN, or None."""
    c = np.asarray(cover, np.float64)
    if len(c) <= END_TICKS:
        return None
    gain = c[END_TICKS:] - c[:-END_TICKS]
    slow = np.flatnonzero(gain < END_GAIN)
    return int(slow[0]) + END_TICKS + 1 if len(slow) else None
