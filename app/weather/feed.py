"""The weather beside a run: `Asker` asks for one reading (the place found once, each good
reading kept, the kept one used when the API fails and nothing better came this run),
`WeatherFeed` asks at the start and every `every_min` minutes on a thread of its own (its
own asyncio loop: no tick or frame ever waits on the network), and `read_once` is a
batch's one wait for its first reading (`frost render`)."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from sim.io.session import weather_event
from sim.weather import Glass, Reading, describe

from . import EVERY_MIN, FORECAST_API, GEOCODING_API, LEAST_EVERY_MIN, client
from .client import TIMEOUT_S, Place, WeatherError
from .kept import keep, kept

log = logging.getLogger(__name__)
FIRST_WAIT_S = 5.0  # how long a batch waits for its first reading

Say = Callable[[str], None]
KEPT_FROM = "going on with the reading kept from "  # a failure's line when the kept reading is used


class Asker:
    """Asks for the weather at one place (a `LAT,LON` or a name, geocoded once); `say(line)`
    hears each line for the user (the place found, a failure, the kept reading used). A
    reading, a place found or a failure that comes after the place moved (`move`) is the old
    place's: it is dropped, neither kept nor handed on (the feed asks at the new place)."""

    def __init__(self, place: str, say: Say, api: str = FORECAST_API,
                 geocoding_api: str = GEOCODING_API, folder: Path | None = None,
                 timeout_s: float = TIMEOUT_S):
        self.asked, self.say, self.api, self.geocoding_api = place.strip(), say, api, geocoding_api
        self.folder, self.timeout_s = folder, timeout_s
        self.place: Place | None = client.coordinates(self.asked)  # (ValueError: off the globe)
        self.had_one = False  # a reading of this place was handed on (then the kept one is not)
        self.last: Reading | None = None  # the last reading handed on, of any place: the frost's

    def move(self, latitude: float, longitude: float) -> None:
        """Ask at (latitude, longitude) from now on (rounded as sent)."""
        self.place = client.at(latitude, longitude)
        self.asked, self.had_one = self.place.name, False

    async def ask(self) -> Reading | None:
        """A reading now: the API's, else (the first time) the one kept for this place; None
        when there is neither, or the place moved while it was asked."""
        asked, place = self.asked, self.place
        try:
            async with _session() as session:
                if place is None:
                    place = await client.find(session, self.geocoding_api, asked, self.timeout_s)
                    if self.asked != asked:
                        return None
                    self.place = place
                    self.say(f"weather: {place.words()}")
                reading = await client.current(session, self.api, place, self.timeout_s)
        except WeatherError as err:
            return None if self.asked != asked else self.failed(str(err))
        if self.asked != asked:  # (moved while asking: the reading is another place's)
            log.info("weather: a reading of %s came after the place moved: dropped", asked)
            return None
        self.had_one, self.last = True, reading
        keep(asked, reading, self.folder)
        return reading

    def failed(self, why: str) -> Reading | None:
        """No reading came (`why`): said in one line with what the frost goes on with: the
        last reading of this place, else the one kept for it (returned), else the last
        reading of the place before a move, else the preset's own temperature."""
        found = None if self.had_one else kept(self.asked, self.folder)
        if found is not None:
            self.had_one, self.last = True, found[0]
            self.say(f"weather: {why}: {KEPT_FROM}{found[1]}")
            return found[0]
        if self.last is None:
            goes_on = "the frost grows by the preset's own temperature"
        elif self.had_one:
            goes_on = "the frost goes on with the last reading"
        else:
            goes_on = f"the frost goes on with the last reading, of {self.last.place}"
        self.say(f"weather: {why}: {goes_on}")
        return None


def _session():
    import aiohttp  # (here: a run without --weather never loads it)
    return aiohttp.ClientSession()


class WeatherFeed:
    """Readings at the start and every `every_min` minutes, on a thread of its own:
    `on_reading(reading)` for each, `on_problem(line)` for each line to tell the user (a
    failure: the frost goes on with what it has). Both are called on the feed's thread."""

    def __init__(self, asker: Asker, on_reading: Callable[[Reading], None],
                 every_min: float = EVERY_MIN):
        if not every_min >= LEAST_EVERY_MIN:
            raise ValueError(f"--weather-every {every_min:g}: at least {LEAST_EVERY_MIN:g} minutes")
        self.asker, self.on_reading, self.every_s = asker, on_reading, every_min * 60.0
        self._loop = asyncio.new_event_loop()
        self._wake = asyncio.Event()
        self._stopping = False
        self._thread = threading.Thread(target=self._run, name="weather", daemon=True)

    @classmethod
    def at_place(cls, place: str, on_reading: Callable[[Reading], None], on_problem: Say,
                 every_min: float = EVERY_MIN, **asking) -> WeatherFeed:
        """A feed for `place` (`Asker`'s keywords: api, geocoding_api, folder, timeout_s)."""
        return cls(Asker(place, on_problem, **asking), on_reading, every_min)

    def start(self) -> WeatherFeed:
        self._thread.start()
        return self

    def set_place(self, latitude: float, longitude: float) -> None:
        """Read the weather at (latitude, longitude) from now on, asking at once."""
        self._loop.call_soon_threadsafe(self._move, latitude, longitude)

    def ask_now(self) -> None:
        """Ask at once (the next reading comes `every_min` minutes after it)."""
        self._loop.call_soon_threadsafe(self._wake.set)

    def stop(self, wait_s: float = TIMEOUT_S + 1.0) -> None:
        """Stop asking (a request under way is given up); waits for the thread."""
        if self._thread.is_alive():
            self._loop.call_soon_threadsafe(self._end)
            self._thread.join(wait_s)

    def _move(self, latitude: float, longitude: float) -> None:
        self.asker.move(latitude, longitude)
        self._wake.set()

    def _end(self) -> None:
        self._stopping = True
        for task in asyncio.all_tasks(self._loop):
            task.cancel()

    def _run(self) -> None:
        try:
            self._loop.run_until_complete(self._every())
        except asyncio.CancelledError:
            pass
        finally:
            self._loop.close()

    async def _every(self) -> None:
        while not self._stopping:
            reading = await self.asker.ask()
            if reading is not None:
                self._hand_on(reading)
            with contextlib.suppress(asyncio.TimeoutError):  # (the time to ask again)
                await asyncio.wait_for(self._wake.wait(), self.every_s)
            self._wake.clear()

    def _hand_on(self, reading: Reading) -> None:
        try:
            self.on_reading(reading)
        except Exception:  # (a consumer's bug must not end the readings)
            log.exception("weather: the reading could not be handed on")


def glass_of(args) -> Glass:
    """The window the weather acts on, as the command line states it."""
    return Glass(args.glazing, args.room_temperature, args.room_humidity)


def feed_for(args, show: Callable[[Reading, Glass], object], say: Say) -> WeatherFeed | None:
    """--weather's feed for a run that goes on (the window, frost serve), started: each
    reading said in one line (`describe`) and handed to `show(reading, glass)`, e.g.
    SimThread.show_weather; None without --weather."""
    if not getattr(args, "weather", None):
        return None
    glass = glass_of(args)

    def on_reading(reading: Reading) -> None:
        say(describe(reading, glass))
        show(reading, glass)

    return WeatherFeed.at_place(args.weather, on_reading, say, args.weather_every,
                                api=args.weather_api, geocoding_api=args.geocoding_api).start()


def first_event(args, say: Say, wait_s: float = FIRST_WAIT_S) -> list[dict[str, Any]]:
    """A batch's --weather (`frost render`): its first reading as a weather event at tick 0
    (at most `wait_s` seconds for the API, else the kept reading), its line said; [] when
    there is none (said: the frost grows by the preset's temperature) or no --weather."""
    if not getattr(args, "weather", None):
        return []
    glass = glass_of(args)
    lines: list[str] = []
    reading = read_once(Asker(args.weather, lines.append, args.weather_api, args.geocoding_api), wait_s)
    if reading is not None:
        read = describe(reading, glass)
        # A failure that fell back on the kept reading and that reading are one line.
        if lines and KEPT_FROM in lines[-1]:
            lines[-1] += ": " + read.removeprefix("weather: ")
        else:
            lines.append(read)
    for line in lines:
        say(line)
    return [] if reading is None else [weather_event(reading, glass)]


def read_once(asker: Asker, wait_s: float = FIRST_WAIT_S) -> Reading | None:
    """A batch's first reading: at most `wait_s` seconds for the API (then the kept one)."""
    async def bounded() -> Reading | None:
        try:
            return await asyncio.wait_for(asker.ask(), wait_s)
        except asyncio.TimeoutError:
            return asker.failed(f"no reading within {wait_s:g} s")
    return asyncio.run(bounded())
