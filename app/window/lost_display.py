"""The display lost while the window runs (the X server gone, or the window killed with
xkill or `xdotool windowkill`): Xlib calls its I/O error handler, then ends the process
with status 1, and Python never runs again. The handler set here gives the window the
moment in between to write what the user made. X11 only (GLFW's other platforms report
a lost display as an error to the frame loop)."""

from __future__ import annotations

import ctypes
import logging
import threading
from collections.abc import Callable
from typing import Any

import glfw

log = logging.getLogger("app.window")

_IOErrorHandler = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p)  # int (*)(Display *)


def on_lost_display(rescue: Callable[[], None]) -> Any:
    """Have `rescue()` run (once) when the X connection is lost, before Xlib exits; it must
    call neither GLFW nor GL. Returns the handler, which the caller keeps as long as the
    window is open (freed while Xlib may call it, it would crash the process); None where
    the window is not on X11 (nothing set)."""
    if glfw.get_platform() != glfw.PLATFORM_X11:
        return None
    try:
        xlib = ctypes.CDLL("libX11.so.6")  # the library GLFW loaded: one handler for both
    except OSError:
        return None
    handler = _IOErrorHandler(_once(rescue))
    xlib.XSetIOErrorHandler.argtypes = [_IOErrorHandler]
    xlib.XSetIOErrorHandler.restype = ctypes.c_void_p
    xlib.XSetIOErrorHandler(handler)
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
