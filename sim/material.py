"""How the ice looks: the Phong terms and the thickness-to-opacity law.

Shared data, numpy-free and GL-free: the renderer hands these to its shaders, and the
exported alpha map (sim.maps) follows the same law, so the two always agree.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

# The ice shader's compile-time variant for each look (Params.look; shaders/ice.frag).
LOOK_DEFINES = MappingProxyType({
    "paper": (),
    "glass": ("FILM", "SCATTER", "SPARKLE", "REFRACT"),
})


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
