// The worker's tick clock (app/web/local/clock.js) on a clock of whole milliseconds, as
// Safari's and every iPhone browser's performance.now() is (WebKit coarsens it to 1 ms):
// its p99 and median still bound the ticks' true durations within the clock's step, and
// its ticks a second are the ticks'. (tests/test_webkit_e2e.py reads them in WebKit.)

import assert from "node:assert/strict";
import { test } from "node:test";

import { TickClock, TICK_MS } from "../../app/web/local/clock.js";

// A tick every 40 ms for `seconds`, each lasting `duration()` ms, starting at a fraction of
// a millisecond that drifts (a timer never fires on the millisecond), timed by a clock of
// whole ms: what the worker records on WebKit.
function coarseRun(duration, seconds = 12) {
  const clock = new TickClock();
  let seed = 7;
  const random = () => ((seed = (seed * 48271) % 2147483647) / 2147483647);
  let last = 0;
  for (let i = 0; i < seconds * 1000 / TICK_MS; i++) {
    const start = 1000 + i * TICK_MS + random() * 3;
    const end = start + duration(random);
    clock.record(Math.floor(start), Math.floor(end));
    last = Math.floor(end);
  }
  return { clock, now: last };
}

test("on a 1 ms clock, a frost's ticks of 2 to 3 ms read a p99 of 3 and a median of 2 or 3", () => {
  const { clock, now } = coarseRun((random) => 2 + random());
  assert.equal(clock.p99(), 3);
  assert.ok([2, 3].includes(clock.percentile(0.5)), String(clock.percentile(0.5)));
  assert.equal(clock.perSecond(now), 25);
});

test("on a 1 ms clock, ticks far under a millisecond read a p99 of at most 1, never less than 0", () => {
  const { clock, now } = coarseRun(() => 0.2);
  // a fifth of them cross a millisecond's edge: the p99 reads one step, the median none
  assert.equal(clock.p99(), 1);
  assert.equal(clock.percentile(0.5), 0);
  assert.equal(clock.perSecond(now), 25);
});
