"""How the ice looks: the Phong terms and the thickness-to-opacity law.

Shared data, GL-free: the renderer hands these to its shaders, and the
exported alpha map (sim.look.maps) follows the same law, so the two always agree.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

# The ice shader's compile-time variant for each look (Params.look; shaders/ice.frag).
LOOK_DEFINES = MappingProxyType({
    "paper": (),
    "glass": ("FILM", "SCATTER", "SPARKLE", "REFRACT"),
})
# The feature pass's variant (shaders/feature.*): the glass look's ridges anti-alias their
# edges (EDGE_AA: coverage and mean height within half a px of an edge; sim.look.maps does the
# same arithmetic); the paper's features are drawn as the paper's frames were, pixel for pixel.
FEATURE_DEFINES = MappingProxyType({"paper": (), "glass": ("EDGE_AA",)})


# What the renderer (and the phone page's port of it) draws with, shared here so that the
# server can name it without GL.
MAX_DEPTH = 64.0  # px; features higher than this share the nearest depth
# Side of a screen tile of the ice pass, px. Smaller tiles hug the ice closer but cost
# more instances (3.8k at most at 16 px, a few kB).
TILE = 16


def default_light() -> np.ndarray:
    """Toward the light: up-left of the screen and in front (x right, y down, z viewer)."""
    v = np.array([-0.35, -0.45, 0.82])
    return v / np.linalg.norm(v)


# The glass look's film (shaders/ice.frag's FILM, the same numbers): the bump surface is
# clear below FILM_CUT px and rises FILM_GAIN times as fast above it.
FILM_CUT, FILM_GAIN = 0.8, 1.3


def film(bumps):
    """The bump surface's height (a numpy array) as the glass look shows it."""
    return np.where(bumps > FILM_CUT, FILM_GAIN * (bumps - FILM_CUT), 0.0)


@dataclass(frozen=True)
class Material:
    """Phong terms and the thickness-to-opacity law of the ice."""

    ice_color: tuple[float, float, float] = (0.93, 0.96, 1.0)
    ambient: float = 0.72  # frost scatters light: bright even away from the lamp
    diffuse: float = 0.38
    specular: float = 1.3  # wide, strong glints read as wet, sparkling ice
    shininess: float = 12.0
    opacity: float = 0.88  # very thick ice still lets a little of the view through
    density: float = 0.45  # alpha = opacity * (1 - exp(-density * thickness_px))
    relief: float = 1.6  # exaggerate slopes so px-high ice still catches the light
    refraction: float = 12.0  # glass look: px the view behind shifts per unit slope
