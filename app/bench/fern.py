"""The fern section of `frost bench sim` (docs/method.md, section 6): shape measures and
tick costs of paper c-2 against the fern look, and where a fern tick goes."""

from __future__ import annotations

import time

import numpy as np

from app.bench.growth import CENTRE, time_phases
from app.bench.morphology import extent, mass_radius_dimension, six_fold_order, turn_shares
from sim import FrostSim, Params
from sim.look.geometry import FrostGeometry

FERN_TICKS = (25, 50, 125, 250, 500, 750)
FERN_LOOKS = {"c-2": {}, "fern": {}, "fern-nogrow": {"grow": False}}
# Touch spots for the cost runs: the centre, then spread over the screen.
TOUCHES = [CENTRE, (190.0, 320.0), (570.0, 960.0), (570.0, 320.0), (190.0, 960.0),
           (380.0, 200.0), (380.0, 1080.0), (120.0, 640.0), (640.0, 640.0), (380.0, 420.0)]


def fern_shape(name: str, seed: int) -> dict:
    """One touch of look `name` grown for 750 ticks: the fern section's measures."""
    base, extra = ("c-2", {}) if name == "c-2" else ("fern", FERN_LOOKS[name])
    sim = FrostSim(Params.preset(base, **extra), seed=seed)
    sim.touch(*CENTRE)
    row: dict = {"crystals": {}, "reach150": None}
    while sim.tick < FERN_TICKS[-1]:
        sim.step()
        if row["reach150"] is None and extent(sim.crystals, CENTRE) >= 150:
            row["reach150"] = sim.tick
        if sim.tick in FERN_TICKS:
            row["crystals"][sim.tick] = len(sim.crystals)
        if sim.tick == 25:
            row["extent25"] = extent(sim.crystals, CENTRE)
        if sim.tick == 500:
            c, p = sim.crystals, sim.parents
            row.update(dim=mass_radius_dimension(c, CENTRE, sim.params.hc), s6=six_fold_order(c, p),
                       **turn_shares(c, p))
    return row


def fern_costs(name: str, touches: int, ticks: int) -> tuple[float, float]:
    """Median sim and geometry ms per tick over `ticks` ticks from `touches` touches."""
    base, extra = ("c-2", {}) if name == "c-2" else ("fern", FERN_LOOKS[name])
    params = Params.preset(base, **extra)
    sim, geometry = FrostSim(params, seed=0), FrostGeometry(params)
    for x, y in TOUCHES[:touches]:
        sim.touch(x, y)
    t_sim, t_geo = [], []
    for _ in range(ticks):
        t0 = time.perf_counter()
        sim.step()
        t1 = time.perf_counter()
        geometry.update(sim)
        t_sim.append(t1 - t0)
        t_geo.append(time.perf_counter() - t1)
    return 1e3 * float(np.median(t_sim)), 1e3 * float(np.median(t_geo))


def fern_profile(ticks: int) -> dict[str, float]:
    """Mean ms per tick spent in each phase of one fern touch's first `ticks` ticks."""
    sim = FrostSim(Params.preset("fern"), seed=0)
    sim.touch(*CENTRE)
    spent = time_phases(sim, more=True)
    for _ in range(ticks):
        sim.step()
    return {k: 1e3 * v / ticks for k, v in spent.items()}


def fern_section(seeds: int, ticks: int) -> dict:
    print(f"\n## Fern growth vs the paper: one touch, seeds 0..{seeds - 1} (median; dimension "
          "and turns at tick 500)")
    print("look        dim   S6  straight  +-60  +-120  150px@tick  extent@25  crystals at "
          + "/".join(map(str, FERN_TICKS)))
    out: dict = {}
    for name in FERN_LOOKS:
        rows = [fern_shape(name, s) for s in range(seeds)]
        med = {k: float(np.median([r[k] for r in rows])) for k in ("dim", "s6", "straight", "60", "120",
                                                                     "extent25")}
        reach = [r["reach150"] or -1 for r in rows]
        counts = [int(np.median([r["crystals"][t] for r in rows])) for t in FERN_TICKS]
        out[name] = {**med, "reach150": reach, "crystals": counts}
        print(f"{name:10} {med['dim']:5.2f} {med['s6']:4.2f} {100 * med['straight']:8.0f}% "
              f"{100 * med['60']:4.0f}% {100 * med['120']:5.0f}% {str(reach):>11}  "
              f"{med['extent25']:6.0f} px  " + "/".join(map(str, counts)))
    print(f"\nms per tick (median of {ticks} ticks from the touches; humidity 3000 each): sim + geometry")
    print("look        1 touch        3 touches      10 touches")
    for name in FERN_LOOKS:  # side by side, so machine load hits every look alike
        cells = [fern_costs(name, n, ticks) for n in (1, 3, 10)]
        out[name]["ms"] = cells
        print(f"{name:10} " + "  ".join(f"{a:5.2f} + {b:5.2f}" for a, b in cells))
    prof = fern_profile(ticks)
    print("\nwhere a fern tick goes (one touch, mean ms; walk includes the relocation of its "
          "leavers, which relocate counts again; counted_and_new: the hits that only counted "
          "placed again and the frozen water's replacement, in one pass): "
          + ", ".join(f"{k} {v:.3f}" for k, v in prof.items()))
    out["fern_profile"] = prof
    return out

