// The phone's own frost as its Web Worker runs it (app/web/local/run.js, fingers.js,
// clock.js, record.js), in Node without the worker: bad input changes nothing, a storm
// of taps is bounded, the worker's figures are what a hand count gives, and the session
// it records is one that sim/ reads and replays (tests/support's Python, FROST_PYTHON).

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import path from "node:path";
import { test } from "node:test";
import { fileURLToPath } from "node:url";

import { LocalRun } from "../../app/web/local/run.js";
import { TickClock, RECENT } from "../../app/web/local/clock.js";
import { PENDING_MOST } from "../../app/web/local/fingers.js";

const ROOT = process.env.FROST_ROOT ?? path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
const PYTHON = process.env.FROST_PYTHON ?? path.join(ROOT, ".venv/bin/python");
const CONFIG = JSON.parse(readFileSync(path.join(ROOT, "app/web/local/params.json"), "utf-8"));

// A run of seed 1 that keeps every message it posts (text as is, bytes as hex).
function newRun(start = {}) {
  const sent = [];
  const run = new LocalRun(CONFIG, (m) => sent.push(typeof m === "string" ? m : Buffer.from(m).toString("hex")),
    { seed: 1, ...start });
  run.hello();
  return { run, sent };
}

const down = (x, y, id = 0, type = "touch") => ({ type, phase: "down", id, x, y });

test("a touch off the pane, or not a number, changes nothing", () => {
  const good = newRun(), bad = newRun();
  for (const r of [good, bad]) r.run.input(down(380, 640));
  for (const m of [down(NaN, 640), down(380, Infinity), down(760, 100), down(-0.5, 100), down(10, 1280),
    down("380", 640), down(null, null), { type: "touch", phase: "move", id: 0, x: NaN, y: 5 },
    down(NaN, 3, 1, "melt"), { type: "touch" }, { type: 7 }, null, "touch", { type: "preset", name: "nope" }]) {
    bad.run.input(m);
  }
  for (let i = 0; i < 40; i++) {
    good.run.tick();
    bad.run.tick();
  }
  assert.ok(good.run.frost.count > 10, "the good touch grew");
  assert.equal(bad.run.frost.count, good.run.frost.count);
  assert.deepEqual(bad.run.frost.crystals.subarray(0, 2 * bad.run.frost.count),
    good.run.frost.crystals.subarray(0, 2 * good.run.frost.count));
  assert.deepEqual(bad.run.session().events, good.run.session().events);
  // the same bytes to the page, but for the one notice the unknown preset brought
  assert.deepEqual(bad.sent.filter((m) => !m.startsWith("{\"type\":\"notice\"") && !m.startsWith("{\"type\":\"state\"")),
    good.sent);
});

test("a storm of taps waits at most PENDING_MOST and the ticks go on", () => {
  const { run } = newRun();
  for (let i = 0; i < 2000; i++) run.input(down(40 + (i * 37) % 680, 40 + (i * 91) % 1200, i % 32));
  assert.equal(run.fingers.pending.length, PENDING_MOST);
  assert.equal(run.fingers.dropped, 2000 - PENDING_MOST);
  // 2 000 taps in 10 s (250 ticks): 8 a tick, each tick takes them all
  const second = newRun().run;
  for (let t = 0; t < 250; t++) {
    for (let k = 0; k < 8; k++) second.input(down(40 + ((8 * t + k) * 37) % 680, 40 + ((8 * t + k) * 91) % 1200, k));
    assert.ok(second.tick());
    assert.equal(second.fingers.pending.length, 0);
  }
  assert.equal(second.frost.tick, 250);
  assert.equal(second.fingers.dropped, 0);
  assert.equal(second.session().events.filter((e) => e.kind === "touch").length, 2000);
});

test("a drag leaves a touch every drag_spacing_hc x hc px, as the window's", () => {
  const { run } = newRun();
  run.input(down(100, 100));
  run.input({ type: "touch", phase: "move", id: 0, x: 100 + 95, y: 100 });
  run.input({ type: "touch", phase: "up", id: 0 });
  const spacing = CONFIG.drag_spacing_hc * CONFIG.presets.fern.hc;  // 28 px: 95 px holds 3
  assert.deepEqual(run.fingers.pending.map(([, x, y]) => [x, y]),
    [[100, 100], [100 + spacing, 100], [100 + 2 * spacing, 100], [100 + 3 * spacing, 100]]);
});

test("the clock's p99 and ticks a second, counted by hand", () => {
  const clock = new TickClock();
  assert.equal(clock.p99(), 0);
  const hundred = new TickClock();
  for (let i = 100; i >= 1; i--) hundred.record(0, i);  // durations 100 .. 1: the 99th is 99
  assert.equal(hundred.p99(), 99);
  assert.equal(hundred.percentile(0.5), 50);
  for (let i = 1; i <= 300; i++) clock.record(1000 * i, 1000 * i + (i % RECENT) + 1);
  // the last 250 durations are 51..250 and 1..50 (i = 51..300): their p99 (nearest rank,
  // the 248th of 250) is 248
  assert.equal(clock.p99(), 248);
  const rate = new TickClock();
  for (let i = 0; i < 40; i++) rate.record(0, 10000 + 40 * i);  // 40 ticks ending 10 000 .. 11 560
  assert.equal(rate.perSecond(11560), 40 / 5);
  assert.equal(rate.perSecond(15100), 37 / 5);  // those at 10 000, 10 040, 10 080 are over 5 s old
});

test("the phone's session is one that sim/ reads and replays", () => {
  const { run } = newRun();
  run.input(down(380, 640));
  for (let i = 0; i < 20; i++) run.tick();
  run.input(down(200, 300, 1, "melt"));
  run.input({ type: "backdrop", name: "dusk" });
  run.tick();
  run.input({ type: "preset", name: "c-2" });
  for (let i = 0; i < 5; i++) run.tick();
  run.input({ type: "look", name: "glass" });
  run.input(down(500, 900));
  for (let i = 0; i < 5; i++) run.tick();
  run.input({ type: "clear" });
  run.input(down(300, 300));
  for (let i = 0; i < 5; i++) run.tick();
  const session = run.session();
  assert.equal(session.source, "phone");
  assert.deepEqual(session.events.map((e) => [e.kind, e.tick]),
    // (the backdrop applies as it comes, the melt before the next tick: both at tick 20)
    [["touch", 0], ["backdrop", 20], ["melt", 20], ["params", 21], ["params", 5], ["touch", 5], ["clear", 10], ["touch", 0]]);
  const script = [
    "import json, sys",
    "from sim.io.session import SessionLog",
    "from sim.io.timeline import replay",
    "log_ = SessionLog.from_json(json.load(sys.stdin))",
    "t = replay(log_)",
    "print(json.dumps([log_.source, log_.version, len(log_.events), t.sim.tick]))",
  ].join("\n");
  const out = execFileSync(PYTHON, ["-c", script], { cwd: ROOT, input: JSON.stringify(session),
    env: { ...process.env, PYTHONPATH: ROOT } }).toString();
  assert.deepEqual(JSON.parse(out), ["phone", CONFIG.session.version, 8, 5]);
});

test("the window's keys do on the phone what frost serve does with them", () => {
  const { run, sent } = newRun();
  run.input(down(380, 640));
  run.tick();
  run.input({ type: "key", name: "SPACE" });
  assert.equal(run.paused, true);
  assert.equal(run.tick(), false);  // paused: no tick
  run.input({ type: "key", name: "N" });  // one tick while paused
  run.input({ type: "key", name: "PERIOD" });
  assert.equal(run.frost.tick, 3);
  run.input({ type: "key", name: "C" });
  assert.equal(run.frost.count, 0);
  run.input({ type: "key", name: "F" });
  assert.match(sent.at(-1), /key F: not on this phone/);
  assert.deepEqual(CONFIG.keys, { SPACE: "pause", N: "step", PERIOD: "step", C: "clear" });
});
