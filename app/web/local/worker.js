// The phone's own frost in a Web Worker (a tick never delays a frame): LocalRun stepped 25
// times a second, each tick timed here (a dedicated worker is not slowed by the page's
// CPU throttling, so the page states these figures), and the page's messages in.
//
// Page -> worker: {type: "start", config (params.json), start}, then each input message
// as the page sends frost serve ({type: "touch", ...}), and {type: "session"} /
// {type: "meta"} / {type: "resync"}; {type: "hold"} (the page joined frost serve: the frost
// waits, kept, and still answers "session") and {type: "resume"} (no server again: it goes
// on from where it was, a hello and its snapshot first). Worker -> page: frost serve's
// messages (a string of JSON, or an ArrayBuffer of the binary protocol), {type: "stats",
// tick, crystals, ticksPerSecond, tickP99Ms, tickMedianMs, dropped}, {type: "session" |
// "meta", data}, {type: "resumed"} (before a resume's hello), and {type: "failed", reason}
// where the frost cannot run.

import { LocalRun, warmUp } from "./run.js";
import { TickClock, TICK_MS } from "./clock.js";

const STATS_EVERY = 5;   // ticks between two stats messages (5 a second)
const MOST_BEHIND = 3;   // ticks run back to back to catch up; beyond, the clock starts anew

let run = null;
const clock = new TickClock();
let next = 0;      // when the next tick is due (performance.now())
let ticks = 0;
let timer = 0;     // the loop's next call
let held = false;  // the page joined frost serve: no ticks until it resumes

function post(message, transfer = []) {
  self.postMessage(message, transfer);
}

function loop() {
  let now = performance.now();
  if (now - next > MOST_BEHIND * TICK_MS) next = now;  // (asleep, or a tick far too slow)
  while (next <= now) {
    const start = performance.now();
    let stepped;
    try {
      stepped = run.tick();
    } catch (err) {
      console.error(err);
      return post({ type: "failed", reason: String(err && err.message || err) });
    }
    if (stepped) {
      clock.record(start, performance.now());
      ticks += 1;
      if (ticks % STATS_EVERY === 0) stats();
    }
    next += TICK_MS;
    now = performance.now();
  }
  timer = setTimeout(loop, Math.max(0, next - performance.now()));
}

function stats() {
  post({ type: "stats", ...run.stats(),
    ticksPerSecond: clock.perSecond(performance.now()), tickP99Ms: clock.p99(),
    tickMedianMs: clock.percentile(0.5) });
}

self.onmessage = (event) => {
  const m = event.data;
  try {
    if (m.type === "start") {
      if (run) return;
      warmUp(m.config);
      run = new LocalRun(m.config, post, m.start);
      run.hello();
      next = performance.now() + TICK_MS;
      timer = setTimeout(loop, TICK_MS);
    } else if (!run) {
      return;
    } else if (m.type === "hold") {
      held = true;
      clearTimeout(timer);
    } else if (m.type === "resume") {
      if (!held) return;
      held = false;
      post({ type: "resumed" });
      run.hello();
      stats();
      next = performance.now() + TICK_MS;
      timer = setTimeout(loop, TICK_MS);
    } else if (m.type === "session") {
      post({ type: "session", data: run.session() });
    } else if (m.type === "meta") {
      post({ type: "meta", data: run.meta() });
    } else if (m.type === "resync") {
      run.snapshot();
    } else {
      run.input(m);
      if (m.type === "clear" || m.type === "pause") stats();
    }
  } catch (err) {
    console.error(err);
    post({ type: "failed", reason: String(err && err.message || err) });
  }
};

// (a module that fails to load never runs this file: the page hears it as an error event)
