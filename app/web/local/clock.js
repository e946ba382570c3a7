// The worker's own clock of its ticks: each tick's duration (the last 250 kept, for their
// 99th percentile) and when each ended (the last 5 s, for the ticks done a second). A
// dedicated worker is not slowed by the page's CPU throttling, so it times itself.

import { TICK_MS } from "./shared.js";
export { TICK_MS };  // 25 ticks a second, as frost serve's simulation thread
export const RECENT = 250;      // durations kept for the p99
export const RATE_MS = 5000;    // ticks a second: those that ended in the last 5 s, / 5

export class TickClock {
  constructor() {
    this.durations = new Float64Array(RECENT);
    this.kept = 0;     // durations held (up to RECENT)
    this.at = 0;       // where the next duration goes
    this.ends = new Float64Array(256);  // end times, a ring (25 a second for 5 s fit)
    this.endAt = 0;
    this.sorted = new Float64Array(RECENT);  // (the p99's scratch: no allocation a tick)
  }

  // A tick that ran from `start` to `end` (ms, performance.now()).
  record(start, end) {
    this.durations[this.at] = end - start;
    this.at = (this.at + 1) % RECENT;
    this.kept = Math.min(this.kept + 1, RECENT);
    this.ends[this.endAt] = end;
    this.endAt = (this.endAt + 1) % this.ends.length;
  }

  // The 99th percentile (nearest rank) of the durations kept, ms; 0 before any.
  p99() {
    return this.percentile(0.99);
  }

  // The `q` quantile (nearest rank) of the durations kept, ms; 0 before any.
  percentile(q) {
    if (this.kept === 0) return 0;
    const s = this.sorted.subarray(0, this.kept);
    s.set(this.durations.subarray(0, this.kept));
    s.sort();
    return s[Math.max(0, Math.ceil(q * this.kept) - 1)];
  }

  // Ticks that ended in the RATE_MS before `now`, a second.
  perSecond(now) {
    let n = 0;
    for (const end of this.ends) if (end > 0 && end > now - RATE_MS && end <= now) n += 1;
    return n / (RATE_MS / 1000);
  }
}
