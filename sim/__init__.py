"""The frost simulation: numpy only, no GL (Im, Choi, Lee and Kim 2018, Sec. 3.3-3.5)."""

from .core.frost import Added, FrostSim, Melted, upsample, walk_displacements
from .params import EXTRA_PRESETS, PRESETS, Params, all_presets, preset_name

__all__ = ["Added", "FrostSim", "Melted", "EXTRA_PRESETS", "PRESETS", "Params", "all_presets",
           "preset_name", "upsample", "walk_displacements"]
