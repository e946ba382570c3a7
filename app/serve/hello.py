"""The hello a page starts from (docs/protocol.md), built here alone: `frost serve` sends it
to every page that connects, and the benches hand it to the page they load, so that the two
cannot drift apart."""

from __future__ import annotations

from app.serve.protocol import VERSION
from sim import Params
from sim.look.material import FEATURE_DEFINES, LOOK_DEFINES, MAX_DEPTH, TILE, Material, default_light
from sim.params import LOOKS
from sim.screen import SIZE
from sim.weather import event_words


def view(backdrop: str) -> dict:
    """The view a page shows by default over `backdrop` (a session file records it)."""
    return {"light": [float(v) for v in default_light()], "features": True, "bumps": True,
            "background": backdrop}


def uniforms() -> dict:
    """The desktop renderer's material, as the page's shader uniforms."""
    m = Material()
    return {"u_ice_color": list(m.ice_color), "u_ambient": m.ambient, "u_diffuse": m.diffuse,
            "u_specular": m.specular, "u_shininess": m.shininess, "u_opacity": m.opacity,
            "u_density": m.density, "u_relief": m.relief, "u_refraction": m.refraction}


def hello_fields(params: Params, backdrop: str, grid: tuple[int, int]) -> dict:
    """The hello's fields that follow from the frost's parameters and the grid the pages get
    (`grid`: cols, rows); the caller adds the state of its session."""
    defines = {look: {"ice": list(LOOK_DEFINES[look]), "feature": list(FEATURE_DEFINES[look])}
               for look in LOOKS}
    return {"protocol": VERSION, "screen": list(SIZE), "grid": list(grid),
            "spacing": params.grid_spacing, "looks": list(LOOKS), "view": view(backdrop),
            "uniforms": uniforms(), "defines": defines, "tile": TILE, "max_depth": MAX_DEPTH}


def weather_field(weather: dict | None) -> dict | None:
    """What the pages are told of the weather outside (the hello's and the state's
    `weather`) by a weather event's {"reading": ..., "glass": ...} (a snapshot's): the
    reading's place, the temperature outside (C) and the reading in words; None for none."""
    if weather is None:
        return None
    place, words = event_words(weather)
    return {"place": place, "temperature_c": float(weather["reading"]["temperature_c"]),
            "reading": words}


class WeatherWords:
    """`weather_field` of the latest weather event, worked out once for each (the state is
    asked for at every tick; a snapshot holds its thread's event until the next)."""

    def __init__(self):
        self._event: dict | None = None
        self._field: dict | None = None

    def __call__(self, weather: dict | None) -> dict | None:
        if weather is not self._event:
            self._event, self._field = weather, weather_field(weather)
        return self._field
