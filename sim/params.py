"""Every tunable of the simulation and its geometry, validated in one place.

Lengths are in phone-screen pixels (760x1280, origin top-left, y down); time is
in ticks (the app runs 25 per second). docs/method.md says where each comes from.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

NEIGHBOR_SEARCHES = ("candidate", "grid9")
# How the ice is drawn (sim.look.material): the paper's per-segment features, or glass ridges.
LOOKS = ("paper", "glass")
# Parameters that only mean something with grains on.
GRAIN_RULES = ("drift", "tip_hits", "side_hits", "side_gap", "order_hits", "max_order")
# The fern rules: off (at their defaults) in the paper's look.
FERN_RULES = ("grains", *GRAIN_RULES, "long_jumps", "launch")
# Parameters that only mean something in window mode (sim/rules/window_mode.py).
WINDOW_RULES = ("frame_sites", "pane_sites", "temperature", "water_far", "near_water",
                "vapour_var", "frame_chill")
# The frond rules (docs/method.md, section 8): off at their defaults; the window preset
# turns them on.
FROND_RULES = ("order_hits", "max_order", "water_far", "near_water", "vapour_var", "frame_chill")
# Bounds on the work one new crystal makes (see Params.__post_init__): at most this many
# upsample particles on a link of length hc (Table 1: at most 10, a-1), and hc at most this
# many grid spacings (Table 1: 2.5). Beyond them a tick of fast growth took seconds.
MAX_UPSAMPLE = 16
MAX_HC_PER_SPACING = 12
MIN_HC = 1.0  # px; see hc


def _p(default: Any, doc: str, lo: float | None = None, hi: float | None = None,
       lo_open: bool = False, choices: tuple | None = None) -> Any:
    """A dataclass field carrying its one-line description and allowed range."""
    meta = {"doc": doc, "lo": lo, "hi": hi, "lo_open": lo_open, "choices": choices}
    return field(default=default, metadata=meta)


@dataclass(frozen=True)
class Params:
    """Simulation and geometry parameters. Construct with keywords; invalid values raise."""

    # hc sizes the hash grid (cells of 2 hc, Eq. 1): its cells grow as 1 / hc^2. At the
    # floor, 1 px, they are 243 200 and a touch's first ten ticks peaked at 47 MB; 0.25
    # at 190 MB, and 0.03 was reported at 11 GB and 39 s for one tick. A crystal under a
    # pixel has no look on the screen anyway.
    hc: float = _p(7.0, "hc: radius of a crystal's freezing area, px (Table 1: 3-10)",
                   MIN_HC, 16.0)
    D: float = _p(7.0, "D: spacing of upsample particles along a skeleton link, px (Table 1: 1-10)",
                  0.0, 64.0, lo_open=True)
    humidity: int = _p(3000, "humidity: water particles per active area (Table 1: 500-5000)",
                       1, 100_000)
    # Not in the paper: its touches each bring `humidity` walkers, so a drag that plants a
    # touch every few px would bring hundreds of thousands. The whole screen's walkers are
    # capped here; a touch beyond it takes a fair share from the areas holding the most.
    # 10 000 is twice the largest pool of Table 1 and keeps a busy tick to a few ms.
    water_budget: int = _p(10000, "water_budget: most water particles on the whole screen, all "
                                  "active areas together", 1, 30_000)
    # Not in the paper. 5 px (below hc = 7, so walkers never tunnel through a freezing
    # area; Table 1 presets with a smaller hc clamp it to hc). Measured at c-2 over seeds
    # 0-9 (`step` 3 / 5 / 7): first crystal after a median 17.5 / 9.5 / 5 ticks (worst 43 /
    # 24 / 16), 90 % of the water frozen after 117 / 85 / 73 ticks. 5 shows frost within a
    # second on every seed and still spreads visibly outward for about three seconds.
    step: float = _p(5.0, "step: longest random-walk step r of Eq. 2, px (at most hc)",
                     0.0, 64.0, lo_open=True)
    # Not in the paper. 200 px: at c-2 the walker density per freezing area
    # (lambda = humidity*hc^2/active_radius^2 ~ 3.7) freezes a visible patch within a
    # second and spreads outward over seconds, while a touch still frosts a palm-sized
    # region of the phone; 260 px took twice as long to show 100 crystals.
    active_radius: float = _p(200.0, "active_radius: radius of the active area around a seed, px",
                              0.0, 4000.0, lo_open=True)
    bump: float = _p(1.0, "bump: height a geometry-grid vertex gains per nearby particle, px",
                     0.0, 100.0)
    max_height: float = _p(6.0, "max_height: cap on the bumpy surface's height, px",
                           0.0, 1000.0, lo_open=True)
    grid_spacing: int = _p(4, "grid_spacing: geometry-grid vertex spacing, px", 1, 64)
    feature_width: float = _p(1.5, "feature_width: side-point offset of a sharp feature, "
                                   "x segment length (Sec. 3.5.1)", 0.0, 10.0)
    feature_height: float = _p(0.5, "feature_height: midpoint elevation of a sharp feature, "
                                    "x segment length (Sec. 3.5.1)", 0.0, 10.0)
    look: str = _p("paper", "look: 'paper' (Fig. 6 features per segment, the paper's shading) or "
                            "'glass' (a tapered ridge per link, clear-to-white film, glints, the "
                            "view refracted; docs/method.md)", choices=LOOKS)
    neighbor_search: str = _p("candidate", "neighbor_search: 'candidate' (the paper's freezing "
                                           "candidate areas) or 'grid9' (Fig. 9's baseline)",
                              choices=NEIGHBOR_SEARCHES)
    replenish: bool = _p(False, "replenish: keep each area's water at humidity (frozen water "
                                "is replaced) instead of spending it", choices=(False, True))
    # Beyond the paper (its stated limit): an area that follows its ice can frost the screen.
    grow: bool = _p(False, "grow: active areas widen with their ice and water is placed near the "
                           "ice front, so frost keeps spreading (implies replenish)",
                    choices=(False, True))

    # Beyond the paper: "fern" growth (docs/method.md, section 6). All off by default, so the
    # simulation is the paper's unless a preset or the user turns them on.
    grains: bool = _p(False, "grains: six-fold growth: each seed draws an orientation and a new "
                             "crystal sits one hc along the nearest of its parent's axes (fern rule 1)",
                      choices=(False, True))
    drift: float = _p(0.0, "drift: spread of the turn of a child's axes from its link, degrees "
                           "(with grains; fronds curve)", 0.0, 30.0)
    tip_hits: int = _p(1, "tip_hits: walker hits a crystal's straight-on slot takes to grow, hits "
                          "(1: every hit, the paper; with grains; fern rule 2)", 1, 10_000)
    side_hits: int = _p(1, "side_hits: walker hits a side slot (+-60 deg) takes to grow, hits "
                           "(with grains)", 1, 10_000)
    side_gap: int = _p(1, "side_gap: least links between side branches on one side of a stem, "
                          "links (1: any; with grains)", 1, 16)
    long_jumps: bool = _p(False, "long_jumps: a walker far from ice jumps to a random point of its "
                                 "clearance circle, exact for Brownian motion (fern rule 3)",
                          choices=(False, True))
    launch: float = _p(0.0, "launch: new and returning water starts on a circle this many px beyond "
                            "its area's farthest ice (0: anywhere in the area; fern rule 4)",
                       0.0, 4000.0)

    # Beyond the paper: a touch brings water to its own seed (docs/method.md, 5.3). Off in
    # Table 1's presets: the paper's touch only tops its area's pool up.
    touch_water: int = _p(0, "touch_water: walkers a touch into an area that already holds water "
                             "moves from that area's pool onto the glass within 2 hc of its "
                             "seed, walkers (0: none, the paper)", 0, 1000)

    # Beyond the paper: the frosted window (sim/rules/window_mode.py). Off by default.
    window_frost: bool = _p(False, "window_frost: frost nucleates on the screen's border and on a few "
                                   "pane sites and grows over the whole pane from one pool of "
                                   "humidity walkers (needs grains)", choices=(False, True))
    frame_sites: float = _p(3.0, "frame_sites: nucleation sites along the border, per 100 px of "
                                 "border (with window_frost)", 0.0, 50.0)
    pane_sites: int = _p(4, "pane_sites: scratch and dust sites on the glass, sites (with "
                            "window_frost)", 0, 1000)
    temperature: float = _p(10.0, "temperature: degrees C below freezing; colder needs fewer hits "
                                  "per slot, so frost grows faster and denser (with window_frost)",
                            0.0, 40.0, lo_open=True)

    # Beyond the paper: fronds (docs/method.md, section 8; sim/rules/fronds.py). Off by default.
    order_hits: float = _p(1.0, "order_hits: a slot needs its hits x order_hits^order, order "
                                "counting side branchings from the stem (1: every order alike; "
                                "with grains; frond rule 1)", 1.0, 10.0)
    max_order: int = _p(0, "max_order: crystals of this branch order or more grow no side "
                           "branches (0: no limit; with grains)", 0, 16)
    water_far: int = _p(0, "water_far: window water lands on glass at least this many cell rings "
                           "from every candidate cell (0: within 3 rings of the ice; with "
                           "window_frost; frond rule 2)", 0, 8)
    near_water: float = _p(0.2, "near_water: weight of a nearer free cell against a far one "
                                "where window water lands (with water_far)", 0.0, 1.0)
    vapour_var: float = _p(0.0, "vapour_var: variance of the log of a smooth random humidity "
                                "field weighting where far water lands (0: even; with "
                                "water_far; frond rule 3)", 0.0, 4.0)
    frame_chill: float = _p(0.0, "frame_chill: hits divided by 1 + frame_chill x e^(-d / 150 px), "
                                 "d the distance to the frame: a denser band along it (with "
                                 "window_frost; frond rule 4)", 0.0, 20.0)

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            _validate(f, getattr(self, f.name))
        if self.step > self.hc:
            raise ValueError(f"step={self.step!r} must not exceed hc={self.hc!r}: "
                             "walkers would tunnel through freezing areas")
        for name in GRAIN_RULES:
            if not self.grains and getattr(self, name) != getattr(Params, name):
                raise ValueError(f"{name}={getattr(self, name)!r} needs grains=True")
        for name in WINDOW_RULES:
            if not self.window_frost and getattr(self, name) != getattr(Params, name):
                raise ValueError(f"{name}={getattr(self, name)!r} needs window_frost=True")
        for name in ("near_water", "vapour_var"):
            if not self.water_far and getattr(self, name) != getattr(Params, name):
                raise ValueError(f"{name}={getattr(self, name)!r} needs water_far > 0")
        if self.window_frost and not self.grains:
            raise ValueError("window_frost=True needs grains=True: the temperature acts "
                             "through the hit counters")
        # Work per new crystal: hc / D upsample particles on its link, and each particle
        # raises (2 hc / grid_spacing + 3)^2 grid vertices. Table 1 stays far inside both.
        if self.hc > self.D * MAX_UPSAMPLE:
            raise ValueError(f"D={self.D!r} is below hc/{MAX_UPSAMPLE}={self.hc / MAX_UPSAMPLE:g}: "
                             f"a link would hold more than {MAX_UPSAMPLE} upsample particles")
        if self.grid_spacing * MAX_HC_PER_SPACING < self.hc:
            raise ValueError(f"grid_spacing={self.grid_spacing!r} is below hc/{MAX_HC_PER_SPACING}: "
                             f"each particle would raise too many grid vertices (hc={self.hc!r})")

    def replace(self, **changes: Any) -> Params:
        """A copy with `changes` applied (validated); unknown names raise ValueError."""
        unknown = set(changes) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise ValueError(f"unknown parameter(s): {', '.join(map(repr, sorted(unknown)))}")
        return dataclasses.replace(self, **changes)

    @classmethod
    def preset(cls, name: str, **overrides: Any) -> Params:
        """Table 1's setting `name` ('a-1' ... 'c-3') or an extra look ('fern', 'window'), with
        optional overrides."""
        table = all_presets()
        if name not in table:
            raise ValueError(f"unknown preset {name!r}; choose one of {', '.join(table)}")
        values = dict(table[name])
        # Table 1 leaves step open; keep the default where it fits, else clamp to hc.
        values.setdefault("step", min(cls.step, values["hc"]))
        values.update(overrides)
        return cls(**values)

    @staticmethod
    def describe() -> list[tuple[str, Any, str]]:
        """(name, default, one-line description) of every parameter, for help texts."""
        return [(f.name, f.default, f.metadata["doc"]) for f in dataclasses.fields(Params)]

    def as_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def _validate(f: dataclasses.Field, value: Any) -> None:
    meta = f.metadata
    name = f.name
    if meta["choices"] is not None:
        if value not in meta["choices"] or type(value) is not type(meta["choices"][0]):
            raise ValueError(f"{name}={value!r} is not one of {meta['choices']}")
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name}={value!r} must be a number")
    # A whole-number parameter takes an int, not 4.0: it sizes arrays and counts particles.
    if isinstance(f.default, int) and not isinstance(value, int):
        raise ValueError(f"{name}={value!r} must be a whole number")
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{name}={value!r} must be finite")
    lo, hi = meta["lo"], meta["hi"]
    below = value <= lo if meta["lo_open"] else value < lo
    if below or value > hi:
        left = "(" if meta["lo_open"] else "["
        raise ValueError(f"{name}={value!r} is out of range {left}{lo}, {hi}]")


# Table 1 of the paper: D and hc in px, humidity in water particles per active area.
PRESETS: dict[str, dict[str, Any]] = {
    "a-1": {"D": 1.0, "hc": 10.0, "humidity": 3000},
    "a-2": {"D": 2.5, "hc": 10.0, "humidity": 3000},
    "a-3": {"D": 5.0, "hc": 10.0, "humidity": 3000},
    "b-1": {"D": 3.0, "hc": 3.0, "humidity": 3000},
    "b-2": {"D": 7.0, "hc": 7.0, "humidity": 3000},
    "b-3": {"D": 10.0, "hc": 10.0, "humidity": 3000},
    "c-1": {"D": 7.0, "hc": 7.0, "humidity": 500},
    "c-2": {"D": 7.0, "hc": 7.0, "humidity": 3000},
    "c-3": {"D": 7.0, "hc": 7.0, "humidity": 5000},
}

# Looks beyond the paper, selectable by name like Table 1's (which PRESETS alone lists).
# "fern": window frost's fronds (docs/method.md, section 6); values tuned with `frost bench
# sim --section fern` (docs/benchmarks.md has the figures).
EXTRA_PRESETS: dict[str, dict[str, Any]] = {
    # Rendered with narrower, taller sharp features on links split in three (D 2.5): glossy
    # stems with a fine texture; the paper's 1.5 made every link a hairy perpendicular rung.
    "fern": {"D": 2.5, "hc": 7.0, "humidity": 3000, "feature_width": 1.0, "feature_height": 0.8,
             "grains": True, "drift": 3.0,
             "tip_hits": 5, "side_hits": 10, "side_gap": 2, "long_jumps": True,
             "launch": 30.0, "grow": True, "water_budget": 6000, "touch_water": 48,
             "look": "glass"},
}
# "window": fern frost nucleating on the frame, grown as fronds (docs/looks.md, the frosted window;
# docs/method.md, section 8). The frond rules at the values a prototype of them found:
# hit counts 1 / 3 at -10 C, x 3 per branch order, no side branches from order 3; water on
# glass 2 cell rings from the ice, a humidity field of log-variance 1, a frame chill of 3.
# The pool of 4 000 follows the temperature (x 2 at -20 C): the budget leaves it room.
# Measured with `frost bench sim --section window`.
EXTRA_PRESETS["window"] = {**EXTRA_PRESETS["fern"], "window_frost": True,
                           "tip_hits": 1, "side_hits": 3, "order_hits": 3.0, "max_order": 3,
                           "water_far": 2, "vapour_var": 1.0, "frame_chill": 3.0,
                           "humidity": 4000, "water_budget": 10000}


def all_presets() -> dict[str, dict[str, Any]]:
    """Table 1's presets, then the extra looks: every name `Params.preset` accepts."""
    return {**PRESETS, **EXTRA_PRESETS}


def preset_name(params: Params) -> str:
    """The preset(s) `params` follows ('b-2/c-2' for Table 1's twins), or 'custom': the
    preset's D, hc and humidity and its fern rules (off for Table 1). Growth mode, the
    budget and the look (bump, features) may differ: they have keys of their own."""
    names = []
    for name in all_presets():
        want = Params.preset(name)
        fields = ("D", "hc", "humidity", *FERN_RULES, "window_frost")
        if all(getattr(params, f) == getattr(want, f) for f in fields):
            names.append(name)
    return "/".join(names) or "custom"
