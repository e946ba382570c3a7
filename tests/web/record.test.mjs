// The phone's session record (app/web/local/record.js): a rebuild (a preset) schedules the
// touches so far again as sim/io/timeline.py's `regrow` does (the oracle, run through the
// checkout's Python): the first at tick 0, each later one after the pause it followed,
// a pause longer than REGROW_GAP shortened to it, a shorter one kept; melts at their ticks.

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import path from "node:path";
import { test } from "node:test";
import { fileURLToPath } from "node:url";

import { REGROW_GAP, SessionRecord } from "../../app/web/local/record.js";

const ROOT = process.env.FROST_ROOT ?? path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
const PYTHON = process.env.FROST_PYTHON ?? path.join(ROOT, ".venv/bin/python");

const CONFIG = JSON.parse(readFileSync(path.join(ROOT, "app/web/local/params.json"), "utf-8"));

// sim/'s regrow of `touches` ({tick, ...} in tick order) with the gap of the phone's
// session version: [the gap, the touches regrown].
function simRegrow(touches) {
  const script = [
    "import json, sys",
    "from sim.core.versions import rules_of",
    "from sim.io.timeline import regrow",
    `gap = rules_of(${CONFIG.session.version}).regrow_gap`,
    "print(json.dumps([gap, regrow(json.load(sys.stdin), gap)]))",
  ].join("\n");
  return JSON.parse(execFileSync(PYTHON, ["-c", script], { cwd: ROOT, input: JSON.stringify(touches),
    env: { ...process.env, PYTHONPATH: ROOT } }).toString());
}

test("a rebuild plants the touches again with their pauses shortened to REGROW_GAP, as sim/", () => {
  const record = new SessionRecord(CONFIG.session, 1, { hc: 2 }, [760, 1280]);
  // pauses of 2, 1, 30, 12, 13, 0 and 400 ticks; a melt between
  const ticks = [5, 7, 8, 38, 50, 63, 63, 463];
  ticks.forEach((tick, i) => {
    record.add({ kind: "touch", tick, x: 10 + i, y: 20 + i });
    if (i === 3) record.add({ kind: "melt", tick, x: 300, y: 400, r: 25 });
  });
  const again = record.rebuild(470, { hc: 3 });

  const [gap, want] = simRegrow(ticks.map((tick, i) => ({ kind: "touch", tick, x: 10 + i, y: 20 + i })));
  assert.equal(REGROW_GAP, gap);
  const touches = again.filter((e) => e[1] === "touch");
  assert.deepEqual(touches, want.map((e) => [e.tick, "touch", e.x, e.y, 0]));
  // by hand: 0, +2, +1, +12 (30), +12, +12 (13), +0, +12 (400)
  assert.deepEqual(touches.map((e) => e[0]), [0, 2, 3, 15, 27, 39, 39, 51]);
  assert.deepEqual(again.filter((e) => e[1] === "melt"), [[38, "melt", 300, 400, 25]]);
  // in tick order, and the record's touches are the new timeline's (a second rebuild's start)
  assert.deepEqual(again.map((e) => e[0]), again.map((e) => e[0]).sort((a, b) => a - b));
  assert.deepEqual(record.touches.map((t) => t.tick), [0, 2, 3, 15, 27, 39, 39, 51]);
  assert.deepEqual(record.events.at(-1), { kind: "params", tick: 470, params: { hc: 3 } });
});
