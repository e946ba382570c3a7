// The page's simulation keeps its objects' shapes as it grows (app/web/local): the worker
// grows a frost of its own before its hello (run.js warmUp) so that the engine compiles
// the tick first, and that compiled code fits the next frost only where its objects have
// the shapes the warm-up's had. A field added after the constructor, or one that held a
// small integer first and a fraction later, gives a frost made before the growth another
// shape than one made after it: the engine's own verdict (%HaveSameMap) is the oracle.

import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import path from "node:path";
import { test } from "node:test";
import { fileURLToPath } from "node:url";
import v8 from "node:v8";

import { seeded } from "../../app/web/local/random.js";
import { LocalRun } from "../../app/web/local/run.js";

const ROOT = process.env.FROST_ROOT ?? path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
const CONFIG = JSON.parse(readFileSync(path.join(ROOT, "app/web/local/params.json"), "utf-8"));
v8.setFlagsFromString("--allow-natives-syntax");
const sameShape = new Function("a", "b", "return %HaveSameMap(a, b);");
v8.setFlagsFromString("--no-allow-natives-syntax");

// The parts of a Frost and its geometry that a tick's compiled code reads.
function parts(run) {
  const f = run.frost;
  return { frost: f, ice: f.ice, areas: f.areas, water: f.water, index: f.index,
    candidates: f.index.candidates, budget: f.budget, growth: f.growth, placer: f.placer,
    supply: f.supply, geometry: run.geometry, grid: run.geometry.grid, encoder: run.encoder };
}

test("a frost made before another grows has the shapes of one made after", () => {
  const before = new LocalRun(CONFIG, () => {}, { seed: 3 });
  const grown = new LocalRun(CONFIG, () => {}, { seed: 1 });
  for (const [x, y] of [[380.37, 640.61], [200.52, 300.29], [560.73, 1000.18]]) {
    grown.input({ type: "touch", phase: "down", id: 0, x, y });
    grown.tick();
  }
  for (let i = 0; i < 80; i++) grown.tick();
  const after = new LocalRun(CONFIG, () => {}, { seed: 2 });
  assert.ok(grown.frost.count > 100, `the frost grew: ${grown.frost.count} crystals`);
  const was = parts(before), is = parts(after), hasGrown = parts(grown);
  const differ = Object.keys(is).filter((name) => !sameShape(was[name], is[name])
    || !sameShape(hasGrown[name], is[name]));
  assert.deepEqual(differ, []);
});

test("a second frost's generator draws a walk without a number boxed for each draw", () => {
  // The worker's warm-up frost draws first, and the engine compiles its generator; the
  // page's frost is the second. Draws that ran uncompiled are boxed on the heap (16 bytes
  // each): 300 walks of 12 000 draws would make about 58 MB of garbage, some thirty
  // collections of the young generation; compiled, they make none.
  const walk = new Float32Array(12000);
  const first = seeded(1);
  for (let i = 0; i < 300; i++) first.fill(walk, walk.length);
  const second = seeded(2), profiler = new v8.GCProfiler();
  profiler.start();
  for (let i = 0; i < 300; i++) second.fill(walk, walk.length);
  const collections = profiler.stop().statistics.filter((gc) => gc.gcType === "Scavenge").length;
  assert.ok(collections <= 2, `${collections} collections of the young generation while the second drew`);
});
