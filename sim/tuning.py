"""What the tuning keys do to the parameters: pure functions, no window needed. The
window's keys and the scripted scribbles (app/bench/scribble.py) both use them, so a benchmark's
key presses are a user's.

Each returns a new, validated Params or raises ValueError saying why not.
"""

from __future__ import annotations

from dataclasses import fields

from .params import EXTRA_PRESETS, WINDOW_RULES, Params, all_presets

# Parameter steps a key makes: humidity scales (it spans 500 to 30000), lengths move in
# px, the window's temperature in degrees C.
HUMIDITY_FACTOR = 1.5
LENGTH_STEP = 0.5
BUMP_STEP = 0.25
TEMPERATURE_STEP = 2.0


def changed(params: Params, name: str, value) -> Params:
    """`params` with `name` set to `value`; lowering hc below step takes step down with it
    (walkers must not step over a freezing area), anything else invalid raises."""
    changes = {name: value}
    if name == "hc" and params.step > value > 0:
        changes["step"] = value
    return params.replace(**changes)


def scaled(params: Params, name: str, factor: float) -> Params:
    """A whole-number parameter (humidity) times `factor`, at least 1."""
    return changed(params, name, max(1, round(getattr(params, name) * factor)))


def shifted(params: Params, name: str, delta: float) -> Params:
    return changed(params, name, round(getattr(params, name) + delta, 6))


def toggled(params: Params, name: str) -> Params:
    """A boolean parameter (grow) switched."""
    return changed(params, name, not getattr(params, name))


def cycled(params: Params, name: str) -> Params:
    """A parameter with a list of choices (look) set to its next choice."""
    choices = next(f.metadata["choices"] for f in fields(Params) if f.name == name)
    return changed(params, name, choices[(choices.index(getattr(params, name)) + 1) % len(choices)])


def preset(params: Params, name: str) -> Params:
    """Preset `name` (Table 1's or 'fern'); the parameters it does not set keep their
    values, except that entering or leaving a look beyond the paper (grains on) also
    resets what those looks set (the fern rules, growth mode, the budget): one key
    brings back the paper's look."""
    reset = set(all_presets()[name]) | {"step"}
    if params.grains or name in EXTRA_PRESETS:
        reset = reset.union(*EXTRA_PRESETS.values())
    if not all_presets()[name].get("window_frost"):
        reset |= set(WINDOW_RULES)  # they need window mode, which this preset leaves
    keep = {k: v for k, v in params.as_dict().items() if k not in reset}
    return Params.preset(name, **keep)


def differences(old: Params, new: Params) -> dict:
    return {k: v for k, v in new.as_dict().items() if getattr(old, k) != v}
