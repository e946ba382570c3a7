"""The tuning panel's widgets (Dear ImGui): a slider, toggle or list for every parameter of
`Params`, grouped, with its validated range and its one-line help as the tooltip; the
preset list, the backdrop, the window's actions and parameter sets saved and loaded.

Every change goes through the window's actions (`Actions.run`), the path the keys take:
the simulation thread applies it at a tick, the session records it, the HUD says it. A
slider commits when it is let go (or its typed value entered), not on every pixel of a
drag. What a widget offers (`Spec`) and when it is off (`why_off`) are plain functions of
`Params`' fields, testable without a window.
"""

from __future__ import annotations

import dataclasses
import functools
import statistics
from dataclasses import dataclass
from typing import Any

from imgui_bundle import imgui

from app.backdrops import BACKDROPS
from sim import Params, all_presets
from sim.params import GRAIN_RULES, WINDOW_RULES

# Every parameter, in groups (a test checks that each is in exactly one).
GROUPS: dict[str, tuple[str, ...]] = {
    "the paper's (Table 1 and walkers)": (
        "hc", "D", "humidity", "water_budget", "step", "active_radius", "neighbor_search",
        "replenish", "grow", "touch_water"),
    "fern rules": ("grains", "drift", "tip_hits", "side_hits", "side_gap", "long_jumps",
                   "launch", "order_hits", "max_order"),
    "window (the frosted pane)": ("window_frost", "temperature", "frame_sites", "pane_sites",
                                  "water_far", "near_water", "vapour_var", "frame_chill"),
    "rendering": ("look", "bump", "max_height", "feature_width", "feature_height",
                  "grid_spacing"),
}
# The switches other parameters need while they are away from their defaults.
LEANING = {"grains": (*GRAIN_RULES, "window_frost"), "window_frost": WINDOW_RULES}
# Buttons: (label, action of the window's dispatch table).
BUTTONS = (("Pause", "pause"), ("One tick", "single_step"), ("Clear", "clear"),
           ("Screenshot", "screenshot"), ("Record", "record"), ("Export maps", "export_maps"))
# A range wider than this ratio gets a logarithmic slider (humidity spans 1 to 100 000).
LOG_RATIO = 100.0
# An open lower end (hc > 0) starts the slider this fraction of the range above it.
OPEN_END = 1e-3
DEFAULT_SET = "frost-params.json"
TOOLTIP_WIDTH = 360  # px
COSTS_KEPT = 240  # the panel's redraw costs kept for the median


@dataclass(frozen=True)
class Spec:
    """What a parameter's widget offers: 'slider' (with ends, a log scale and an int or
    float value), 'toggle' or 'list' (of choices)."""

    kind: str
    lo: float = 0.0
    hi: float = 0.0
    log: bool = False
    whole: bool = False
    choices: tuple = ()


def spec(f: dataclasses.Field) -> Spec:
    """The widget for field `f`, its ends inside its validated range."""
    meta = f.metadata
    if meta["choices"] is not None:
        kind = "toggle" if type(f.default) is bool else "list"
        return Spec(kind, choices=tuple(meta["choices"]))
    lo, hi = meta["lo"], meta["hi"]
    if meta["lo_open"]:
        lo = lo + OPEN_END * (hi - lo)
    whole = isinstance(f.default, int)
    return Spec("slider", lo, hi, hi > LOG_RATIO * max(lo, 1.0), whole)


def why_off(params: Params, name: str) -> str | None:
    """Why parameter `name` cannot change now (None: it can), as Params would refuse it."""
    if name == "grid_spacing":
        return "fixed for a session (the renderer's height grid): start with --grid-spacing"
    if name in GRAIN_RULES and not params.grains:
        return "needs grains on"
    if name in WINDOW_RULES and not params.window_frost:
        return "needs window_frost on"
    if name in ("near_water", "vapour_var") and not params.water_far:
        return "needs water_far > 0"
    if name == "window_frost" and not params.grains:
        return "needs grains on"
    users = [n for n in LEANING.get(name, ()) if getattr(params, n) != getattr(Params, n)]
    if getattr(params, name) is True and users:
        return f"{', '.join(users)} need(s) it: pick a preset to turn it off"
    return None


@functools.cache
def preset_params(name: str) -> Params:
    """Params.preset(name), made once: the panel asks for it per widget and frame."""
    return Params.preset(name)


def tooltip(f: dataclasses.Field, preset: str) -> str:
    """The field's one-line help, its range and the preset's value."""
    meta, spec = f.metadata, SPECS[f.name]
    if spec.kind == "slider":
        left = "(" if meta["lo_open"] else "["
        extent = f"range {left}{meta['lo']:g}, {meta['hi']:g}]"
    elif spec.kind == "toggle":
        extent = "on or off"
    else:
        extent = "one of " + ", ".join(map(str, spec.choices))
    value = getattr(preset_params(preset), f.name)
    shown = ("on" if value else "off") if spec.kind == "toggle" else value
    return f"{meta['doc']}\n{extent}; preset {preset}: {shown}"


FIELDS = {f.name: f for f in dataclasses.fields(Params)}
SPECS = {name: spec(f) for name, f in FIELDS.items()}


class TuningPanel:
    """Draws the widgets each frame (between imgui.new_frame and imgui.render). `actions`
    is the window's Actions: `params` (what was asked for last), `preset` (the last preset
    chosen), `backdrop()` and `run(action, arg)`; `costs` are the times of its redraws."""

    def __init__(self, actions):
        self.actions = actions
        self.editing: dict[str, Any] = {}  # a slider's value while it is dragged
        self.path = DEFAULT_SET
        self.costs: list[float] = []  # ms a redraw, the last COSTS_KEPT
        self.rects: dict[str, tuple[float, float, float, float]] = {}  # widget boxes, window px

    def draw(self) -> None:
        self._presets()
        self._buttons()
        self._param_sets()
        params = self.actions.params
        for title, names in GROUPS.items():
            if imgui.collapsing_header(title, imgui.TreeNodeFlags_.default_open):
                for name in names:
                    self._param(params, name)
        if self.costs:
            imgui.text_disabled(f"panel {statistics.median(self.costs):.2f} ms a redraw (median)")

    def add_cost(self, ms: float) -> None:
        self.costs = [*self.costs[-COSTS_KEPT + 1:], ms]

    def _remember(self, name: str) -> None:
        """Where the last widget lies (window px), for the log and the end-to-end test."""
        (x0, y0), (x1, y1) = imgui.get_item_rect_min(), imgui.get_item_rect_max()
        self.rects[name] = (x0, y0, x1 - x0, y1 - y0)

    # ---- presets, backdrop, buttons, files -------------------------------------------

    def _presets(self) -> None:
        chosen = self._combo("preset", self.actions.preset, tuple(all_presets()))
        if chosen is not None:
            self.actions.run("preset", chosen)
        own = getattr(self.actions, "own_backdrop", None)  # a --background file stays listed
        backdrops = tuple(b for b in dict.fromkeys((*BACKDROPS, own, self.actions.backdrop())) if b)
        chosen = self._combo("backdrop", self.actions.backdrop(), backdrops)
        if chosen is not None:
            self.actions.run("set_backdrop", chosen)

    def _combo(self, label: str, current, choices: tuple):
        """A list of `choices`; the one picked this frame, or None."""
        picked = None
        if imgui.begin_combo(label, str(current)):
            for choice in choices:
                if imgui.selectable(str(choice), choice == current)[0] and choice != current:
                    picked = choice
            imgui.end_combo()
        self._remember(label)
        return picked

    def _buttons(self) -> None:
        for i, (label, action) in enumerate(BUTTONS):
            if i % 3:
                imgui.same_line()
            if imgui.button(label):
                self.actions.run(action)
            self._remember(action)

    def _param_sets(self) -> None:
        # A click selects the whole name, so typing replaces it.
        self.path = imgui.input_text("file", self.path, imgui.InputTextFlags_.auto_select_all)[1]
        self._remember("file")
        for label, action in (("Save set", "save_params"), ("Load set", "load_params")):
            if label == "Load set":
                imgui.same_line()
            if imgui.button(label):
                self.actions.run(action, self.path)
            self._remember(action)

    # ---- one parameter ---------------------------------------------------------------

    def _param(self, params: Params, name: str) -> None:
        f, off = FIELDS[name], why_off(params, name)
        imgui.begin_disabled(off is not None)
        value = self._widget(f, self.editing.get(name, getattr(params, name)))
        self._remember(name)
        imgui.end_disabled()
        if imgui.is_item_hovered(imgui.HoveredFlags_.allow_when_disabled):
            _wrapped_tooltip(tooltip(f, self.actions.preset) + (f"\n(off: {off})" if off else ""))
        self._commit(name, value)
        self._reset_button(params, name, off)

    def _widget(self, f: dataclasses.Field, value):
        """The widget for `f` showing `value`; (changed, value)."""
        spec = SPECS[f.name]
        if spec.kind == "toggle":
            return imgui.checkbox(f.name, value)
        if spec.kind == "list":
            picked = self._combo(f.name, value, spec.choices)
            return picked is not None, value if picked is None else picked
        flags = imgui.SliderFlags_.always_clamp | (imgui.SliderFlags_.logarithmic if spec.log else 0)
        if spec.whole:
            return imgui.slider_int(f.name, value, int(spec.lo), int(spec.hi), flags=flags)
        return imgui.slider_float(f.name, value, spec.lo, spec.hi, "%.3g", flags)

    def _commit(self, name: str, result) -> None:
        """A toggle or a list at once; a slider's value kept while dragged, sent when it
        is let go (or a typed value entered)."""
        changed, value = result
        if SPECS[name].kind != "slider":
            if changed:
                self.actions.run("set_param", (name, value))
            return
        if changed:
            self.editing[name] = _rounded(value)
        if imgui.is_item_deactivated():
            if imgui.is_item_deactivated_after_edit() and name in self.editing:
                self.actions.run("set_param", (name, self.editing[name]))
            self.editing.pop(name, None)

    def _reset_button(self, params: Params, name: str, off: str | None) -> None:
        want = getattr(preset_params(self.actions.preset), name)
        imgui.same_line()
        imgui.begin_disabled(off is not None or getattr(params, name) == want)
        if imgui.small_button(f"R##{name}"):
            self.actions.run("set_param", (name, want))
        imgui.end_disabled()
        if imgui.is_item_hovered(imgui.HoveredFlags_.allow_when_disabled):
            imgui.set_tooltip(f"reset {name} to preset {self.actions.preset}'s {want}")


def _wrapped_tooltip(text: str) -> None:
    """A tooltip no wider than the panel, so it stays beside the phone."""
    imgui.begin_tooltip()
    imgui.push_text_wrap_pos(TOOLTIP_WIDTH)
    imgui.text_unformatted(text)
    imgui.pop_text_wrap_pos()
    imgui.end_tooltip()


def _rounded(value):
    """A float slider's value to 4 significant digits (what it shows is 3): the session
    records a readable number, not 0.30000001192."""
    return value if isinstance(value, int) else float(f"{value:.4g}")

