"""The one place shaders are loaded: GLSL ES 3.00 files in shaders/, given their header here."""

from __future__ import annotations

from app.resources import SHADER_DIR

__all__ = ["SHADER_DIR", "HEADER", "load_program", "shader_source"]

# The files carry no #version line so that the same source serves OpenGL ES 3.0 phones,
# desktop GL (4.3+ accepts "300 es") and the headless EGL context alike.
HEADER = "#version 300 es\nprecision highp float;\n"


def shader_source(name: str, defines: tuple[str, ...] = ()) -> str:
    """The full source of shaders/`name` with the version and precision header, and a
    `#define` for each of `defines` (a compile-time variant)."""
    path = SHADER_DIR / name
    if not path.is_file():
        raise FileNotFoundError(f"shader {name!r} not found in {SHADER_DIR}")
    return HEADER + "".join(f"#define {d}\n" for d in defines) + path.read_text()


def load_program(ctx, vert: str, frag: str, defines: tuple[str, ...] = ()):
    """A moderngl Program from two shader files of shaders/, both compiled with
    `defines`."""
    return ctx.program(vertex_shader=shader_source(vert, defines),
                       fragment_shader=shader_source(frag, defines))
