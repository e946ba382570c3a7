"""The tile figures of docs/engine-maps.md: a window-preset tile grown to its frosted end (the share
of hash cells holding a crystal gains less than END_GAIN over END_TICKS ticks,
app.bench.measures), timed as `frost maps --tile` grows it (simulation, geometry, growth clock),
then its maps computed and written, with the peak memory of the process.

python -m bench tiles [SIZE] [--max-ticks N] [--out DIR] [--record] (from a checkout)
"""

from __future__ import annotations

import tempfile
import time

import numpy as np

from app.bench.measures import frosted_end
from app.bench.memory import mb, peak_rss_mb
from app.bench.options import Parser
from app.tools.engine_maps import EngineRun, write_engine_maps
from app.tools.maps import tile_window
from sim import Params
from sim.io.timeline import Timeline
from sim.look.growthmap import GrowthClock


class Cover:
    """Share of the hash grid's cells holding a crystal after each tick (new crystals only)."""

    def __init__(self, cells: int):
        self.shares: list[float] = []
        self._held = np.zeros(cells, bool)

    def add(self, sim) -> int | None:
        """Count the tick's new crystals; the frosted end's tick once it has come."""
        c = sim.crystals[sim.added.crystals]
        self._held[sim.grid.keys(c[:, 0], c[:, 1])] = True
        self.shares.append(float(self._held.mean()))
        return frosted_end(self.shares) if len(self.shares) % 50 == 0 else None


def grow_to_end(params: Params, size: tuple[int, int], max_ticks: int):
    """(timeline, clock, end tick or None) of a tile grown to its frosted end."""
    timeline = Timeline(params, 0, *size, wrap=True)
    clock, cover = GrowthClock(params, *size, True), Cover(timeline.sim.grid.size)
    end = None
    while end is None and timeline.tick < max_ticks:
        for delta in timeline.step():
            clock.apply(delta)
        end = cover.add(timeline.sim)
    print(f"cells holding a crystal: {cover.shares[-1]:.1%}")
    return timeline, clock, end


def main(argv: list[str] | None = None, prog: str = "python -m bench tiles") -> int:
    p = Parser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("size", type=int, nargs="?", default=2048, help="tile side, px (default 2048)")
    p.add_argument("--max-ticks", type=int, default=6000, help="give up after (default 6000)")
    p.add_argument("--out", help="write the maps here (default a temporary folder)")
    args = p.parse_args(argv)
    size = (args.size, args.size)
    params = tile_window(Params.preset("window"), size)
    t0 = time.perf_counter()
    timeline, clock, end = grow_to_end(params, size, args.max_ticks)
    grown = time.perf_counter() - t0
    print(f"peak RSS after growing: {mb(peak_rss_mb())}")
    job = EngineRun(timeline.sim, timeline.geometry, clock, params, 0, [], True, "up",
                    timeline.tick)
    with tempfile.TemporaryDirectory() as tmp:
        write_engine_maps(args.out or tmp, job)
    written = time.perf_counter() - t0 - grown
    print(f"{args.size}x{args.size} window tile: frosted end at tick {end} "
          f"(ran {timeline.tick}); grown in {grown:.1f} s, maps written in {written:.1f} s, "
          f"peak RSS {mb(peak_rss_mb())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
