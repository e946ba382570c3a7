"""What a page's input does: the window's commands for the simulation thread (a finger is
the left button, the warm finger the right; a key is the window's key of that name), so it
is recorded with its tick and `frost replay` plays it again."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from app.backdrops import BACKDROPS
from app.keys import BINDINGS, Binding
from app.photos import is_photo, photo_file
from app.serve.pages import POINT_RATE, TokenBucket
from app.serve.protocol import Input
from app.serve.turns import PAGE_WAITING, PageQueue, Turns
from app.simthread.thread import SimThread
from sim import Params, all_presets, preset_name, tuning
from sim.io.gestures import DRAG_SPACING_HC, MELT_SPACING, path_points
from sim.params import LOOKS
from sim.screen import SIZE, touch_problem

# The window's key actions that act on the shared frost; the others (screenshot, recording,
# panel, HUD, light, the desktop's view toggles) are the page's own or the desktop's.
KEY_TUNES = {"scale": tuning.scaled, "shift": tuning.shifted, "toggle_param": tuning.toggled,
             "cycle_param": tuning.cycled}
KEY_COMMANDS = {"pause": "pause", "single_step": "step", "clear": "clear"}
# Input not of a page (the bench's own scribble): most commands that may wait for the
# simulation thread before its touches and melts are dropped (the finger still moves on).
# A page's wait in its own queue (app/serve/turns.py, PAGE_WAITING).
MAX_WAITING = 2000
# The photos shown in a run that a page may choose again (the hello's list): the latest.
MAX_PHOTOS = 8
# A page is told of its dropped input at the first, then once every this many.
DROP_TOLD = 100


class Controls:
    """Turns checked page input into commands; `params` is what was asked for last (the
    thread applies it at its next tick); `backdrop` is the one every page shows."""

    def __init__(self, thread: SimThread, params: Params, melt_radius: float, backdrop: str,
                 notice: Callable[[str], None], tick: Callable[[], int]):
        self.thread, self.params, self.melt_radius = thread, params, melt_radius
        self.backdrop, self.tick = backdrop, tick
        # The count of the last backdrop sent to the thread (`follow_backdrop`); the session
        # records the one it starts on.
        self.backdrop_sent = thread.show_backdrop(backdrop)
        self.notice = self.tell_all = notice
        self.chosen = ""  # the preset a page chose last
        self.store: Path | None = None  # the folder of photos (app/serve/photo.py)
        self.photos: list[str] = []  # those shown in this run, oldest first (MAX_PHOTOS)
        self.dropped = 0  # touches and melts dropped while too much input waited
        self.dropped_here = 0  # those of input not of a page (`_dropped`)
        self.skipped = self.skipped_told = 0  # touches and melts over a page's bound
        self.points: TokenBucket | None = None  # the bound of the page being handled
        self.turns = Turns(thread)  # the pages' commands, sent to the thread in turns
        self.queue: PageQueue | None = None  # the queue of the page being handled
        self.keys: dict[str, Binding] = {name: b for b in BINDINGS for name in b.keys}
        self._handlers: dict[str, Callable[[Input, dict], None]] = {
            "touch": self._pointer, "melt": self._pointer,
            "preset": lambda m, _f: self._preset(m.name),
            "look": lambda m, _f: self._tune(lambda p, v: tuning.changed(p, "look", v), m.name,
                                             check=LOOKS),
            "backdrop": lambda m, _f: self._backdrop(m.name),
            "key": lambda m, _f: self._key(m.name),
            "pause": self._command, "step": self._command, "clear": self._command}

    def preset(self) -> str:
        """The preset the parameters follow: the one last chosen if they still do (Table
        1's twins b-2 and c-2 are the same numbers), else the first, or 'custom'."""
        names = preset_name(self.params).split("/")
        return self.chosen if self.chosen in names else names[0]

    def handle(self, message: Input, fingers: dict,
               reply: Callable[[str], None] | None = None,
               points: TokenBucket | None = None, queue: PageQueue | None = None) -> None:
        """Apply one page message; `fingers` holds that page's drags, `reply` tells that
        page why a change was refused (default: every page), `points` (a TokenBucket, or
        None: no bound) how many touches and melts its fingers may still leave, `queue`
        (`turns.open()`; None: straight to the thread) where its commands wait their turn."""
        self.notice = reply or self.tell_all
        self.points, self.queue = points, queue
        self._handlers[message.kind](message, fingers)

    def _submit(self, kind: str, arg=None) -> None:
        """A command for the thread: in the page's turn, or at once (no page)."""
        if self.queue is None:
            self.thread.send(kind, arg)
        else:
            self.turns.put(self.queue, kind, arg)

    def _too_much_waiting(self) -> str | None:
        """Why a touch or melt of the page is dropped now (its queue, or the thread's, is
        full), or None."""
        if self.queue is not None:
            return f"{PAGE_WAITING} or more of this page's" if self.queue.full() else None
        full = self.thread.sent - self.thread.handled >= MAX_WAITING
        return f"{MAX_WAITING} or more" if full else None

    def _command(self, m: Input, _fingers: dict) -> None:
        self._submit(m.kind)

    def _pointer(self, m: Input, fingers: dict) -> None:
        key = (m.kind, m.finger)
        if m.phase == "up":
            fingers.pop(key, None)
            return
        spot = (m.x, m.y)
        if touch_problem(*spot, SIZE) is not None:
            return  # off the screen, as a click beside the phone
        full = self._too_much_waiting()
        if full is not None:
            fingers[key] = spot  # the next move goes on from here, not from the last spot sent
            self._dropped(full)
            return
        if m.phase == "down" or key not in fingers:
            fingers[key] = spot
            if self._granted(1):
                self._send(m.kind, spot, timed=m.phase == "down")
            return
        spacing = DRAG_SPACING_HC * self.params.hc if m.kind == "touch" \
            else MELT_SPACING * self.melt_radius
        points = path_points(fingers[key], spot, spacing)
        kept = self._granted(len(points))
        for point in points[:kept]:
            self._send(m.kind, point, timed=False)
        if kept < len(points):
            fingers[key] = spot  # the rest of the path skipped: the finger goes on from here
        elif points:
            fingers[key] = points[-1]

    def _dropped(self, full: str) -> None:
        """A touch or melt dropped, `full` saying what was full: told to the page that sent
        it (each page counted on its own), at its first and every DROP_TOLD-th since."""
        self.dropped += 1
        counter = self.queue if self.queue is not None else self
        counter.dropped_here += 1
        n = counter.dropped_here
        if n % DROP_TOLD == 1:
            self.notice(f"too much input waiting ({full}): touches and melts of this page "
                        f"dropped: {n} so far")

    def _granted(self, wanted: int) -> int:
        """How many of `wanted` touches or melts the page's bound lets through."""
        if self.points is None or wanted == 0:
            return wanted
        granted = self.points.grant(wanted)
        if granted < wanted:
            self.skipped += wanted - granted
            if self.skipped_told < self.skipped // 1000 + 1:
                self.skipped_told = self.skipped // 1000 + 1
                self.notice(f"a finger faster than {POINT_RATE:g} touches or melts a second: "
                            "part of its path was skipped")
        return granted

    def _send(self, kind: str, spot: tuple[float, float], timed: bool) -> None:
        if kind == "melt":
            self._submit("melt", (*spot, self.melt_radius))
        else:
            self._submit("touch", (spot, (self.tick(), time.monotonic()) if timed else None))

    def _key(self, name: str) -> None:
        binding = self.keys.get(name)
        if binding is None:
            self.notice(f"key {name[:16]} is not one of the window's keys")
        elif binding.action in KEY_COMMANDS:
            self._submit(KEY_COMMANDS[binding.action])
        elif binding.action == "preset":
            self._preset(binding.arg)
        elif binding.action in KEY_TUNES:
            args = binding.arg if isinstance(binding.arg, tuple) else (binding.arg,)
            self._tune(KEY_TUNES[binding.action], *args)
        elif binding.action == "backdrop":
            names = list(BACKDROPS)
            self._backdrop(names[(names.index(self.backdrop) + 1) % len(names)]
                           if self.backdrop in names else names[0])
        else:
            self.notice(f"key {name}: {binding.description}: not on a page")

    def _preset(self, name: str) -> None:
        if name in all_presets():
            self.chosen = name
        self._tune(tuning.preset, name, check=all_presets())

    def backdrops(self) -> list[str]:
        """The backdrops a page may choose: the built-ins, then the photos of this run."""
        return [*BACKDROPS, *self.photos]

    def show_photo(self, name: str) -> None:
        """Photo `name`, kept in the store, becomes every page's backdrop (and the latest of
        the photos a page may choose again)."""
        if name in self.photos:
            self.photos.remove(name)
        self.photos = [*self.photos, name][-MAX_PHOTOS:]
        self._backdrop(name)

    def _backdrop(self, name: str) -> None:
        if not (name in BACKDROPS or self._kept(name)):
            self.notice(f"backdrop {name[:40]!r} refused: one of "
                        f"{', '.join(BACKDROPS)} or a photo shown since frost serve started")
            return
        self.backdrop = name
        self.backdrop_sent = self.thread.show_backdrop(name)  # (the session records it)

    def follow_backdrop(self, name: str | None, handled: int) -> None:
        """The backdrop the thread says (`name`, after `handled` commands): under frost
        serve --window, the window's own choice (its key, a file dropped on it) becomes
        every page's; not while a page's last choice is still on its way to the thread."""
        if name is None or name == self.backdrop or handled < self.backdrop_sent:
            return
        if is_photo(name) and self.store is not None and photo_file(name, self.store).is_file():
            self.photos = [*(p for p in self.photos if p != name), name][-MAX_PHOTOS:]
        elif name not in BACKDROPS:
            return  # (a file the window was given by path: the pages cannot load it)
        self.backdrop = name

    def _kept(self, name: str) -> bool:
        """Whether `name` is a photo of this run whose file is still in the store."""
        return (name in self.photos and self.store is not None
                and photo_file(name, self.store).is_file())

    def _tune(self, change, *args, check=None) -> None:
        """The window's way to change the parameters (Actions._tune); the grid's spacing
        stays (the pages' height grid is the session's)."""
        if check is not None and args[0] not in check:
            self.notice(f"{args[0][:16]!r} refused: one of {', '.join(check)}")
            return
        try:
            params = change(self.params, *args).replace(grid_spacing=self.params.grid_spacing)
        except ValueError as err:
            self.notice(f"refused: {err}")
            return
        if tuning.differences(self.params, params):
            self.params = params
            self._submit("params", params)
