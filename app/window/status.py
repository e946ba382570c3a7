"""What the window says about itself: the HUD's stats and messages, a stats line in the
log every LOG_PERIOD, click latencies, and the summary at exit (no GL, no GLFW)."""

from __future__ import annotations

import logging
import statistics
import time

from app.simthread.thread import Snapshot, Stats
from sim import Params, preset_name

log = logging.getLogger("app.window")

HUD_PERIOD = 0.25  # s between HUD stats refreshes
LOG_PERIOD = 2.0  # s between stats lines in the log
FPS_PERIOD = 0.5  # s over which the HUD's fps is counted
MESSAGE_SECONDS = 4.0
# What the two click latencies of the log measure: the first frame showing the seed's
# frost, and the first frame showing a crystal that froze onto that seed.
LATENCY_NOTES = {"frost": "seed shown", "growth": "first crystal frozen onto the seed"}
NO_STATS = Stats(0, 0.0, 0, 0, 0.0, 0, False)


class Status:
    """Counts frames, times them, and words what the window shows."""

    def __init__(self):
        self.started = time.monotonic()
        self.frames, self.fps = 0, 0.0
        self.frame_ms = 0.0  # render + present, moving average
        self.message, self.message_until = "", 0.0
        self.latencies: list[tuple[str, int, float]] = []  # (kind, ticks, ms)
        self.clicks_pending: list[tuple[str, tuple[int, float], int]] = []
        self.drags: list[tuple[int, int, float]] = []  # right drags whose melts are not all shown
        self.drags_shown: list[tuple[int, float, int]] = []  # shown in the frame being made
        self.hud_next, self._log_next = 0.0, self.started + LOG_PERIOD
        self._fps_mark = self._log_mark = (0, self.started)
        self.stats: list[str] = []  # the HUD's stats lines, refreshed every HUD_PERIOD

    def say(self, text: str, level: int = logging.INFO) -> None:
        """A message for the HUD (shown MESSAGE_SECONDS) and the log."""
        log.log(level, "%s", text)
        self.message, self.message_until = text, time.monotonic() + MESSAGE_SECONDS
        self.hud_next = 0.0

    def melted(self, last: int, melts: int, radius: float) -> None:
        """A right drag ended: `melts` melts, the last of them the thread's command `last`."""
        self.drags.append((last, melts, radius))

    def shown(self, snap: Snapshot) -> None:
        """A snapshot was applied: its clicks' latencies, and the right drags whose melts it
        completes, are logged with the next frame."""
        tick = snap.stats.tick
        self.clicks_pending.extend(("frost", c, tick) for c in snap.clicks)
        self.clicks_pending.extend(("growth", c, tick) for c in snap.grown)
        done = [d for d in self.drags if d[0] <= snap.stats.handled]
        self.drags = [d for d in self.drags if d[0] > snap.stats.handled]
        self.drags_shown.extend((melts, radius, tick) for _, melts, radius in done)

    def refresh(self, now: float, lines) -> None:
        """New HUD stats when they are due; `lines(now)` words them."""
        if now < self.hud_next:
            return
        frames, since = self._fps_mark
        if now - since >= FPS_PERIOD:
            self.fps = (self.frames - frames) / (now - since)
            self._fps_mark = (self.frames, now)
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
            self._log_next = now + LOG_PERIOD
            frames, since = self._log_mark
            self._log_mark = (self.frames, now)
            log.info("stats: %.1f fps over %.1f s  %s", (self.frames - frames) / (now - since),
                     now - since, "  ".join(lines(now)[:3]))

    def timed(self, seconds: float) -> None:
        self.frame_ms = 0.9 * self.frame_ms + 100.0 * seconds

    def lines(self, now: float, snap: Snapshot | None, params: Params, view, recording: str | None,
              render_ms: float) -> list[str]:
        """The HUD's stats: `params` and the stats of the snapshot shown (else `params`), the
        renderer's `view` switches, `recording` (e.g. "REC 12 frames") when on."""
        s = snap.stats if snap else NO_STATS
        p = snap.params if snap else params  # what the frame shows
        state = [w for w in ("PAUSED" if s.paused else None, recording) if w]
        lines = [
            f"fps {self.fps:5.1f}  frame {self.frame_ms:5.1f} ms  render {render_ms:5.1f} ms",
            f"tick {s.tick}  {s.tick_ms:5.1f} ms  rate {s.rate:4.1f}/s  overruns {s.overruns}",
            f"crystals {s.crystals}  water {s.water}  preset {preset_name(p)}",
            f"hc {p.hc:g}  D {p.D:g}  humidity {p.humidity}  step {p.step:g}  bump {p.bump:g}  "
            f"grow {onoff(p.grow)}",
            f"look {p.look}  features {onoff(view.show_features)}  bumps {onoff(view.show_bumps)}  "
            "light ({:.2f}, {:.2f}, {:.2f})".format(*view.light),
            "  ".join(state) or "running",
        ]
        if now < self.message_until:
            lines.append(self.message)
        return lines + ["H help"]

    def summary(self, snap: Snapshot | None, renders: int, ticks: int, screenshots: int,
                exit_status: int) -> None:
        elapsed = max(time.monotonic() - self.started, 1e-9)
        s = snap.stats if snap else NO_STATS
        lat = latency_summary(self.latencies)
        log.info("summary: %.1f s, %d frames (%.1f fps), %d phone renders, %d ticks "
                 "(%.1f ticks/s), %d overruns, %d screenshots, latency %s, exit status %d",
                 elapsed, self.frames, self.frames / elapsed, renders, ticks,
                 ticks / elapsed, s.overruns, screenshots, lat, exit_status)


def latency_summary(latencies: list[tuple[str, int, float]]) -> str:
    """Per kind of click latency (LATENCY_NOTES): how many, the median and the worst."""
    parts = []
    for kind in LATENCY_NOTES:
        ms = sorted(m for k, _, m in latencies if k == kind)
        if ms:
            parts.append(f"{kind} {len(ms)} clicks median {statistics.median(ms):.0f} ms "
                         f"max {ms[-1]:.0f} ms")
    return ", ".join(parts) or "none"


def onoff(flag: bool) -> str:
    return "on" if flag else "off"
