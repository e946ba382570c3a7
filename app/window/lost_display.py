"""The display lost while the window runs, and a window destroyed from outside.

The display lost (the X server gone, or the window killed with xkill or `xdotool
windowkill`): Xlib calls its I/O error handler, then ends the process with status 1, and
Python never runs again. The handler set here gives the window the moment in between to
write what the user made.

A window destroyed from outside (`xdotool windowclose`: the X window is gone, the
connection is not): the next request on it fails with BadWindow or BadDrawable, and
Xlib's default error handler prints the error and ends the process. The handler set here
reports it instead (the phone's window: the frame loop ends and closes as Esc does, with
status 1; the tuning panel's: the panel closes, the app runs on). From then on the errors
on that window are expected (its GL context and GLFW's clean-up meet it again: its X
window, and the GLX window GLFW made for it) and ignored; any other error is not, as
another window still in use may yet go.

X11 only (GLFW's other platforms report a lost display as an error to the frame loop)."""

from __future__ import annotations

import ctypes
import logging
import threading
from collections.abc import Callable, Iterable
from typing import Any

import glfw

log = logging.getLogger("app.window")

_IOErrorHandler = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p)  # int (*)(Display *)
BAD_WINDOW, BAD_DRAWABLE = 3, 9  # X protocol error codes (X.h)


class XErrorEvent(ctypes.Structure):
    """Xlib's XErrorEvent."""

    _fields_ = [("type", ctypes.c_int), ("display", ctypes.c_void_p),
                ("resourceid", ctypes.c_ulong), ("serial", ctypes.c_ulong),
                ("error_code", ctypes.c_ubyte), ("request_code", ctypes.c_ubyte),
                ("minor_code", ctypes.c_ubyte)]


# int (*)(Display *, XErrorEvent *)
_ErrorHandler = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.POINTER(XErrorEvent))


def _xlib() -> Any:
    """The X library GLFW loaded (one set of handlers for both); None off X11."""
    if glfw.get_platform() != glfw.PLATFORM_X11:
        return None
    try:
        return ctypes.CDLL("libX11.so.6")
    except OSError:
        return None


def on_lost_display(rescue: Callable[[], None]) -> Any:
    """Have `rescue()` run (once) when the X connection is lost, before Xlib exits; it must
    call neither GLFW nor GL. Returns the handler, which the caller keeps as long as the
    window is open (freed while Xlib may call it, it would crash the process); None where
    the window is not on X11 (nothing set)."""
    xlib = _xlib()
    if xlib is None:
        return None
    handler = _IOErrorHandler(_once(rescue))
    xlib.XSetIOErrorHandler.argtypes = [_IOErrorHandler]
    xlib.XSetIOErrorHandler.restype = ctypes.c_void_p
    xlib.XSetIOErrorHandler(handler)
    return handler


def on_lost_window(lost: Callable[[int], Iterable[int]]) -> Any:
    """Have `lost(resource)` called when a request fails on a window or drawable that is
    gone (`resource`: its X id), instead of Xlib's exit; it must call neither GLFW nor GL,
    and returns the X ids of the window that went, whose errors are ignored from then on.
    Other errors go to the handler there was. Returns the handler, kept by the caller until
    GLFW has terminated; None off X11."""
    xlib = _xlib()
    if xlib is None:
        return None
    xlib.XSetErrorHandler.argtypes = [_ErrorHandler]
    xlib.XSetErrorHandler.restype = _ErrorHandler
    previous: list = []
    handler = _ErrorHandler(reporting(lost, lambda d, e: previous[0](d, e)))
    previous.append(xlib.XSetErrorHandler(handler))
    return handler


def reporting(lost: Callable[[int], Iterable[int]], otherwise: Callable[[Any, Any], int]
              ) -> Callable[[Any, Any], int]:
    """The error handler: an error on a window gone already is ignored; the first
    BadWindow or BadDrawable on any other is reported to `lost`, which names that window's
    ids (ignored from then on: the resource itself always is); any other error goes to
    `otherwise`."""
    gone: set[int] = set()

    def handler(display, event) -> int:
        error = event.contents
        if error.resourceid in gone:
            return 0
        if error.error_code not in (BAD_WINDOW, BAD_DRAWABLE):
            return otherwise(display, event)
        gone.add(error.resourceid)
        try:
            gone.update(lost(error.resourceid))
        except BaseException:  # nothing may unwind into Xlib's C frames
            log.exception("reporting the lost window failed")
        return 0

    return handler


def _once(rescue: Callable[[], None]) -> Callable[[int | None], int]:
    """The handler: the first thread to meet the lost connection rescues; another one
    waits on the lock until Xlib ends the process; the rescuer meeting it again (which it
    must not) returns at once rather than wait on itself."""
    lock = threading.Lock()
    rescuer: list[threading.Thread] = []

    def handler(_display: int | None) -> int:
        if rescuer == [threading.current_thread()]:
            return 0
        lock.acquire()  # never released: the process ends when the rescue returns
        rescuer.append(threading.current_thread())
        try:
            rescue()
        except BaseException:  # nothing may unwind into Xlib's C frames
            log.exception("writing the files after the display was lost failed")
        return 0

    return handler
