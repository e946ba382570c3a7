// The weather's effect on the page's frost (app/web/local/frost.js setWeather, touches.js
// meltTips, run.js's weather message), against sim/'s rules (sim/core/frost.py set_weather,
// sim/core/melting.py melt_tips, sim/io/timeline.py's thaw) worked by hand here, and a
// wiped path of the window that refreezes from its edges (tests/test_window_frost.py's).

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';
import { fileURLToPath } from 'node:url';

import { Frost } from '../../app/web/local/frost.js';
import { LocalRun, THAW_TICKS } from '../../app/web/local/run.js';
import { presetParams } from './simoracle.mjs';
import { cover } from './window.mjs';

const ROOT = process.env.FROST_ROOT ?? path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const CONFIG = JSON.parse(readFileSync(path.join(ROOT, 'app/web/local/params.json'), 'utf-8'));
const WINDOW = presetParams('window');
const SMALL = { width: 300, height: 400 };  // a small pane frosts within a few hundred ticks

function live(frost) {
  const out = [];
  for (let i = 0; i < frost.count; i++) if (frost.crystalAlive[i]) out.push(i);
  return out;
}

/** Each live crystal's height: links down to its farthest live descendant (0: a tip). */
function heights(frost) {
  const h = new Map(live(frost).map((i) => [i, 0]));
  for (let i = frost.count - 1; i >= 0; i--) {  // (a child comes after its parent)
    const p = frost.parents[i];
    if (h.has(i) && p >= 0 && h.has(p)) h.set(p, Math.max(h.get(p), h.get(i) + 1));
  }
  return h;
}

test('weather at -20 C on the -10 C window: its hits and its pool as the -20 C window\'s, and it grows faster', () => {
  const cold = new Frost(presetParams('window', { temperature: 20 }), { seed: 3 });
  const told = new Frost(WINDOW, { seed: 3 });
  const plain = new Frost(WINDOW, { seed: 3 });
  told.setWeather(20, 1);
  // by hand: hits 1 / 3 at 10 C, x 10 / 20 = 0.5 / 1.5, rounded half to even = 0 / 2, at least 1
  assert.deepEqual(told.growth.need, [1, 2, -1]);
  assert.deepEqual(cold.growth.need, [1, 2, -1]);
  assert.deepEqual(plain.growth.need, [1, 3, -1]);
  for (let t = 0; t < 30; t++) [cold, told, plain].forEach((f) => f.step());
  // the pool follows the temperature: twice the water of -10 C (8 000 of the budget's 10 000)
  assert.equal(told.pane.pool(WINDOW.humidity), 2 * WINDOW.humidity);
  assert.equal(cold.pane.pool(WINDOW.humidity), 2 * WINDOW.humidity);
  assert.equal(plain.pane.pool(WINDOW.humidity), WINDOW.humidity);
  assert.equal(told.water.n, 2 * WINDOW.humidity);
  assert.ok(told.water.n > 1.8 * plain.water.n);
  assert.ok(told.count > 1.2 * plain.count, `${told.count} at -20 C, ${plain.count} at -10 C`);
  // the supply alone: its factor on the pool
  const wet = new Frost(WINDOW, { ...SMALL, seed: 3 });
  const pool = wet.pane.pool(WINDOW.humidity);
  wet.setWeather(10, 2);
  assert.equal(wet.pane.pool(WINDOW.humidity), Math.trunc(2 * pool));
  assert.throws(() => wet.setWeather(0, 1), RangeError);
  assert.throws(() => wet.setWeather(10, NaN), RangeError);
});

test('a thaw grows nothing, and each meltTips takes one layer of tips: after k layers the crystals of height k or more are left', () => {
  for (const [params, touch] of [[presetParams('fern'), [380, 640]], [WINDOW, null]]) {
    const frost = new Frost(params, { seed: 2, ...(touch ? {} : SMALL) });
    if (touch) frost.touch(...touch);
    for (let t = 0; t < 150; t++) frost.step();
    const height = heights(frost), before = frost.alive, water = frost.water.n;
    const xs = Array.from(frost.water.x.subarray(0, water));
    frost.setWeather(null);
    for (let t = 0; t < 20; t++) assert.equal(frost.step().end - frost.step().start, 0);
    assert.equal(frost.alive, before);
    assert.deepEqual(Array.from(frost.water.x.subarray(0, frost.water.n)), xs);  // the walkers wait
    const top = Math.max(...height.values());
    assert.ok(top >= 10, `the ice is ${top} links deep`);
    for (let k = 1; k <= top + 1; k++) {
      const created = frost.supply.created;
      const melted = frost.meltTips();
      assert.deepEqual(live(frost), [...height.keys()].filter((i) => height.get(i) >= k).sort((a, b) => a - b), `layer ${k}`);
      assert.ok(melted.length > 0);
      for (const d of melted) assert.equal(frost.index.candidates.count[frost.index.grid.key(frost.crystals[2 * d], frost.crystals[2 * d + 1])] >= 0, true);
      assert.ok(frost.supply.created >= created);
    }
    assert.equal(frost.alive, 0);
    assert.equal(frost.index.candidates.count.reduce((a, b) => a + b, 0), 0);  // no melted crystal listed
  }
});

test('LocalRun takes the page\'s weather: a thaw melts a layer every 50 ticks, the cold grows again, bad readings are refused', () => {
  const sent = [];
  const run = new LocalRun(CONFIG, (m) => sent.push(m), { seed: 1, preset: 'window' });
  run.hello();
  assert.equal(run.chosen, 'window');
  for (let t = 0; t < 100; t++) run.tick();
  const grown = run.frost.alive;
  assert.ok(grown > 1000);
  run.input({ type: 'weather', temperature: null });
  const alive = [];
  for (let t = 0; t < 2 * THAW_TICKS; t++) {
    run.tick();
    alive.push(run.frost.alive);
  }
  // ticks 100 and 150 melt (at the tick's start, as sim/io/timeline.py); none between
  assert.ok(alive[0] < grown);
  assert.ok(alive.slice(0, THAW_TICKS).every((a) => a === alive[0]));
  assert.ok(alive[THAW_TICKS] < alive[0]);
  const refused = sent.length;
  for (const bad of [{ temperature: -3 }, { temperature: 'cold' }, { temperature: 10, supply: -1 }, { temperature: Infinity }, {}]) {
    run.input({ type: 'weather', ...bad });
  }
  assert.equal(sent.length, refused + 5);
  assert.ok(sent.slice(refused).every((m) => JSON.parse(m).type === 'notice'));
  assert.ok(run.frost.thawing);
  run.input({ type: 'weather', temperature: 14, supply: 1 });
  const thawed = run.frost.alive;
  for (let t = 0; t < 50; t++) run.tick();
  assert.ok(run.frost.alive > thawed);
  assert.deepEqual(run.frost.growth.need, [1, 2, -1]);  // window's 1 / 3 hits at 10 C, x 10 / 14, rounded
  run.preset('window');  // a rebuild keeps the weather
  assert.deepEqual(run.frost.growth.need, [1, 2, -1]);
});

const PATH = Array.from({ length: 23 }, (_, i) => [40 + 10 * i, 150 + 3 * i]);  // a finger's drag
const R = 20;

function inPath(x, y) {
  return PATH.some(([px, py]) => (x - px) ** 2 + (y - py) ** 2 < R * R);
}

test('a wiped path across the frosted window is clear, then refreezes from its edges', () => {
  const frost = new Frost(WINDOW, { ...SMALL, seed: 1 }), grid = frost.index.grid, s = grid.cell;
  const cells = [];
  for (let k = 0; k < grid.size; k++) {
    const x0 = (k % grid.cols) * s, y0 = Math.floor(k / grid.cols) * s;
    if ([[x0, y0], [x0 + s, y0], [x0, y0 + s], [x0 + s, y0 + s]].every(([x, y]) => inPath(x, y))) cells.push(k);
  }
  const pathCover = () => {
    const held = new Set();
    for (const i of live(frost)) held.add(grid.key(frost.crystals[2 * i], frost.crystals[2 * i + 1]));
    return cells.filter((k) => held.has(k)).length / cells.length;
  };
  const shares = [];
  while (frost.tick < 2500) {  // to the frosted end (app/bench/measures.py frosted_end)
    frost.step();
    shares.push(cover(frost));
    if (shares.length > 250 && shares.at(-1) - shares.at(-251) < 0.01) break;
  }
  for (let t = 0; t < 300; t++) frost.step();
  const before = pathCover();
  assert.ok(before > 0.5, `the path's cells ${before}`);
  const survivors = new Set(live(frost));
  for (const [x, y] of PATH) frost.melt(x, y, R);
  assert.ok(live(frost).every((i) => !inPath(frost.crystals[2 * i], frost.crystals[2 * i + 1])));
  assert.equal(pathCover(), 0);
  const start = frost.count;
  let ticks = 0;
  while (pathCover() < 0.9 * before && ticks < 600) {
    const added = frost.step();
    ticks++;
    for (let i = added.start; i < added.end; i++) {  // each new crystal hangs from the ice: no seed
      const p = frost.parents[i];
      assert.ok(p >= 0 && frost.crystalAlive[p]);
      assert.ok(Math.hypot(frost.crystals[2 * i] - frost.crystals[2 * p], frost.crystals[2 * i + 1] - frost.crystals[2 * p + 1]) <= WINDOW.hc * (1 + 1e-5));
    }
  }
  assert.ok(pathCover() >= 0.9 * before, `path at ${pathCover()} of ${before} after ${ticks} ticks`);
  // from its edges: every crystal in the path descends from ice that outlived the wipe
  for (let i = start; i < frost.count; i++) {
    let r = i;
    while (r >= start) r = frost.parents[r];
    assert.ok(survivors.has(r));
  }
  console.log(JSON.stringify({ before, ticks }));
});
