"""GLFW set-up: can a window open here, and the phone's window with every hint in one place."""

from __future__ import annotations

import sys

import glfw

from app.window.view import PHONE, SCALES, fit_scale, scale_problem, screen_scale

TITLE = "frost"


class WindowError(RuntimeError):
    pass


def display_problem() -> str | None:
    """None when GLFW can reach the display; else why not (e.g. DISPLAY=:99 with no X
    server there). On success GLFW stays initialized for the window: disconnecting the
    only client would make a bare X server (Xvfb) reset, and a connection made during the
    reset fails."""
    errors: list[str] = []
    glfw.set_error_callback(lambda code, text: errors.append(glfw_text(text)))
    ok = glfw.init()
    glfw.set_error_callback(None)  # type: ignore[arg-type]  # None removes it (GLFW docs)
    return None if ok else "; ".join(errors) or "GLFW could not start"


def open_window(scale: float | None) -> tuple:
    """A GLFW window for the phone at `scale` (default: fit the monitor); (window, scale)."""
    problem = None if scale is None else scale_problem(scale)
    if problem:
        raise WindowError(problem)
    errors: list[str] = []
    glfw.set_error_callback(lambda code, text: errors.append(f"{glfw_text(text)} ({code:#x})"))
    if not glfw.init():
        raise WindowError(f"GLFW could not start: {'; '.join(errors) or 'no reason given'}")
    scale = scale or opening_scale()
    size = (max(1, round(PHONE[0] * scale)), max(1, round(PHONE[1] * scale)))
    _window_hints()
    window = glfw.create_window(*size, TITLE, None, None)
    if not window:
        glfw.terminate()
        raise WindowError(f"cannot open a {size[0]}x{size[1]} OpenGL 3.3 core window: "
                          f"{'; '.join(errors) or 'no reason given'}")
    glfw.make_context_current(window)
    glfw.swap_interval(1)
    glfw.set_window_aspect_ratio(window, *PHONE)
    return window, scale


def open_side_window(size: tuple[int, int], title: str):
    """A second window with an OpenGL context of its own, hidden until shown, that does
    not take the keyboard from the phone when shown; None if it cannot open. Its context
    is left current (the caller makes the phone's current again)."""
    _window_hints()
    glfw.window_hint(glfw.VISIBLE, False)
    glfw.window_hint(glfw.FOCUS_ON_SHOW, False)
    window = glfw.create_window(*size, title, None, None)
    glfw.default_window_hints()
    if window:
        glfw.make_context_current(window)
        glfw.swap_interval(0)  # the phone's swap waits for the screen; one wait a frame
    return window or None


def _window_hints() -> None:
    """Every GLFW hint in one place: OpenGL 3.3 core (runs the GLSL ES 3.00 shaders)."""
    glfw.default_window_hints()
    glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
    glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
    glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
    glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
    glfw.window_hint(glfw.RESIZABLE, True)
    glfw.window_hint(glfw.DOUBLEBUFFER, True)
    glfw.window_hint(glfw.SCALE_TO_MONITOR, False)


def x_window_ids(window) -> tuple[int, ...]:
    """The X ids that name a GLFW window in X errors: its X window, then the GLX window
    GLFW made for its context (glXDestroyWindow meets that one when the window is gone);
    () off X11."""
    if glfw.get_platform() != glfw.PLATFORM_X11:
        return ()
    return tuple(i for i in (glfw.get_x11_window(window), glfw.get_glx_window(window)) if i)


def opening_scale() -> float:
    """The window's scale when --scale does not say: the phone at the primary monitor's
    content scale (`screen_scale`), as large as fits its work area, within SCALES."""
    monitor = glfw.get_primary_monitor()
    if not monitor:
        return 1.0
    _, _, w, h = glfw.get_monitor_workarea(monitor)
    most = screen_scale(glfw.get_monitor_content_scale(monitor)[0], points_not_pixels())
    return max(SCALES[0], min(SCALES[1], fit_scale((w, h), most=most)))


def points_not_pixels() -> bool:
    """Whether screen coordinates are points the system scales (a Mac), not pixels."""
    return sys.platform == "darwin"


def glfw_text(text) -> str:
    return text.decode(errors="replace") if isinstance(text, bytes) else str(text)
