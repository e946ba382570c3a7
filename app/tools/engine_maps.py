"""The files `frost maps` writes for game engines, all together or none: height.png (16-bit),
normal.png (the Y convention asked for), alpha.png, growth.png (16-bit: when each pixel
froze), preview.png (the frost as drawn over a neutral backdrop; with a tile also
preview-2x2.png, four copies side by side, where a seam would show) and maps.json, which
says what every file and channel holds."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from app.images import frost_meta, png_writer
from sim import FrostSim, Params
from sim.io.files import write_all_atomic
from sim.look.geometry import FrostGeometry
from sim.look.growthmap import GROWTH_NONE, GROWTH_TOP, GrowthClock, encode_growth
from sim.look.maps import MEANING, FrostMaps, compute_maps, encode, live_segments, map_triangles

# What the growth map's values stand for (maps.json and the PNG's text chunk).
GROWTH_MEANING = (f"16-bit grey: when the pixel's ice last appeared, tick x {GROWTH_TOP} / ticks "
                  f"(0 ... {GROWTH_TOP}); {GROWTH_NONE} where no ice is; ice at a share p of the "
                  f"run where growth <= p x {GROWTH_TOP}")
NORMAL_Y = {"up": "OpenGL (Y+: Godot, Unity, Blender, glTF)", "down": "DirectX (Y-: Unreal)"}
# The preview's backdrop: a flat, neutral blue-grey that white ice reads against.
BACKDROP_RGB = (70, 76, 86)
ENGINE_FILES = ("height.png", "normal.png", "alpha.png", "growth.png", "preview.png",
                "preview-2x2.png", "maps.json")


@dataclass(frozen=True)
class EngineRun:
    """A grown frost and how its maps were asked for."""

    sim: FrostSim
    geometry: FrostGeometry
    clock: GrowthClock  # fed every delta of the run
    params: Params
    seed: int
    touches: list
    tile: bool
    normal_y: str  # "up" (OpenGL) or "down" (DirectX)
    ticks: int


def engine_images(job: EngineRun) -> tuple[dict[str, np.ndarray], float]:
    """The integer images of height, normal (Y flipped for "down"), alpha and growth; and
    the px that height's 65535 stands for."""
    sim = job.sim
    maps = compute_maps(job.geometry.heights, live_segments(sim), job.params, sim.width,
                        sim.height, triangles=map_triangles(sim, job.params), wrap=job.tile)
    if job.normal_y == "down":
        maps = FrostMaps(maps.height, maps.normal * np.array([1, -1, 1], np.float32), maps.alpha)
    images, top = encode(maps)
    images["growth"] = encode_growth(job.clock.ticks(maps.height > 0), job.ticks)
    return images, top


def sidecar(job: EngineRun, top: float, files: list[str]) -> dict:
    """maps.json: what each file and channel holds, in which units and encoding."""
    w, h = job.sim.width, job.sim.height
    return {
        "generator": "frost maps", "size": [w, h], "tiling": "both directions" if job.tile else "none",
        "seed": job.seed, "ticks": job.ticks, "touches": [list(t) for t in job.touches],
        "parameters": job.params.as_dict(), "files": {
            "height.png": {"channels": {"grey": "height above the glass"}, "bits": 16,
                           "encoding": "linear", "px_per_unit": top / 65535, "height_max_px": top},
            "normal.png": {"channels": {"R": "x right", "G": f"y {job.normal_y} the image",
                                        "B": "z out of the glass"},
                           "bits": 8, "encoding": "linear, n x 0.5 + 0.5",
                           "convention": NORMAL_Y[job.normal_y], "normal_y": job.normal_y},
            "alpha.png": {"channels": {"grey": "ice opacity 0 ... 1"}, "bits": 8, "encoding": "linear",
                          "law": "opacity x (1 - exp(-density x height_px))"},
            "growth.png": {"channels": {"grey": GROWTH_MEANING}, "bits": 16, "encoding": "linear",
                           "top": GROWTH_TOP, "none": GROWTH_NONE},
            **{f: {"channels": {"RGB": "the frost as drawn over a neutral backdrop"}, "bits": 8,
                   "encoding": "sRGB", "copies": "2x2" if f == "preview-2x2.png" else "1"}
               for f in files if f.startswith("preview")}}}


def write_engine_maps(folder, job: EngineRun) -> list[Path]:
    """Compute and write every file (preview first: no EGL fails before any write)."""
    previews = render_previews(job)
    images, top = engine_images(job)
    folder = Path(folder)
    meta = frost_meta("frost maps", job.params, job.seed, job.sim.tick, job.touches,
                      height_max_px=top)
    meaning = {**MEANING, "growth": GROWTH_MEANING}
    if job.normal_y == "down":
        meaning["normal"] = meaning["normal"].replace("y up (OpenGL)", "y down (DirectX)")
    writes = {folder / f"{name}.png": png_writer(image, {**meta, "map": name, "encoding": meaning[name],
                                                        "normal_y": job.normal_y})
              for name, image in images.items()}
    writes.update({folder / name: png_writer(image, {**meta, "map": "preview"})
                   for name, image in previews.items()})
    files = sorted(p.name for p in writes) + ["maps.json"]
    text = json.dumps(sidecar(job, top, files), indent=1).encode()
    writes[folder / "maps.json"] = lambda f: f.write(text)
    return write_all_atomic(writes)


def render_previews(job: EngineRun) -> dict[str, np.ndarray]:
    """preview.png (and preview-2x2.png for a tile) drawn by the renderer, headless."""
    from app.tools.preview import draw_preview  # GL only when the maps are written

    image = draw_preview(job.sim, job.params, job.tile, BACKDROP_RGB)
    out = {"preview.png": image}
    if job.tile:
        out["preview-2x2.png"] = np.tile(image, (2, 2, 1))
    return out
