"""What the keys do: one dispatch table from the key table's action names (keys.BINDINGS)
to the simulation thread, the renderer's view, the HUD and the capture of files."""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

import glfw

from app.backdrops import BACKDROPS, LIVE, next_backdrop
from app.keys import DEFAULT_PRESET, key_table
from app.simthread.thread import SimThread, Snapshot
from app.window.capture import Capture
from app.window.presenter import Presenter
from app.window.record import Recorder
from app.window.status import Status, onoff
from sim import Params, preset_name, tuning
from sim.io.files import why
from sim.io.paramsets import load_params, save_params

# Actions that repeat while their key is held.
REPEATING = {"single_step", "scale", "shift", "light"}
MAX_LIGHT_TILT = 0.95  # |xy| of the unit light vector: it never grazes the glass
# What to do about a change refused for a mode that is off (the end of Params' message).
REFUSED_HINTS = {"needs window_frost=True": "press W (the frosted window) first",
                 "needs grains=True": "press 0 (fern) or W (the frosted window) first"}


def moved_light(light, dx: float, dy: float) -> tuple[float, float, float]:
    """The light direction moved on the screen (x right, y down), kept toward the viewer."""
    x, y = float(light[0]) + dx, float(light[1]) + dy
    r = math.hypot(x, y)
    if r > MAX_LIGHT_TILT:
        x, y = x * MAX_LIGHT_TILT / r, y * MAX_LIGHT_TILT / r
    return x, y, math.sqrt(max(0.0, 1.0 - x * x - y * y))


class Actions:
    """The key callback and what each action does. `params` is what the keys asked for
    last (the thread applies it at its next tick); `shown()` is the snapshot on screen,
    `redraw()` asks for the phone to be rendered again, `quit_()` ends the frame loop."""

    def __init__(self, params: Params, thread: SimThread, presenter: Presenter, status: Status,
                 capture: Capture, recorder: Recorder, shown: Callable[[], Snapshot | None],
                 redraw: Callable[[], None], quit_: Callable[[], None]):
        self.params, self.thread, self.presenter = params, thread, presenter
        self.status, self.redraw = status, redraw
        # The backdrop shown at the start (a --background file joins the X key's cycle).
        self.own_backdrop: str | None = None
        # The count of the window's last backdrop sent to the thread: snapshots older than
        # its tick still say the one before, and are not followed (`follow_backdrop`).
        self.backdrop_sent = 0
        self._refused: str | None = None  # a backdrop a snapshot said that could not be read
        self.follows_backdrops = True  # False: --background imposed on a replay
        self.keys = key_table(lambda name: getattr(glfw, f"KEY_{name}"))
        self.preset = first_preset(params)  # the last chosen: the panel's reset goes to it
        self.params_sent = 0  # the thread's number of the last change sent (`_tune`)
        self.toggle_panel: Callable[[], None] = lambda: None  # the window sets it
        self.weather_sets_temperature = False  # --weather: T and Y change nothing
        self.table: dict[str, Callable] = {
            "pause": lambda _: thread.send("pause"),
            "single_step": lambda _: thread.send("step"),
            "clear": self._clear, "record": lambda _: recorder.toggle(),
            "screenshot": lambda _: capture.screenshot(shown(), self.params),
            "export_maps": lambda _: capture.export_maps(),
            "scale": lambda arg: self._tune(tuning.scaled, *arg),
            "shift": self._shift,
            "preset": self._preset,
            "set_param": lambda arg: self._tune(tuning.changed, *arg),
            "set_backdrop": self._set_backdrop, "save_params": self._save_params,
            "load_params": self._load_params, "toggle_panel": lambda _: self.toggle_panel(),
            "toggle_param": lambda name: self._tune(tuning.toggled, name),
            "cycle_param": lambda name: self._tune(tuning.cycled, name),
            "toggle_view": self._toggle_view, "light": self._move_light,
            "backdrop": self._next_backdrop,
            "toggle_hud": lambda _: self._toggle_hud("visible"),
            "toggle_help": lambda _: self._toggle_hud("show_help"),
            "quit": lambda _: quit_()}

    def run(self, action: str, arg=None) -> None:
        """Action `action` of the table, as its key does it (the panel's way in)."""
        self.table[action](arg)
        self.status.hud_next = 0.0

    def backdrop(self) -> str:
        return self.presenter.renderer.backdrop

    def on_key(self, _window, key, _scancode, action, _mods) -> None:
        binding = self.keys.get(key)
        if binding is None or action == glfw.RELEASE:
            return
        if action == glfw.REPEAT and binding.action not in REPEATING:
            return
        self.table[binding.action](binding.arg)
        self.status.hud_next = 0.0  # show the change at once

    def _clear(self, _arg) -> None:
        self.thread.send("clear")
        self.status.say("cleared")

    def _toggle_hud(self, flag: str) -> None:
        hud = self.presenter.hud
        setattr(hud, flag, not getattr(hud, flag))

    def _toggle_view(self, name: str) -> None:
        renderer = self.presenter.renderer
        setattr(renderer, name, not getattr(renderer, name))
        self.redraw()
        self.status.say(f"{name} {onoff(getattr(renderer, name))}")

    def _next_backdrop(self, _arg) -> None:
        renderer = self.presenter.renderer
        self.own_backdrop = self.own_backdrop or renderer.backdrop
        self._set_backdrop(next_backdrop(renderer.backdrop, self.own_backdrop))

    def _set_backdrop(self, name: str) -> None:
        renderer = self.presenter.renderer
        self.own_backdrop = self.own_backdrop or renderer.backdrop
        try:
            renderer.set_backdrop(name)
        except ValueError as err:  # the file went away since the start
            self.status.say(f"refused: {err}", logging.WARNING)
            return
        self.thread.show_clock("window", name == LIVE)  # its minutes recorded while shown
        self.backdrop_sent = self.thread.show_backdrop(name)  # (the session records it)
        self.redraw()
        self.status.say(f"background {name}")

    def follow_backdrop(self, name: str | None, handled: int) -> bool:
        """Show the backdrop a snapshot says (`name`, after `handled` commands): one a page
        chose (frost serve --window), a photo dropped on the window, a replay's; not while
        the window's own last choice is still on its way. Whether the picture changed."""
        renderer = self.presenter.renderer
        if name is None or name in (renderer.backdrop, self._refused) \
                or handled < self.backdrop_sent or not self.follows_backdrops:
            return False
        try:
            renderer.set_backdrop(name)
        except ValueError as err:  # a photo whose file is gone: said once
            self._refused = name
            self.status.say(str(err), logging.WARNING)
            return False
        self.thread.show_clock("window", name == LIVE)
        if name not in BACKDROPS:  # a photo: it joins the X key's cycle (the latest one)
            self.own_backdrop = name
        return True

    def _preset(self, name: str) -> None:
        self.preset = name
        self._tune(tuning.preset, name, said=f"preset {name}")

    def _save_params(self, path: str) -> None:
        try:
            written = save_params(path, self.params)
        except OSError as err:
            self.status.say(f"params NOT saved: {why(err, path)}", logging.WARNING)
            return
        self.status.say(f"params saved: {written}")

    def _load_params(self, path: str) -> None:
        """A parameter set, applied as one change (its grid_spacing aside: the session's
        height grid keeps its own)."""
        try:
            loaded = load_params(path)
        except ValueError as err:
            self.status.say(f"params NOT loaded: {err}", logging.WARNING)
            return
        keep = self.params.grid_spacing
        kept = f" (grid_spacing stays {keep}, set at start)" if loaded.grid_spacing != keep else ""
        self._tune(lambda p: loaded.replace(grid_spacing=keep),
                   said=f"params loaded from {path}{kept}")

    def _move_light(self, arg) -> None:
        self.presenter.renderer.light = moved_light(self.presenter.renderer.light, *arg)
        self.redraw()

    def _shift(self, arg) -> None:
        """A length or the temperature stepped; under --weather the weather sets the
        temperature (every reading), so T and Y say so and change nothing."""
        if arg[0] == "temperature" and self.weather_sets_temperature:
            self.status.say("temperature: the weather sets it (--weather): T and Y change nothing")
            return
        self._tune(tuning.shifted, *arg)

    def _tune(self, change, *arg, said: str = "params") -> None:
        """The parameters changed by `change(params, *arg)`, sent to the thread; the HUD
        names each value changed after `said`, or says why nothing changed."""
        try:
            params = change(self.params, *arg)
        except ValueError as err:
            self.status.say(f"refused: {refusal(err)}", logging.WARNING)
            return
        changed = tuning.differences(self.params, params)
        if not changed:
            self.status.say(f"{said}: unchanged")
            return
        self.params = params
        self.params_sent = self.thread.send("params", params)
        self.status.say(f"{said}: " + " ".join(f"{k}={_number(v)}" for k, v in changed.items()))

    def follow(self, params: Params, applied: int) -> None:
        """The parameters of a rebuild the thread made (`applied`: the commands it had
        applied by then), taken as the keys' own once every change they sent is applied,
        so the next key builds on them: with `frost serve --window` a page changes them too
        (its preset or look), and a key built on its own older ones undid that change. A
        change not of the keys' making is said in the HUD."""
        if applied < self.params_sent:
            return  # (a change of the keys' own is on its way; its rebuild follows)
        changed = tuning.differences(self.params, params)
        self.params = params
        if changed:
            self.status.say("params (a page's change): "
                            + " ".join(f"{k}={_number(v)}" for k, v in changed.items()))


def first_preset(params: Params) -> str:
    """The preset `params` follows (the first of Table 1's twins), else the default look."""
    name = preset_name(params).split("/")[0]
    return DEFAULT_PRESET if name == "custom" else name


def refusal(err: ValueError) -> str:
    """Why a change was refused, and what to do where a mode it needs is off."""
    text = str(err)
    hint = next((h for end, h in REFUSED_HINTS.items() if text.endswith(end)), None)
    return f"{text}: {hint}" if hint else text


def _number(v) -> str:
    if isinstance(v, bool):
        return onoff(v)
    return f"{v:g}" if isinstance(v, float) else str(v)
