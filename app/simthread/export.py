"""Frost maps exported from the simulation thread: the arrays are copied at the tick the
snapshot shows, the PNGs written by a worker so the thread's schedule does not slip."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from app.images import export_maps, frost_meta
from sim.io.files import why
from sim.io.timeline import Timeline
from sim.look.maps import live_segments, map_triangles

Notify = Callable[[int, str], None]


def export_now(folder, timeline: Timeline, seed: int, notify: Notify) -> threading.Thread:
    """Start writing the frost maps of `timeline`'s current tick into `folder`: its
    arrays, parameters, touches and tick are copied here; success or failure goes to
    `notify(level, text)`. Returns the (started) worker."""
    sim = timeline.sim
    grid, segments = timeline.geometry.heights.copy(), live_segments(sim).copy()
    meta = frost_meta("window, key E", timeline.params, seed, sim.tick, timeline.touch_ticks())
    job = (folder, grid, segments, timeline.params, meta, notify,
           map_triangles(sim, timeline.params))
    worker = threading.Thread(target=write_maps, args=job, name="frost-maps")
    worker.start()
    return worker


def write_maps(folder, grid, segments, params, meta, notify: Notify, triangles=None) -> None:
    """The export worker: success or failure goes to `notify`, nothing dies silently."""
    try:
        paths = export_maps(folder, grid, segments, params, meta, triangles=triangles)
    except OSError as err:
        notify(logging.WARNING, f"frost maps NOT written: {why(err, folder)}")
        return
    notify(logging.INFO, "frost maps written: " + ", ".join(str(p) for p in paths.values()))


class MapExports:
    """The map exports asked for: each written at the tick after it was asked (the tick the
    snapshot then shows), by a worker; `finish` writes those still asked for at the end."""

    def __init__(self, notify: Notify):
        self.notify = notify
        self.asked: list = []  # folders asked for in the tick being made
        self.writers: list[threading.Thread] = []

    def ask(self, folder) -> None:
        self.asked.append(folder)

    def write_asked(self, timeline: Timeline, seed: int) -> None:
        """The folders asked for in this tick, written from its timeline's state now."""
        asked, self.asked = self.asked, []
        for folder in asked:
            self.writers.append(export_now(folder, timeline, seed, self.notify))

    def finish(self, folders, timeline: Timeline | None, seed: int) -> None:
        """`folders` asked for but never taken by a tick: written from `timeline` (the
        last tick's; None: a tick was still running, so reported not written), then
        every writer waited for."""
        for folder in folders:
            if timeline is None:
                self.notify(logging.WARNING, f"frost maps NOT written: {folder}: the "
                            "simulation did not stop")
            else:
                self.writers.append(export_now(folder, timeline, seed, self.notify))
        for writer in self.writers:
            writer.join()
