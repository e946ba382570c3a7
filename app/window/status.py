"""What the window says about itself: the HUD's stats and messages, a stats line in the
log every LOG_PERIOD, click latencies, and the summary at exit (no GL, no GLFW)."""

from __future__ import annotations

import logging
import statistics
import time
from collections import deque

from app.simthread.thread import Snapshot, Stats
from sim import Params, preset_name
from sim.weather import THAW_TICKS, Frost, event_frost, event_words
from sim.weather.glass import WORDS

log = logging.getLogger("app.window")

HUD_PERIOD = 0.25  # s between HUD stats refreshes
LOG_PERIOD = 2.0  # s between stats lines in the log
# The window draws the phone only when it changed: its frame rate is counted over the
# redraws of the last DRAW_WINDOW s, a gap longer than IDLE_GAP (nothing changed) left out,
# and it reads "idle" once no redraw came for IDLE_GAP.
DRAW_WINDOW = 2.0
IDLE_GAP = 0.5
MESSAGE_SECONDS = 4.0
# The HUD shows the last few messages (a parameter change and the rebuild it made come
# in the same frame): each for MESSAGE_SECONDS, the newest last.
MESSAGES_SHOWN = 3
# What the two click latencies of the log measure: the first frame showing the seed's
# frost, and the first frame showing a crystal that froze onto that seed.
LATENCY_NOTES = {"frost": "seed shown", "growth": "first crystal frozen onto the seed"}
NO_STATS = Stats(0, 0.0, 0, 0, 0.0, 0, False)


class DrawRate:
    """Frames per second while the phone is being redrawn (see DRAW_WINDOW)."""

    def __init__(self):
        self.times: deque[float] = deque()  # redraws of the last DRAW_WINDOW s

    def drew(self, now: float) -> None:
        self.times.append(now)
        while self.times[0] < now - DRAW_WINDOW:
            self.times.popleft()

    def fps(self, now: float) -> float | None:
        """None when idle: no redraw in the last IDLE_GAP s."""
        recent = [x for x in self.times if x >= now - DRAW_WINDOW]
        if not recent or now - recent[-1] > IDLE_GAP:
            return None
        gaps = [b - a for a, b in zip(recent, recent[1:], strict=False) if b - a <= IDLE_GAP]
        return len(gaps) / sum(gaps) if gaps and sum(gaps) > 0 else None


class Status:
    """Counts frames, times them, and words what the window shows."""

    def __init__(self):
        self.started = time.monotonic()
        self.frames = 0
        self.drawing = DrawRate()
        self.fps: float | None = None  # while drawing; None: idle
        self.messages: deque[tuple[str, float]] = deque(maxlen=MESSAGES_SHOWN)  # (text, until)
        self.latencies: list[tuple[str, int, float]] = []  # (kind, ticks, ms)
        self.clicks_pending: list[tuple[str, tuple[int, float], int]] = []
        self.drags: list[tuple[int, int, float]] = []  # right drags whose melts are not all shown
        self.drags_shown: list[tuple[int, float, int]] = []  # shown in the frame being made
        self.hud_next, self._log_next = 0.0, self.started + LOG_PERIOD
        self._log_since = self.started
        self.stats: list[str] = []  # the HUD's stats lines, refreshed every HUD_PERIOD

    def say(self, text: str, level: int = logging.INFO) -> None:
        """A message for the HUD (shown MESSAGE_SECONDS) and the log."""
        log.log(level, "%s", text)
        self.messages.append((text, time.monotonic() + MESSAGE_SECONDS))
        self.hud_next = 0.0

    def melted(self, last: int, melts: int, radius: float) -> None:
        """A right drag ended: `melts` melts, the last of them the thread's command `last`."""
        self.drags.append((last, melts, radius))

    def shown(self, snapshot: Snapshot) -> None:
        """A snapshot was applied: its clicks' latencies, and the right drags whose melts it
        completes, are logged with the next frame."""
        tick = snapshot.stats.tick
        self.clicks_pending.extend(("frost", c, tick) for c in snapshot.clicks)
        self.clicks_pending.extend(("growth", c, tick) for c in snapshot.grown)
        done = [d for d in self.drags if d[0] <= snapshot.stats.handled]
        self.drags = [d for d in self.drags if d[0] > snapshot.stats.handled]
        self.drags_shown.extend((melts, radius, tick) for _, melts, radius in done)

    def refresh(self, now: float, lines) -> None:
        """New HUD stats when they are due; `lines(now)` words them."""
        if now < self.hud_next:
            return
        self.fps = self.drawing.fps(now)
        self.stats = lines(now)
        self.hud_next = now + HUD_PERIOD

    def presented(self, now: float, lines) -> None:
        """A frame reached the screen: log the latencies it shows and, when due, a stats line."""
        self.frames += 1
        for kind, (click_tick, t_click), tick in self.clicks_pending:
            ms = (time.monotonic() - t_click) * 1000.0
            self.latencies.append((kind, tick - click_tick, ms))
            log.info("click-to-first-%s: %d ticks, %.1f ms (%s)", kind, tick - click_tick, ms,
                     LATENCY_NOTES[kind])
        self.clicks_pending = []
        for melts, radius, tick in self.drags_shown:
            log.info("warm finger: %d melts of radius %g px, all shown at tick %d", melts, radius, tick)
        self.drags_shown = []
        if now >= self._log_next:
            self._log_next, since, self._log_since = now + LOG_PERIOD, self._log_since, now
            log.info("stats (%.1f s): %s", now - since, "  ".join(lines(now)[:3]))

    def lines(self, now: float, snapshot: Snapshot | None, params: Params, view,
              recording: str | None, render_ms: float, panel: str | None = None) -> list[str]:
        """The HUD's stats: `params` and the stats of the snapshot shown (else `params`), the
        weather outside where it has one (its place and reading), the renderer's `view`
        switches, `recording` (e.g. "REC 12 frames") when on, the tuning
        panel's cost while it is shown (on the second line, which the log's lines keep)."""
        stats = snapshot.stats if snapshot else NO_STATS
        shown = snapshot.params if snapshot else params  # what the frame shows
        weather = snapshot.weather if snapshot is not None else None
        frost = event_frost(weather) if weather is not None else None
        state = [w for w in ("PAUSED" if stats.paused else None, recording) if w]
        if self.fps is not None:
            drawing = f"{self.fps:4.1f} fps"
        elif frost is not None and frost.thaw and stats.crystals and not stats.paused:
            # (a thaw takes a layer of tips every THAW_TICKS ticks: a redraw each, idle between)
            drawing = f"at each thaw step (the ice's edges melt every {THAW_TICKS} ticks)"
        else:
            drawing = "idle (nothing changed)"
        rate = "paused" if stats.paused else f"{stats.rate:4.1f} ticks/s"
        waiting = f"  input waiting {stats.waiting}" if stats.waiting else ""
        lines = [
            f"sim {rate}  tick median {stats.tick_median_ms:4.1f} ms  "
            f"overruns {stats.overruns}{waiting}",
            f"drawing {drawing}  render {render_ms:4.1f} ms" + (f"  {panel}" if panel else ""),
            f"tick {stats.tick}  crystals {stats.crystals}  water {stats.water}  "
            f"preset {preset_name(shown)}",
            params_line(shown, frost),
            f"look {shown.look}  features {onoff(view.show_features)}  "
            f"bumps {onoff(view.show_bumps)}  " + "light ({:.2f}, {:.2f}, {:.2f})".format(*view.light),
            "  ".join(state) or "running",
        ]
        if weather is not None:
            place, words = event_words(weather)
            lines.insert(4, f"weather {place}: {words}")
        lines += [text for text, until in self.messages if now < until]
        return lines + ["H help"]

    def summary(self, snapshot: Snapshot | None, renders: int, ticks: int, screenshots: int,
                exit_status: int) -> None:
        elapsed = max(time.monotonic() - self.started, 1e-9)
        stats = snapshot.stats if snapshot else NO_STATS
        latency = latency_summary(self.latencies)
        log.info("summary: %.1f s, %d frames (%.1f fps), %d phone renders, %d ticks "
                 "(%.1f ticks/s), %d overruns, %d screenshots, latency %s, exit status %d",
                 elapsed, self.frames, self.frames / elapsed, renders, ticks,
                 ticks / elapsed, stats.overruns, screenshots, latency, exit_status)


def latency_summary(latencies: list[tuple[str, int, float]]) -> str:
    """Per kind of click latency (LATENCY_NOTES): how many, the median and the worst."""
    parts = []
    for kind in LATENCY_NOTES:
        ms = sorted(m for k, _, m in latencies if k == kind)
        if ms:
            parts.append(f"{kind} {len(ms)} clicks median {statistics.median(ms):.0f} ms "
                         f"max {ms[-1]:.0f} ms")
    return ", ".join(parts) or "none"


def params_line(params: Params, weather: Frost | None = None) -> str:
    """The HUD's line of the parameters the keys change (the window's temperature in its
    look, as degrees below freezing: the weather's where it sets it, `weather` being what
    the weather does to the frost; None: no weather)."""
    if not params.window_frost:
        cold = ""
    elif weather is None:
        cold = f"  temperature -{params.temperature:g} C"
    elif weather.temperature is not None:
        cold = f"  temperature -{weather.temperature:.1f} C (the weather's)"
    else:  # (a thaw: nothing grows)
        cold = f"  temperature: none, {WORDS[weather.state]} (the weather's)"
    return (f"hc {params.hc:g}  D {params.D:g}  humidity {params.humidity}  "
            f"step {params.step:g}  bump {params.bump:g}  grow {onoff(params.grow)}{cold}")


def onoff(flag: bool) -> str:
    return "on" if flag else "off"
