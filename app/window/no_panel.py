"""The window without its tuning panel: where imgui-bundle cannot be installed (it has no
wheel for Python 3.10), key M says why and the keys tune everything as before."""

from __future__ import annotations

import logging

log = logging.getLogger("app.window")

WHY = ("the tuning panel needs imgui-bundle, which needs Python 3.11 or later "
       "(pip install imgui-bundle==1.93.0); the keys still tune every parameter (H)")


class NoPanel:
    """PanelHost's interface, doing nothing: input is never the panel's."""

    ids: tuple[int, ...] = ()  # no window of its own

    def __init__(self, say=None):
        self.say = say or (lambda text: log.warning("%s", text))

    def toggle(self) -> None:
        self.say(WHY)

    def needs_frame(self) -> bool:
        return False

    def frame(self, phone_drawn: bool) -> None:
        pass

    def readout(self, phone_frames: int) -> str | None:
        return None

    def lost(self, resource: int) -> tuple[int, ...]:
        return ()

    def close(self) -> None:
        pass
