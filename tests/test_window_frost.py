"""Window mode (sim/rules/window_mode.py): seeds on the frame, one pane-wide pool, temperature, and a wiped
path that refreezes from its edges, against brute-force oracles."""

import numpy as np
import pytest

from app.bench.measures import frosted_end
from sim import FrostSim, Params, preset_name
from sim.index.grid import CELL_MARGIN
from sim.params import FROND_RULES
from sim.rules.window_mode import BAND

WINDOW = Params.preset("window")
W, H = 300, 400  # a small pane keeps full coverage within a few hundred ticks
PATH = [(40.0 + 10 * i, 150.0 + 3 * i) for i in range(23)]  # a finger's drag
R = 20.0  # its radius, px


def seeds_of(sim):
    return sim.crystals[sim.parents == -1].astype(np.float64)


def arc_length(p, w, h):
    """Clockwise distance along the border from the top-left corner to the border point p
    (the nearest side), an independent parametrisation of the frame."""
    x, y = p[:, 0], p[:, 1]
    side = np.argmin(np.column_stack((y, w - x, h - y, x)), axis=1)
    return np.choose(side, [x, w + y, 2 * w + h - x, 2 * (w + h) - y])


def test_window_is_fern_plus_window_mode_and_the_others_are_untouched():
    off = {k: getattr(Params, k) for k in FROND_RULES}
    assert WINDOW.replace(window_frost=False, tip_hits=5, side_hits=10, humidity=3000,
                          water_budget=6000, **off) == Params.preset("fern")
    assert preset_name(WINDOW) == "window" and preset_name(Params.preset("fern")) == "fern"
    assert not Params().window_frost and not Params.preset("fern").window_frost


@pytest.mark.parametrize("changes, named", [
    ({"window_frost": True, "temperature": 0.0}, "temperature"),
    ({"window_frost": True, "frame_sites": -1.0}, "frame_sites"),
    ({"window_frost": True, "pane_sites": 2.5}, "pane_sites"),
    ({"frame_sites": 5.0}, "window_frost"),
    ({"window_frost": True, "grains": False}, "grains"),
])
def test_bad_window_values_name_the_parameter(changes, named):
    base = Params.preset("fern").replace(window_frost=False) if "grains" in changes else Params.preset("fern")
    with pytest.raises(ValueError, match=named):
        base.replace(**changes)


def test_frame_seeds_lie_on_the_border_and_pane_sites_on_the_glass():
    sim = FrostSim(WINDOW.replace(pane_sites=0), W, H, seed=3)
    s = seeds_of(sim)
    edge = np.min(np.column_stack((s[:, 0], W - s[:, 0], s[:, 1], H - s[:, 1])), axis=1)
    assert len(s) == round(WINDOW.frame_sites * 2 * (W + H) / 100)
    assert (edge <= 1.0).all() and (edge > 0).all()
    more = seeds_of(FrostSim(WINDOW.replace(pane_sites=7), W, H, seed=3))
    assert len(more) == len(s) + 7


@pytest.mark.parametrize("per_100", [1.0, 3.0, 8.0])
def test_frame_spacing_matches_the_parameter_and_is_irregular(per_100):
    gaps = []
    for seed in range(5):
        sim = FrostSim(WINDOW.replace(frame_sites=per_100, pane_sites=0), 760, 1280, seed=seed)
        t = np.sort(arc_length(seeds_of(sim), 760, 1280))
        gaps.append(np.diff(t, append=t[0] + 2 * (760 + 1280)))
    g = np.concatenate(gaps)
    assert abs(g.mean() - 100 / per_100) < 0.01 * 100 / per_100
    # One site uniform in each equal stretch: gaps spread like a triangle on [0, 2s]
    # (coefficient of variation 1/sqrt(6) = 0.41); equal spacing gives 0, Poisson 1.
    assert 0.3 < g.std() / g.mean() < 0.52
    assert g.max() < 2 * 100 / per_100 * 1.02


def test_one_pool_for_the_whole_pane_placed_on_glass_near_the_ice():
    # (the window's placement without the fronds, which water_far 0 keeps)
    near = WINDOW.replace(water_far=0, vapour_var=0.0, frame_chill=0.0)
    for frame in (1.0, 10.0):
        sim = FrostSim(near.replace(frame_sites=frame), W, H, seed=2)
        sim.touch(150, 200)
        for _ in range(60):
            sim.step()
            assert len(sim.areas) == 1 and len(sim.water) <= WINDOW.humidity
        assert (sim.water_area == 0).all()
        x, y, ok = sim.pane.place(2000)
        assert ok.mean() > 0.9
        p = np.column_stack((x[ok], y[ok])).astype(np.float64)
        c = sim.crystals[sim.crystal_alive].astype(np.float64)
        d = np.hypot(p[:, None, 0] - c[None, :, 0], p[:, None, 1] - c[None, :, 1]).min(axis=1)
        assert (d >= WINDOW.hc / 2).all()
        # Within BAND cell rings of a cell some freezing area reaches: at most that far.
        assert (d <= (BAND + 1) * sim.grid.cell * np.sqrt(2) + WINDOW.hc).all()
        held = np.unique(sim.grid.keys(c[:, 0].astype(np.float32), c[:, 1].astype(np.float32)))
        assert not np.isin(sim.grid.keys(x[ok], y[ok]), held).any()


def test_colder_glass_grows_more_crystals():
    counts = []
    for temperature in (4.0, 10.0, 25.0):
        n = 0
        for seed in range(3):
            sim = FrostSim(WINDOW.replace(temperature=temperature), W, H, seed=seed)
            for _ in range(120):
                sim.step()
            n += int(sim.crystal_alive.sum())
        counts.append(n)
    assert counts[0] < counts[1] < counts[2]


def test_window_mode_is_deterministic_and_both_searches_agree():
    runs = []
    for mode, seed in (("candidate", 4), ("candidate", 4), ("grid9", 4), ("candidate", 5)):
        sim = FrostSim(WINDOW.replace(neighbor_search=mode), W, H, seed=seed)
        for t in range(150):
            if t == 100:
                sim.melt(150, 200, 40)
            sim.step()
        runs.append(sim)
    a = runs[0]
    for other in runs[1:3]:
        for name in ("crystals", "parents", "crystal_alive", "segments", "water"):
            assert getattr(a, name).tobytes() == getattr(other, name).tobytes(), name
    assert a.crystals.tobytes() != runs[3].crystals.tobytes()


# ---- wipe and regrow ------------------------------------------------------------------------

def in_path(px, py):
    return np.min([(px - x) ** 2 + (py - y) ** 2 for x, y in PATH], axis=0) < R * R


def path_cells(sim):
    """Cells wholly inside the wiped path (all four corners)."""
    g = sim.grid
    cx, cy = (a.ravel() for a in np.meshgrid(np.arange(g.cols), np.arange(g.rows)))
    x0, y0, x1, y1 = cx * g.cell, cy * g.cell, (cx + 1) * g.cell, (cy + 1) * g.cell
    whole = in_path(x0, y0) & in_path(x1, y0) & in_path(x0, y1) & in_path(x1, y1)
    return np.flatnonzero(whole)


def coverage(sim, cells):
    """Share of `cells` holding a live crystal."""
    c = sim.crystals[sim.crystal_alive]
    return np.isin(cells, sim.grid.keys(c[:, 0], c[:, 1])).mean()


def candidate_oracle(sim):
    """Each cell's sorted crystal ids, from every live crystal's disc against every cell."""
    g, r = sim.grid, sim.params.hc + CELL_MARGIN
    cx, cy = (a.ravel() for a in np.meshgrid(np.arange(g.cols), np.arange(g.rows)))
    live = np.flatnonzero(sim.crystal_alive)
    p = sim.crystals[live].astype(np.float64)
    gx = np.clip(p[:, 0, None], cx * g.cell, (cx + 1) * g.cell) - p[:, 0, None]
    gy = np.clip(p[:, 1, None], cy * g.cell, (cy + 1) * g.cell) - p[:, 1, None]
    hit = gx * gx + gy * gy < r * r
    return [sorted(live[hit[:, k]].tolist()) for k in range(g.size)]


# Ticks a wiped path gets to refreeze: 24 s at 25 ticks/s ("within tens of seconds");
# measured 30-200, so a generous bound, not a timing.
REGROW_TICKS = 600
MODES = {
    "window": (WINDOW, (), (W, H)),
    # The full pane: its wipe's edge is all old fronds (whose slots mostly face away).
    "window-760x1280": (WINDOW, (), (760, 1280)),
    "fern-grow": (Params.preset("fern"), ((150.0, 200.0),), (W, H)),
    "c-2-grow": (Params.preset("c-2", grow=True), ((150.0, 200.0),), (W, H)),
}


@pytest.mark.parametrize("mode", [pytest.param(m, marks=pytest.mark.validation)
                                  if m == "window-760x1280" else m for m in MODES])
def test_a_wiped_path_is_clear_then_refreezes_from_its_edges(mode):
    params, touches, size = MODES[mode]
    sim = FrostSim(params, *size, seed=1)
    for x, y in touches:
        sim.touch(x, y)
    cells = path_cells(sim)
    cover: list[float] = []
    for _ in range(2500):  # to the frosted end (app/bench/measures.py), or full coverage
        sim.step()
        cover.append(coverage(sim, np.arange(sim.grid.size)))
        if cover[-1] >= 0.95 or frosted_end(cover) is not None:
            break
    for _ in range(300):  # a while frosted: the ice's open slots fill up
        sim.step()
    before = coverage(sim, cells)
    # (fronds leave clear glass between them by design: about 60 % of cells hold ice)
    assert before > (0.5 if params.water_far else 0.8)
    for x, y in PATH:
        sim.melt(x, y, R)
        assert len(sim.water) <= params.humidity
    c = sim.crystals[sim.crystal_alive]
    assert not in_path(c[:, 0], c[:, 1]).any()
    lists = [sorted(sim.candidates.items[k, :sim.candidates.count[k]].tolist())
             for k in range(sim.grid.size)]
    assert lists == candidate_oracle(sim)
    for _tick in range(REGROW_TICKS):
        new = sim.step().crystals
        p = sim.parents[new]
        assert (p >= 0).all()
        assert sim.crystal_alive[p].all()
        d = np.hypot(*(sim.crystals[new] - sim.crystals[p]).T.astype(np.float64))
        assert (d <= params.hc * (1 + 1e-5)).all()
        if coverage(sim, cells) >= 0.9 * before:
            break
    assert coverage(sim, cells) >= 0.9 * before, f"path at {coverage(sim, cells):.2f} of {before:.2f}"


def test_a_wipe_opens_all_six_slots_of_the_ice_at_its_edge():
    # (the window without the fronds: with them the edge keeps its slots, test_fronds.py)
    old = WINDOW.replace(tip_hits=3, side_hits=6, **{k: getattr(Params, k) for k in FROND_RULES})
    sim = FrostSim(old, W, H, seed=2)
    for _ in range(500):  # the pane is frosted
        sim.step()
    seeds_before = sim.growth.seed.view().copy()
    reach = R + sim.ice.longest_link + 1.0
    sim.melt(30.0, 200.0, R)
    c = sim.crystals.astype(np.float64)
    d = np.hypot(c[:, 0] - 30.0, c[:, 1] - 200.0)
    edge = sim.crystal_alive & (d < reach)
    assert edge.sum() > 5
    opened = sim.growth.seed.view()
    assert opened[edge].all()
    assert (opened[~edge] == seeds_before[~edge]).all()


def test_the_app_opens_window_mode_and_its_keys_rebuild_it():
    from app.cli.parser import build_parser
    from app.cli.shared_options import params_from
    from app.keys import BINDINGS
    from sim import tuning

    parse = build_parser().parse_args
    assert params_from(parse(["--window-frost"])) == WINDOW
    assert params_from(parse(["--window-frost", "--temperature", "20"])).temperature == 20.0
    # on top of a Table 1 preset: its numbers (Table 1's c-2: D 7, hc 7, humidity 3000) and
    # hit counters (1), window mode, and the grains window mode needs (the help says so)
    c2 = params_from(parse(["--window-frost", "--preset", "c-2"]))
    assert (c2.D, c2.hc, c2.humidity, c2.tip_hits) == (7.0, 7.0, 3000, 1)
    assert c2.window_frost and c2.grains
    with pytest.raises(ValueError, match="needs grains"):  # unless the user turns them off
        params_from(parse(["--window-frost", "--preset", "c-2", "--grains", "off"]))
    keys = {b.keys[0]: b for b in BINDINGS}
    assert (keys["W"].action, keys["W"].arg) == ("preset", "window")
    colder = tuning.shifted(WINDOW, *keys["T"].arg)
    assert colder.temperature > WINDOW.temperature
    assert tuning.shifted(colder, *keys["Y"].arg) == WINDOW
    # back to fern (key 0) from a tuned window: window mode and its tunables go
    assert tuning.preset(colder, "fern") == Params.preset("fern")
    assert tuning.preset(Params.preset("fern"), "window") == WINDOW


def test_the_band_reaches_band_rings_beyond_the_candidate_cells_and_skips_held_cells():
    # A 140 px pane (10 x 10 cells of 14 px) with one touch at (70, 70): its disc lists it
    # in the 2 x 2 cells around that corner (rows, cols 4-5). BAND = 3 rings beyond them is
    # rows and cols 1-8; the outer ring (4 away) is not in it, nor the touch's own cell
    # (5, 5). The pool is DENSITY a band cell: int(2.5 x 63) = 157, at most humidity.
    p = Params.preset("window", frame_sites=0, pane_sites=0, water_far=0, vapour_var=0.0)
    sim = FrostSim(p, 140, 140, seed=0)
    sim.touch(70.0, 70.0)
    assert sim.grid.cell == 14 and BAND == 3
    assert np.flatnonzero(sim.candidates.count).tolist() == [44, 45, 54, 55]
    expected = {r * 10 + c for r in range(1, 9) for c in range(1, 9)} - {55}
    assert set(sim.pane.band().tolist()) == expected
    assert sim.pane.pool(3000) == 157 and sim.pane.pool(100) == 100
