"""`sim/` answering the Node tests of the page's own simulation (tests/web/*.test.mjs):
run as a script with one JSON request on stdin, it writes one JSON answer on stdout.
The requests: a preset's parameters, a growth's figures (crystals at given ticks, the
first arm, the shape's measures), the measures of a skeleton the page grew, and the
exact parts (a walk step from given uniform numbers, the candidate cells of given
crystals, the crystallization of given walkers and the fern rule's decisions), and the
glass model of sim/weather/ (what given readings do to the frost, and its line)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent))

from app.bench.measures import clear_boxes, frame_mid, skeleton_measures  # noqa: E402
from app.bench.morphology import mass_radius_dimension, six_fold_order, turn_shares  # noqa: E402
from app.bench.taps import GAP_S, NEVER, tap_spots, waits  # noqa: E402
from sim import FrostSim, Params  # noqa: E402
from sim.core.buffers import Growable  # noqa: E402
from sim.core.frost import VERSION  # noqa: E402
from sim.core.placement import TWO_PI  # noqa: E402
from sim.core.skeleton import Skeleton  # noqa: E402
from sim.core.walk import walk_water  # noqa: E402
from sim.index.freezing import FreezingIndex  # noqa: E402
from sim.index.grid import HashGrid  # noqa: E402
from sim.rules.fern import FernGrowth  # noqa: E402
from sim.weather import Glass, Reading, describe, frost_of  # noqa: E402


class GivenStream:
    """A stand-in for numpy's Generator that hands out given uniform numbers in order
    (the shared seeded stream: the same numbers fed to both simulations)."""

    def __init__(self, values) -> None:
        self.values, self.at = np.asarray(values, np.float64), 0

    def random(self, size, dtype=np.float64):
        n = int(np.prod(size))
        out = self.values[self.at:self.at + n]
        if len(out) < n:
            raise ValueError(f"the given stream has {len(self.values)} numbers; {self.at + n} drawn")
        self.at += n
        return out.astype(dtype).reshape(size)

    def standard_normal(self, size):
        """Zeros (a drift of 0 makes them count for nothing), none of the given drawn."""
        return np.zeros(size)


def params_of(request: dict) -> Params:
    """The request's parameters: a preset with overrides, or fields given whole."""
    if "preset" in request:
        return Params.preset(request["preset"], **request.get("overrides", {}))
    return Params(**request["fields"])


def gyration_dimension(c: np.ndarray) -> float:
    """D of M ~ Rg^D: slope of log M on log Rg over the cluster's growth (M = 300 ... all)."""
    ks = np.geomspace(300, len(c), 12).astype(int)
    rg = [np.sqrt(((c[:k] - c[:k].mean(axis=0)) ** 2).sum(axis=1).mean()) for k in ks]
    return float(np.polyfit(np.log(rg), np.log(ks), 1)[0])


def measures(crystals: np.ndarray, parents: np.ndarray, centre, hc: float) -> dict:
    """The shape's figures of docs/benchmarks.md: dimension, S6, straight share; the
    mean link length and the gyration dimension (tests/test_fern.py's)."""
    child = np.flatnonzero(parents >= 0)
    links = np.hypot(*(crystals[child] - crystals[parents[child]]).astype(np.float64).T)
    with np.errstate(divide="ignore"):  # (a melt's hole leaves no crystal near the centre)
        return {"link": float(links.mean()) if len(links) else float("nan"),
                "dimension": mass_radius_dimension(crystals, centre, hc),
                "s6": six_fold_order(crystals, parents),
                "straight": turn_shares(crystals, parents)["straight"],
                "gyration": gyration_dimension(crystals.astype(np.float64))
                if len(crystals) >= 600 else float("nan")}


def live_skeleton(sim: FrostSim) -> tuple[np.ndarray, np.ndarray]:
    """The live crystals and their parents, renumbered among the live (-1: a root)."""
    alive = sim.crystal_alive
    index = np.full(len(alive) + 1, -1, np.int32)  # (the last: a seed's parent, -1)
    index[np.flatnonzero(alive)] = np.arange(int(alive.sum()), dtype=np.int32)
    return sim.crystals[alive], index[sim.parents[alive]]


def grow(request: dict) -> dict:
    """One touch grown: crystals at `ticks`, the tick of the seed's first child, and the
    measures at `measure_at` (or once `until_crystals` crystals are reached); with `melt`,
    a warm finger, and the live crystals at the ticks of `live_at`."""
    params, centre = params_of(request), tuple(request.get("touch", (380.0, 640.0)))
    sim = FrostSim(params, seed=request["seed"])
    sim.touch(*centre)
    ticks, counts, first = set(request.get("ticks", ())), {}, None
    last = max([*ticks, request.get("measure_at", 0)])
    until = request.get("until_crystals")
    melt = request.get("melt")  # [tick, x, y, r]: a warm finger before that tick
    live = {}
    while sim.tick < last or (until and len(sim.crystals) < until):
        if melt and sim.tick == melt[0]:
            live["melted"] = len(sim.melt(*melt[1:]).crystals)
        sim.step()
        if str(sim.tick) in request.get("live_at", ()):
            live[str(sim.tick)] = int(sim.crystal_alive.sum())
        if first is None and len(sim.crystals) > 1:
            first = sim.tick
        if sim.tick in ticks:
            counts[str(sim.tick)] = len(sim.crystals)
        if sim.tick == request.get("measure_at") and not until:
            break
    crystals, parents = live_skeleton(sim)
    if melt:  # the live crystals that grew back inside the melted disc
        inside = np.hypot(*(crystals.astype(np.float64) - melt[1:3]).T) < melt[3]
        live["inside"] = int(inside.sum())
    return {"counts": counts, "first_child": first, "live": live,
            "upsampled_per_link": len(sim.upsampled) / max(1, int((sim.parents >= 0).sum())),
            "measures": measures(crystals, parents, centre, params.hc)}


def measure(request: dict) -> dict:
    c = np.asarray(request["crystals"], np.float32).reshape(-1, 2)
    p = np.asarray(request["parents"], np.int32)
    return measures(c, p, tuple(request["centre"]), request["hc"])


def walk(request: dict) -> dict:
    """One walk of walkers at `xy` in an area `area` (centre x, y, radius) by the given
    uniforms, with `jump` (each walker's clearance, float64: long jumps) if given: their
    new positions and which left."""
    xy = np.asarray(request["xy"], np.float32).reshape(-1, 2)
    x, y = xy[:, 0].copy(), xy[:, 1].copy()
    columns = np.asarray(request["area"], np.float32)
    jump = None if request.get("jump") is None else np.asarray(request["jump"], np.float64)
    left = walk_water(GivenStream(request["u"]), x, y, columns, request["step"], jump,
                      (request["width"], request["height"]), False)
    # Where numpy's float32 cos and sin of a walker's angle are the correctly rounded ones
    # (a float64 cos rounded to float32, as the page computes them).
    theta = np.asarray(request["u"], np.float32)[len(x):] * TWO_PI
    wide = theta.astype(np.float64)
    rounded = ((np.cos(theta) == np.cos(wide).astype(np.float32))
               & (np.sin(theta) == np.sin(wide).astype(np.float32)))
    return {"x": x.tolist(), "y": y.tolist(), "left": left.tolist(), "trig_rounded": rounded.tolist()}


def cells(request: dict) -> dict:
    """The candidate cells of crystals at `crystals` (each cell's list), the cell of each
    walker at `walkers`, and the walkers within hc of a crystal with their nearest."""
    c = Growable(np.float32, (2,))
    c.append(np.asarray(request["crystals"], np.float32).reshape(-1, 2))
    index = FreezingIndex(c, request["width"], request["height"], request["hc"], "candidate",
                          False, False)
    index.register(slice(0, c.n))
    listed = np.flatnonzero(index.candidates.count)
    lists = {str(int(k)): index.candidates.items[k, :index.candidates.count[k]].tolist() for k in listed}
    w = np.asarray(request["walkers"], np.float32).reshape(-1, 2)
    x, y = np.ascontiguousarray(w[:, 0]), np.ascontiguousarray(w[:, 1])
    hits, parents = index.nearest(x, y)
    return {"lists": lists, "keys": index.grid.keys(x, y).tolist(), "hits": hits.tolist(),
            "parents": parents.tolist()}


def fern(request: dict) -> list[dict]:
    """The fern rule's decisions (sim/rules/fern.py FernGrowth.settle, newest rules) over
    ticks of given walkers: seeds at `seeds` (their grains from the given uniforms `u`,
    `ringed` each), then each tick the walkers within hc of a crystal settle, and those
    that grow become crystals linked to their parents."""
    params = params_of(request)
    width, height = request["width"], request["height"]
    ice = Skeleton()
    index = FreezingIndex(ice.crystals, width, height, params.hc, "candidate", False,
                          params.long_jumps)
    growth = FernGrowth(params, GivenStream(request["u"]), pooled_first=True, capped=True)
    seeds = np.asarray(request["seeds"], np.float32).reshape(-1, 2)
    new = ice.add(seeds, np.full(len(seeds), -1, np.int32), np.zeros(len(seeds), np.int32))
    growth.add_seeds(len(seeds), request["ringed"])
    index.register(new)
    out = []
    for walkers in request["ticks"]:
        w = np.asarray(walkers, np.float32).reshape(-1, 2)
        hits, parents = index.nearest(np.ascontiguousarray(w[:, 0]), np.ascontiguousarray(w[:, 1]))
        grown, parents, pts, counted = growth.settle(w[hits], hits, parents, ice, index)
        new = ice.add(pts, parents, np.zeros(len(pts), np.int32))
        ice.link(new.start, ice.crystals.raw()[parents], pts, params.D)
        index.register(new)
        out.append({"grown": grown.tolist(), "parents": parents.tolist(),
                    "pts": pts.ravel().tolist(), "counted": sorted(counted.tolist())})
    return out


def taps(request: dict) -> dict:
    """The page bench's taps through sim/ (app/bench/taps.py): their spots, and each tap's
    wait for its seed's first child, seed by seed (NEVER: none)."""
    n = request["taps"]
    return {"spots": tap_spots(n).ravel().tolist(), "never": NEVER, "gap_s": GAP_S,
            "waits": [waits(request["preset"], VERSION, n, s).tolist() for s in request["seeds"]]}


def pane_figures(crystals, parents, alive, upsampled, width: int, height: int, hc: float) -> dict:
    """app/bench/measures.py's pane measures (its `pane_measures`) of a skeleton given as
    arrays: every crystal (x, y), its parent (-1 a root) and alive flag, and the live
    upsample particles."""
    c = np.asarray(crystals, np.float32).reshape(-1, 2)
    alive = np.asarray(alive, bool)
    out = skeleton_measures(c, np.asarray(parents, np.int64), alive)
    nodes = np.vstack((c[alive], np.asarray(upsampled, np.float32).reshape(-1, 2))).astype(np.float64)
    out["clear21"] = clear_boxes(nodes, width, height)
    out["frame_mid"] = frame_mid(nodes, width, height)
    grid = HashGrid(width, height, hc)
    held = np.zeros(grid.size, bool)
    held[grid.keys(c[alive, 0], c[alive, 1])] = True
    out["cells"] = float(held.mean())
    return out


def pane_measure(request: dict) -> dict:
    return pane_figures(request["crystals"], request["parents"], request["alive"], request["upsampled"],
                        request["width"], request["height"], request["hc"])


def cover(sim: FrostSim) -> float:
    """Share of the hash cells holding a live crystal."""
    c = sim.crystals[sim.crystal_alive]
    held = np.zeros(sim.grid.size, bool)
    held[sim.grid.keys(c[:, 0], c[:, 1])] = True
    return float(held.mean())


def window(request: dict) -> dict:
    """The window preset (`overrides` applied) grown on a `size` pane from `seed` with no
    touch: the ticks to `cover_to` of the cells (None past `most` ticks) and, at
    `measure_at`, the pane's measures."""
    params = params_of({"preset": "window", **request})
    width, height = request.get("size", (760, 1280))
    sim = FrostSim(params, width, height, seed=request["seed"])
    reached, to, at = None, request.get("cover_to"), request.get("measure_at", 0)
    out: dict = {}
    while sim.tick < max(at, request.get("most", 0)):
        sim.step()
        if to is not None and reached is None and cover(sim) >= to:
            reached = sim.tick
            if sim.tick >= at:
                break
        if sim.tick == at:
            alive = sim.crystal_alive
            out["measures"] = pane_figures(sim.crystals, sim.parents, alive,
                                           sim.upsampled[sim.upsampled_alive], width, height, params.hc)
            if to is None or reached is not None:
                break
    return {**out, "reached": reached}


def glass(request: dict) -> list[dict]:
    """sim/weather's glass for each reading of `readings` ({"reading": Reading's JSON,
    "glass": Glass's JSON}): the glass's temperature, the state, the preset's temperature,
    the supply and the reading's line."""
    out = []
    for case in request["readings"]:
        reading, window = Reading.from_json(case["reading"]), Glass.from_json(case["glass"])
        frost = frost_of(reading.temperature_c, window)
        out.append({"glass": frost.glass_c, "state": frost.state, "temperature": frost.temperature,
                    "supply": frost.supply, "line": describe(reading, window)})
    return out


def answer(request: dict) -> object:
    kind = request["kind"]
    if kind == "params":
        return params_of(request).as_dict()
    if kind == "grow":
        return [grow({**request, "seed": s}) for s in request["seeds"]]
    if kind == "window":
        return [window({**request, "seed": s}) for s in request["seeds"]]
    handlers = {"pane_measure": pane_measure, "measure": measure, "walk": walk, "cells": cells,
                "fern": fern, "taps": taps, "glass": glass}
    if kind not in handlers:
        raise ValueError(f"unknown request kind {kind!r}")
    return handlers[kind](request)


if __name__ == "__main__":
    json.dump(answer(json.load(sys.stdin)), sys.stdout, allow_nan=True)
