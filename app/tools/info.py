"""`frost info`: what a bug report needs, a line each: the platform, Python and the libraries,
frost's config folder (what is kept across runs), the tuning panel (or why there is none),
GLFW and the screen (platform, monitor, content scale, a window's OpenGL), the headless
OpenGL context (vendor, renderer, version) and the shader dialect they compile."""

from __future__ import annotations

import platform
import sys
from importlib import metadata

from app.config import config_dir
from app.gl.shaders import DESKTOP, load_program
from sim.io.files import one_line

# What the config folder holds (app/config.py), as `frost info` says it.
KEPT = ("frost serve's local authority, token and QR images; the last weather reading")
PACKAGES = ("frost", "numpy", "moderngl", "glfw", "Pillow", "aiohttp", "imgui-bundle")


def lines() -> list[tuple[str, str]]:
    """(what, value) pairs, in the order printed."""
    out = [("frost", _version("frost")), ("platform", platform.platform()),
           ("python", f"{platform.python_implementation()} {sys.version.split()[0]}"),
           ("packages", ", ".join(f"{p} {_version(p)}" for p in PACKAGES[1:])),
           ("config folder", f"{config_dir()} ({KEPT})"),
           ("tuning panel", _panel()),
           ("shader dialect", f"GLSL {DESKTOP} (files in shaders/; the page: ES 3.00)")]
    # (the window's GLX context first: a standalone EGL context made before it kills the
    # process at GLX's first call)
    screen = _screen()
    return out + _headless() + screen


def _version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def _panel() -> str:
    """The window's tuning panel (key M), or why it has none here."""
    from app.window.no_panel import panel_problem

    problem = panel_problem()
    return f"imgui-bundle {_version('imgui-bundle')} (key M)" if problem is None else f"none: {problem}"


def _headless() -> list[tuple[str, str]]:
    from app.tools.offscreen import make_context

    try:
        ctx = make_context()
    except RuntimeError as err:
        return [("headless OpenGL", one_line(str(err)))]
    try:
        return [("headless OpenGL", _gl(ctx)), ("its shaders", _compiles(ctx))]
    finally:
        ctx.release()


def _gl(ctx) -> str:
    info = ctx.info
    return f"{info['GL_VERSION']}; {info['GL_RENDERER']}; {info['GL_VENDOR']}"


def _compiles(ctx) -> str:
    """Whether the desktop dialect compiles here, and the page's (ES 3.00) too."""
    said = []
    for dialect in (DESKTOP, "es"):
        try:
            load_program(ctx, "fullscreen.vert", "background.frag", dialect=dialect).release()
            said.append(f"{dialect}: compiles")
        except Exception as err:  # moderngl raises its own Error with the compiler's log
            said.append(f"{dialect}: refused ({compiler_says(str(err))[:80]})")
    return "; ".join(said)


def compiler_says(log: str) -> str:
    """A compiler's log in one line: its lines that say an error (the headings and rules
    around them dropped), else the whole log's words."""
    errors = [line.strip() for line in log.splitlines() if "error" in line.lower()]
    return one_line("; ".join(errors) if errors else " ".join(log.split()))


def _screen() -> list[tuple[str, str]]:
    """GLFW, the primary monitor and a hidden window's context; why not, with no display."""
    import glfw

    from app.window.glfw_setup import display_problem, open_side_window

    version = glfw.get_version_string()
    version = version.decode() if isinstance(version, bytes) else str(version)
    problem = display_problem()
    if problem:
        return [("GLFW", f"{version}; no display: {one_line(problem)}")]
    try:
        out = [("GLFW", f"{version}; platform {_platform_name(glfw.get_platform())}")]
        monitor = glfw.get_primary_monitor()
        if monitor:
            _, _, w, h = glfw.get_monitor_workarea(monitor)
            scale = glfw.get_monitor_content_scale(monitor)
            out.append(("monitor", f"work area {w}x{h}, content scale {scale[0]:g}x{scale[1]:g}"))
        window = open_side_window((64, 64), "frost info")
        if window is None:
            return out + [("window OpenGL", "no OpenGL 3.3 core window could open")]
        import moderngl
        ctx = moderngl.create_context()
        (ww, wh), (fw, fh) = glfw.get_window_size(window), glfw.get_framebuffer_size(window)
        out += [("window OpenGL", _gl(ctx)),
                ("window", f"{ww}x{wh} screen coordinates, framebuffer {fw}x{fh}, content "
                           f"scale {glfw.get_window_content_scale(window)[0]:g}")]
        glfw.destroy_window(window)
        return out
    finally:
        glfw.terminate()


def _platform_name(code: int) -> str:
    import glfw
    names = {getattr(glfw, f"PLATFORM_{n}", None): n.lower()
             for n in ("WIN32", "COCOA", "WAYLAND", "X11", "NULL")}
    return names.get(code, f"unknown ({code})")


def run(_args=None, _params=None) -> int:
    for what, value in lines():
        print(f"{what}: {value}")
    return 0
