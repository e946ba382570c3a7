// Version 14's top-up and repay on the page, case by case (app/web/local/supply.js,
// placement.js, frost.js; issue 56, item 16's mutants): a pool whose owed walkers fill it,
// or whose budget they spend, is not topped up; a bare area's owed walkers are dropped at
// once, none placed; BARE_DRAWS draws all on ice mark an area bare (its walkers dropped,
// not owed), fewer do not; a replenished pool (no growth mode) is topped up at the tick's
// end. And the session record (record.js) keeps MOST_EVENTS events, no more.

import assert from 'node:assert/strict';
import test from 'node:test';

import { Frost } from '../../app/web/local/frost.js';
import { BARE_DRAWS, CELL_TRIES } from '../../app/web/local/placement.js';
import { MOST_EVENTS, SessionRecord } from '../../app/web/local/record.js';
import { presetParams } from './simoracle.mjs';

const FERN = presetParams('fern');

/** A fern touch on a 60 px screen whose launch circle (100 px out) lies beyond it: its
 * pool is placed from cells, CELL_WORK = 400 of them, and the rest owed. */
function beyond(over = {}) {
  const frost = new Frost({ ...FERN, launch: 100, ...over }, { width: 60, height: 60, seed: 0 });
  frost.touch(30, 30);
  return frost;
}

test('a pool whose owed walkers fill it, or spend the budget, is not topped up', () => {
  // humidity 3 000: ~448 walk (400 placed, 48 of the ring), 2 600 owed: the pool is full
  // counting them. Budget 500: 400 placed, 100 owed, the ring's 48: the budget is spent.
  for (const over of [{}, { water_budget: 500 }]) {
    const frost = beyond(over), s = frost.supply;
    const pool = frost.water.n + s.waiting, created = s.created;
    assert.ok(pool >= Math.min(FERN.humidity, frost.params.water_budget), `${pool}`);
    s.topUp(frost.iceState());
    assert.equal(s.created, created, JSON.stringify(over));
    assert.equal(frost.water.n + s.waiting, pool, JSON.stringify(over));
  }
});

test("a bare area's owed walkers are dropped at once, none placed", () => {
  const frost = new Frost(FERN, { seed: 0 }), s = frost.supply;
  frost.touch(380, 640);
  s.owed[0] = 40;  // owed to the touch's area (created when they were cut)
  s.created += 40;
  frost.placer.bare.set(0, frost.iceState() % 4294967296);  // no glass, nothing melted since
  const n = frost.water.n, dropped = s.dropped, work = frost.placer.cellWork, drawn = frost.placer.at;
  s.repay(frost.iceState());
  assert.equal(s.waiting, 0);
  assert.equal(s.dropped, dropped + 40);
  assert.equal(frost.water.n, n);
  assert.equal(frost.placer.cellWork, work);
  assert.equal(frost.placer.at, drawn);  // not a draw taken
});

test('BARE_DRAWS draws of glass cells all missed mark an area bare: its walkers dropped, not owed', () => {
  assert.equal(BARE_DRAWS, 8 * CELL_TRIES);
  const frost = new Frost(FERN, { seed: 0 }), placer = frost.placer;
  frost.touch(380, 640);
  // an area whose every cell holds ice (no disc draws: its annulus is full): its plan
  // draws glass spots, and none is ever found
  const plan = { cells: new Int32Array([0]), glass: true, rIn: 0, misses: 0, fresh: true };
  placer.plans.set(0, plan);
  placer.plansKey = 7;
  placer.full.set(0, true);
  placer.cellDraw = () => false;
  for (let k = 1; k <= 9; k++) {
    assert.equal(placer.place(0, false, 7), false);
    // 7 walkers' 56 draws: the area may hold glass, they are owed; from the 8th's 64, bare
    assert.equal(placer.isBare(0, 7), k >= 8, `after ${k * CELL_TRIES} draws`);
    assert.equal(placer.owe, k < 8, `walker ${k}`);
  }
  assert.equal(placer.isBare(0, 8), false);  // a melt since: glass again
});

test('a replenished pool gets back the water it lost by the tick\'s end', () => {
  // Table 1's c-2 with replenish (no growth mode): a kept pool that lost 100 walkers
  // (dropped) is topped up to humidity by the next tick's end.
  const params = { ...presetParams('c-2'), replenish: true };
  const frost = new Frost(params, { width: 240, height: 320, seed: 0 }), s = frost.supply;
  frost.touch(120, 160);
  frost.step();
  for (let i = 0; i < 100; i++) frost.water.drop[i] = 1;
  s.dropped += frost.water.sweep();
  assert.equal(frost.water.n + s.waiting, params.humidity - 100);
  frost.step();
  assert.equal(frost.water.n + s.waiting, params.humidity);
});

test('the session record keeps MOST_EVENTS events, and no more', () => {
  const record = new SessionRecord({ format: 'frost-session', version: 14 }, 1, {}, [760, 1280]);
  for (let i = 0; i < MOST_EVENTS; i++) record.add({ kind: 'touch', tick: i, x: 1, y: 2 });
  assert.equal(record.events.length, MOST_EVENTS);
  assert.equal(record.full, false);  // the limit itself is kept
  record.add({ kind: 'touch', tick: MOST_EVENTS, x: 1, y: 2 });
  assert.equal(record.events.length, MOST_EVENTS);
  assert.equal(record.full, true);
  assert.equal(record.events.at(-1).tick, MOST_EVENTS - 1);
});
