"""Which pane a run's water belongs to: none (touch mode), the pane of window mode
(sim/rules/window_mode.py), or its open glass under the frond rules (sim/rules/openglass.py)."""

from __future__ import annotations

import numpy as np

from ..params import Params
from .openglass import OpenGlass
from .window_mode import NoPane, Pane


def make_pane(params: Params, rng: np.random.Generator, index, ice,
              tries_at_once: bool) -> NoPane | Pane:
    """The pane of window mode (`window_frost`; open glass with `water_far`), else none."""
    if params.water_far:  # (frond rules 2 and 3)
        return OpenGlass(params, rng, index, ice, tries_at_once)
    return Pane(params, rng, index, ice) if params.window_frost else NoPane()
