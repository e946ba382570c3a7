"""The one place shaders are loaded: the files in shaders/, given their header here.

The files are the common subset of GLSL ES 3.00 and GLSL 3.30 and carry no #version line.
The phone page (WebGL2) compiles them as ES 3.00 with its own copy of the "es" header
(app/web/programs.js). Every desktop context compiles them as 3.30 core ("core"): a Mac's
OpenGL stops at 4.1 core, and desktop GL accepts "300 es" only from 4.3
(ARB_ES3_compatibility); on Linux the same dialect runs, so what is tested here is what a
Mac compiles. glslangValidator checks the files as ES (tests/test_render.py), which
rejects what 3.30 lets pass (an int where a float is meant).
"""

from __future__ import annotations

from app.resources import SHADER_DIR

__all__ = ["DESKTOP", "HEADERS", "SHADER_DIR", "load_program", "shader_source"]

HEADERS = {"core": "#version 330 core\n", "es": "#version 300 es\nprecision highp float;\n"}
DESKTOP = "core"  # the dialect of every OpenGL context on a desktop


def shader_source(name: str, defines: tuple[str, ...] = (), dialect: str | None = None) -> str:
    """The full source of shaders/`name` with `dialect`'s header (HEADERS; default
    DESKTOP) and a `#define` for each of `defines` (a compile-time variant)."""
    dialect = dialect or DESKTOP
    if dialect not in HEADERS:
        raise ValueError(f"GLSL dialect {dialect!r}: one of {', '.join(HEADERS)}")
    path = SHADER_DIR / name
    if not path.is_file():
        raise FileNotFoundError(f"shader {name!r} not found in {SHADER_DIR}")
    return HEADERS[dialect] + "".join(f"#define {d}\n" for d in defines) + path.read_text(encoding="utf-8")


def load_program(ctx, vert: str, frag: str, defines: tuple[str, ...] = (),
                 dialect: str | None = None):
    """A moderngl Program from two shader files of shaders/, both compiled with
    `defines` in `dialect`."""
    return ctx.program(vertex_shader=shader_source(vert, defines, dialect),
                       fragment_shader=shader_source(frag, defines, dialect))
