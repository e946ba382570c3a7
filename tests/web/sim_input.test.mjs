// The page's simulation under a finger: bad input changes nothing, a seed gives the same
// frost, clear() empties the pane, a storm of taps stays within the budgets, and a warm
// finger melts what it covers and nothing else.

import assert from 'node:assert/strict';
import test from 'node:test';

import { CELL_CAP } from '../../app/web/local/budget.js';
import { Frost } from '../../app/web/local/frost.js';
import { seeded } from '../../app/web/local/random.js';
import { presetParams } from './simoracle.mjs';

const FERN = presetParams('fern');
const C2 = presetParams('c-2');

/** Everything a user or the geometry could see of `frost`, as plain numbers. */
function state(frost) {
  const water = frost.water;
  return JSON.stringify({
    count: frost.count, tick: frost.tick, water: Array.from(water.x.subarray(0, water.n)),
    crystals: Array.from(frost.crystals.subarray(0, 2 * frost.count)),
    alive: Array.from(frost.crystalAlive.subarray(0, frost.count)),
    segments: frost.segmentCount, areas: Array.from(frost.areas.rows.subarray(0, 5 * frost.areas.n)),
  });
}

function grown(params, seed, ticks, touches = [[380, 640]]) {
  const frost = new Frost(params, { seed });
  for (const [x, y] of touches) frost.touch(x, y);
  for (let t = 0; t < ticks; t++) frost.step();
  return frost;
}

test('a touch or a melt off the pane or not finite changes nothing', () => {
  const frost = grown(FERN, 2, 30), before = state(frost);
  for (const [x, y] of [[-1, 5], [760, 10], [10, 1280], [NaN, 3], [3, Infinity], [-Infinity, 0]]) {
    assert.equal(frost.touch(x, y), false, `touch(${x}, ${y})`);
  }
  for (const [x, y, r] of [[380, 640, NaN], [380, 640, 0], [380, 640, -3], [NaN, 640, 30], [380, 1300, 30],
    [380, 640, Infinity], [380, 640, 10001]]) {
    assert.equal(frost.melt(x, y, r).length, 0, `melt(${x}, ${y}, ${r})`);
  }
  assert.equal(state(frost), before);
  assert.equal(frost.touch(759.9999999, 1279.9999999), true);  // the last pixel is on the pane
  assert.ok(frost.crystals[2 * (frost.count - 1)] < 760 && frost.crystals[2 * frost.count - 1] < 1280);
});

test('a seed grows the same frost; another seed another', () => {
  const a = grown(FERN, 7, 60), b = grown(FERN, 7, 60), c = grown(FERN, 8, 60);
  assert.equal(state(a), state(b));
  assert.notEqual(state(a), state(c));
  const u = seeded(3), draws = Array.from({ length: 10000 }, u);
  assert.ok(draws.every((v) => v >= 0 && v < 1));
  const mean = draws.reduce((s, v) => s + v, 0) / draws.length;
  assert.ok(Math.abs(mean - 0.5) < 0.01, `mean of 10 000 draws ${mean}`);
});

test('clear() empties the pane, its water and its areas, and the frost grows again', () => {
  const frost = grown(FERN, 4, 40, [[380, 640], [200, 300]]);
  assert.ok(frost.count > 50 && frost.waterCount > 0);
  frost.clear();
  assert.deepEqual([frost.count, frost.waterCount, frost.areas.n, frost.segmentCount], [0, 0, 0, 0]);
  frost.step();
  assert.equal(frost.count, 0);
  assert.ok(frost.touch(380, 640));
  for (let t = 0; t < 40; t++) frost.step();
  assert.ok(frost.count > 50, `${frost.count} crystals 40 ticks after a touch on a cleared pane`);
});

test('a storm of taps keeps the water budget and the cells\' cap', () => {
  const frost = new Frost(FERN, { seed: 5 }), u = seeded(9), spot = [];
  for (let t = 0; t < 250; t++) {  // 2 000 taps in 10 s: 8 a tick, half of them on one spot
    for (let k = 0; k < 8; k++) {
      if (k % 2) spot.push(frost.touch(400, 500));
      else frost.touch(760 * u(), 1280 * u());
    }
    frost.step();
    assert.ok(frost.waterCount <= FERN.water_budget, `tick ${t}: ${frost.waterCount} walkers`);
  }
  const lists = frost.index.candidates, grid = frost.index.grid;
  assert.ok(Math.max(...lists.count) <= CELL_CAP, `a cell lists ${Math.max(...lists.count)} crystals`);
  // The one spot's cells filled, and its taps stopped planting seeds there.
  const cells = Array.from(grid.cells.subarray(0, grid.discCells(400, 500, FERN.hc)));
  assert.equal(Math.max(...cells.map((c) => lists.count[c])), CELL_CAP);
  assert.ok(spot.slice(-500).every((taken) => !taken));
  assert.ok(spot.filter(Boolean).length >= 10, 'the spot took its first taps');
});

test('a warm finger melts the crystals within its radius, their links and their children\'s', () => {
  for (const params of [FERN, C2]) {
    const frost = grown(params, 1, 120), r = 40, [x, y] = [380, 640];
    const melted = frost.melt(x, y, r), c = frost.crystals;
    const near = (i) => Math.hypot(c[2 * i] - x, c[2 * i + 1] - y) < r;
    assert.ok(melted.length > 10);
    for (let i = 0; i < frost.count; i++) {
      assert.equal(frost.crystalAlive[i] === 0, near(i), `crystal ${i}`);
    }
    const { orphans, segments } = frost.melted;
    for (const o of orphans) assert.equal(frost.parents[o], -1);
    for (const s of segments) assert.equal(frost.segmentsAlive[s], 0);
    for (let s = 0; s < frost.segmentCount; s++) {  // every live segment hangs from two live crystals
      const child = frost.segmentsLink[s];
      if (frost.segmentsAlive[s]) assert.ok(frost.crystalAlive[child] && frost.crystalAlive[frost.parents[child]]);
    }
    assert.ok(frost.waterCount <= params.water_budget);
    for (let t = 0; t < 5; t++) frost.step();  // and the frost grows on
  }
});

test('parameters it cannot run are refused in one line that names them', () => {
  assert.throws(() => new Frost({ ...FERN, window_frost: true, grains: false, frame_sites: 3, pane_sites: 4,
    temperature: 10 }), /^Error: window mode needs grains$/);
  const { hc, ...noHc } = FERN;
  assert.ok(hc > 0);
  assert.throws(() => new Frost(noHc), /^Error: parameters lack hc$/);
  for (const name of ['a-1', 'b-1', 'c-3', 'fern', 'window']) assert.ok(new Frost(presetParams(name)).touch(380, 640), name);
});
