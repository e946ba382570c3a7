"""The commands the simulation thread applies at its ticks: input from the window and the
pages (touches, melts, parameter changes, clear, pause, single step, the backdrop, the
weather outside, a map export), each recorded on the timeline as an event or changing the
thread's own state."""

from __future__ import annotations

import logging
import queue
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from app.backdrops import BACKDROPS
from app.photos import is_photo
from app.simthread.backlog import Backlog, group_melts
from app.simthread.clicks import Clicks
from sim import Params
from sim.io.session import DEFAULT_BACKDROP, weather_event
from sim.io.timeline import Applied, Timeline
from sim.look.geometry import GeometryDelta
from sim.weather import Glass, Reading

# Commands that change the frost, by the name a report gives them.
INPUT_NAMES = {"touch": "touches", "melt": "melts", "melts": "melts",
               "params": "parameter changes", "clear": "clears"}


@dataclass(frozen=True)
class Command:
    kind: str  # a key of Commands._handlers
    arg: Any = None


class Commands:
    """The commands waiting (`backlog`) and applied, and what they change beside the
    timeline: `paused`, the backdrop no event records; `handled` counts the commands
    applied so far as they were sent (a group of melts counts each)."""

    def __init__(self, timeline: Timeline, clicks: Clicks, backlog: Backlog,
                 export: Callable[[Any], None]):
        """`backlog`, where commands wait when more arrive than a tick takes (of
        `command_kind`); `export(folder)`, a map export asked for (the thread's writer's)."""
        self.timeline, self.clicks, self.backlog = timeline, clicks, backlog
        self.paused = False
        self.handled = 0  # applied (the first `handled` that `SimThread.send` sent)
        self.replaced = 0  # tuning changes replaced by the next before their tick
        # The backdrop shown where the session's rules record no backdrop events (older
        # versions replayed) or its name is not a backdrop's (a file given by path).
        self.unrecorded_backdrop: str | None = None
        self._handlers: dict[str, Callable[[Any, dict], None]] = {
            "touch": self._touch, "melt": self._melt, "melts": self._melts,
            "params": self._set_params, "clear": self._clear, "pause": self._pause,
            "step": self._single, "backdrop": self._show_backdrop, "weather": self._weather,
            "export": lambda folder, _notes: export(folder)}

    @property
    def backdrop(self) -> str | None:
        """The backdrop shown (None: the default)."""
        return self.unrecorded_backdrop or self.timeline.backdrop

    def run(self, arrived: list[Command], notes: dict) -> None:
        """At a tick: the commands `arrived` queued behind those waiting (a tuning change
        right behind another replaces it: a page or a held key can ask for hundreds, and
        each applied would regrow the frost), then those the backlog's room allows applied."""
        replaced = self.backlog.extend(group_melts(arrived, _disc, _melts), replaces=_superseded)
        self.handled += replaced
        self.replaced += replaced
        done = self.backlog.run(lambda command: self.apply(command, notes))
        self.handled += done  # (after the run: a group of melts added the rest of its own)

    def apply(self, command: Command, notes: dict) -> None:
        """`command` applied now; what it did noted in `notes["applied"]` (a group of
        melts adds the rest of its commands to `handled`; the caller counts one)."""
        self._handlers[command.kind](command.arg, notes)

    def apply_in_time(self, waiting: list[Command], seconds: float, notes: dict) -> list[Command]:
        """`waiting` applied in order until `seconds` have passed (the map exports left to
        their writer); what is left returned, oldest first."""
        deadline = time.perf_counter() + seconds
        left: list[Command] = []
        late = False  # (in order: once one is left for want of time, all after it are)
        for command in waiting:
            late = late or time.perf_counter() >= deadline
            if late or command.kind == "export":
                left.append(command)
                continue
            self.apply(command, notes)
            self.handled += 1  # (a group of melts added the rest of its commands)
        return left

    def said_at_the_end(self, left: list[Command]) -> list[tuple[int, str]]:
        """(logging level, text) of the end: the input `left` never applied (neither the
        frame nor the session holds it), the tuning changes replaced before their tick."""
        lost: Counter = Counter()
        for command in left:
            if command.kind in INPUT_NAMES:
                lost[INPUT_NAMES[command.kind]] += inputs(command)
        said = []
        if lost:
            said.append((logging.WARNING, "input still waiting at exit, never applied (not in "
                         "the session): " + ", ".join(f"{n} {k}" for k, n in lost.items())))
        if self.replaced:
            said.append((logging.INFO, f"{self.replaced} parameter changes were replaced by "
                         "the next before their tick (the session holds the later)"))
        return said

    def _touch(self, arg, notes: dict) -> None:
        (x, y), click = arg
        seed = len(self.timeline.sim.crystals)  # its seed's index, if it plants one
        notes["applied"].append(self.timeline.apply([{"kind": "touch", "x": x, "y": y}]))
        if click is not None and len(self.timeline.sim.crystals) > seed:  # (not full cells)
            self.clicks.planted(click, seed)

    def _melt(self, arg, notes: dict) -> None:
        x, y, r = arg
        notes["applied"].append(self.timeline.apply([{"kind": "melt", "x": x, "y": y, "r": r}]))

    def _melts(self, discs, notes: dict) -> None:
        """A fast drag's melts of one tick (`group_melts`): applied as one melt. (The
        group stands for that many commands sent: `handled` counts them all.)"""
        self.handled += len(discs) - 1
        notes["applied"].append(self.timeline.apply(
            [{"kind": "melt", "x": x, "y": y, "r": r} for x, y, r in discs]))

    def _set_params(self, params: Params, notes: dict) -> None:
        notes["applied"].append(self.timeline.apply([{"kind": "params", "params": params}]))

    def _clear(self, _arg, notes: dict) -> None:
        notes["applied"].append(self.timeline.apply([{"kind": "clear"}]))

    def _pause(self, _arg, _notes: dict) -> None:
        self.paused = not self.paused

    def _single(self, _arg, notes: dict) -> None:
        notes["single"] = True

    def _show_backdrop(self, name: str, notes: dict) -> None:
        if name == (self.backdrop or DEFAULT_BACKDROP):
            return
        if self.timeline.rules.backdrop_events and (name in BACKDROPS or is_photo(name)):
            self.unrecorded_backdrop = None
            notes["applied"].append(self.timeline.apply([{"kind": "backdrop", "name": name}]))
        else:
            self.unrecorded_backdrop = name

    def _weather(self, arg: tuple[Reading, Glass], notes: dict) -> None:
        """A reading of the weather outside, recorded as a weather event (a session
        replayed by rules older than version 12 records none: its frost grows as it did)."""
        reading, glass = arg
        if not self.timeline.rules.weather_events:
            notes["applied"].append(Applied(message="weather: a session of version "
                                            f"{self.timeline.version} grows without the weather"))
            return
        notes["applied"].append(self.timeline.apply([weather_event(reading, glass)]))


def inputs(command: Command) -> int:
    """The commands sent that `command` stands for (a group of melts: each)."""
    return len(command.arg) if command.kind == "melts" else 1


def _disc(command: Command):
    """A melt command's (x, y, r); None for other commands."""
    return command.arg if command.kind == "melt" else None


def _melts(commands: list[Command]) -> Command:
    """One command for a run of melts (`group_melts`)."""
    return Command("melts", tuple(c.arg for c in commands))


def take_all(q: queue.Queue) -> list:
    """Everything waiting in `q` now, oldest first, without blocking."""
    items = []
    while True:
        try:
            items.append(q.get_nowait())
        except queue.Empty:
            return items


def merged(applied: list[Applied]) -> tuple[bool, tuple[GeometryDelta, ...], str | None]:
    """One tick's results: a rebuild drops the melt deltas made before it."""
    reset, message = False, None
    melts: list[GeometryDelta] = []
    for a in applied:
        if a.reset:
            reset, melts = True, []
        melts.extend(a.deltas)
        message = a.message or message
    return reset, tuple(melts), message


def _superseded(waiting: Command, arriving: Command) -> bool:
    """`arriving` makes `waiting` moot: both set the whole parameters, nothing between."""
    return waiting.kind == arriving.kind == "params"


def command_kind(command: Command) -> str:
    return command.kind
