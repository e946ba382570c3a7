"""The frost simulation: numpy only, no GL (Im, Choi, Lee and Kim 2018, Sec. 3.3-3.5)."""

from .frost import Added, FrostSim, Melted, upsample, walk_displacements
from .params import PRESETS, Params

__all__ = ["Added", "FrostSim", "Melted", "PRESETS", "Params", "upsample", "walk_displacements"]
