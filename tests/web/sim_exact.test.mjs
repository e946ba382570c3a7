// The page's simulation against sim/ where the two must agree number for number, fed the
// same numbers (docs/local-sim.md): one walk step from the same uniform draws, the
// candidate cells of the same crystals, the crystallization of the same walkers, and the
// fern rule's decisions on the same hits.

import assert from 'node:assert/strict';
import test from 'node:test';

import { Budget } from '../../app/web/local/budget.js';
import { FernGrowth } from '../../app/web/local/fern.js';
import { FreezingIndex } from '../../app/web/local/index.js';
import { float32Of, seeded } from '../../app/web/local/random.js';
import { Skeleton } from '../../app/web/local/skeleton.js';
import { Water } from '../../app/web/local/water.js';
import { givenStream, presetParams, python, walkPage } from './simoracle.mjs';

const W = 760, H = 1280;

/** The float32 units in the last place between a and b (both float32 values). */
function ulps(a, b) {
  const f = new Float32Array([a, b]), i = new Int32Array(f.buffer);
  return Math.abs(i[0] - i[1]);
}

/** The largest float32 below `v`. */
function below(v) {
  const f = new Float32Array([v]);
  new Int32Array(f.buffer)[0] -= 1;
  return f[0];
}

/** `n` float32 points of a disc, from a seeded stream. */
function points(n, cx, cy, r, seed) {
  const u = seeded(seed), out = [];
  for (let j = 0; j < n; j++) {
    const a = 2 * Math.PI * u(), d = r * Math.sqrt(u());
    out.push(Math.fround(cx + d * Math.cos(a)), Math.fround(cy + d * Math.sin(a)));
  }
  return out;
}

test('one walk step from the same uniform draws lands where sim/ lands it', () => {
  const m = 4000, xy = points(m, 380, 640, 205, 3), area = [380, 640, 200], step = 5;
  const u = seeded(11), draws = Array.from({ length: 2 * m }, () => float32Of(u()));
  const want = python({ kind: 'walk', xy, u: draws, area, step, width: W, height: H });
  const { water, left: leftJs } = walkPage(xy, area, step, draws, null, [W, H]);
  // numpy's float32 cos and sin are within one unit in the last place of the correctly
  // rounded value that Math.fround(Math.cos()) gives (17 % of angles differ by one): where
  // they agree (sim/ says which) the walker lands on sim/'s float32 exactly, elsewhere
  // within one unit in the last place.
  let exact = 0;
  for (let j = 0; j < m; j++) {
    const dx = ulps(water.x[j], want.x[j]), dy = ulps(water.y[j], want.y[j]);
    const at = `walker ${j}: (${water.x[j]}, ${water.y[j]}) against (${want.x[j]}, ${want.y[j]})`;
    assert.ok(want.trig_rounded[j] ? dx === 0 && dy === 0 : dx <= 1 && dy <= 1, at);
    exact += want.trig_rounded[j];
  }
  assert.ok(exact >= 0.5 * m, `${exact} of ${m} walkers' angles have a correctly rounded cos and sin`);
  assert.deepEqual(leftJs, want.left);
  assert.ok(leftJs.length > 0, 'some walkers leave the area (the test sees the rim)');
});

/** The page's index over crystals at `xy` (hc px). */
function indexOver(xy, hc) {
  const ice = new Skeleton();
  for (let j = 0; j < xy.length; j += 2) ice.add(xy[j], xy[j + 1], -1, 0);
  const index = new FreezingIndex(ice, W, H, hc, false);
  index.register(0, ice.count);
  return index;
}

for (const hc of [7, 3, 10]) {
  test(`the candidate cells and the crystallization of the same ice agree with sim/ (hc ${hc})`, () => {
    // A cluster; crystals on cell borders, at the screen's corners, one twice (a tie:
    // the lower index wins); walkers on every cell border of a row (float32 rounding
    // decides their cell), exactly hc from a crystal (not within) and just inside.
    const crystals = [...points(300, 380, 640, 120, 5), 2 * hc * 20, 2 * hc * 30, 2 * hc * 20 + hc, 2 * hc * 30,
      0, 0, W - 0.5, H - 0.5, 100, 200, 100, 200];
    const borders = [];
    for (let k = 1; k < W / (2 * hc); k++) borders.push(2 * hc * k, 2 * hc * 30, below(2 * hc * k), 2 * hc * 30);
    const walkers = [...points(3000, 380, 640, 140, 6), 2 * hc * 20 + hc / 2, 2 * hc * 30 + 0.1, ...borders,
      crystals[0] + hc, crystals[1], crystals[2] + Math.fround(hc - 1e-4), crystals[3], 1, 1,
      100 + hc, 200, 100, 200 + hc - 0.25];
    const want = python({ kind: 'cells', crystals, walkers, hc, width: W, height: H });
    const index = indexOver(crystals, hc), lists = index.candidates, got = {};
    for (let cell = 0; cell < lists.count.length; cell++) {
      const n = lists.count[cell];
      if (n) got[cell] = Array.from(lists.items.subarray(cell * lists.width, cell * lists.width + n));
    }
    assert.deepEqual(got, want.lists);
    const keys = [], hits = [], parents = [];
    for (let j = 0; j < walkers.length; j += 2) {
      const [x, y] = [Math.fround(walkers[j]), Math.fround(walkers[j + 1])], key = index.grid.key(x, y);
      keys.push(key);
      const p = index.nearest(x, y, key);
      if (p >= 0) {
        hits.push(j / 2);
        parents.push(p);
      }
    }
    assert.deepEqual(keys, want.keys);
    assert.deepEqual(hits, want.hits);
    assert.deepEqual(parents, want.parents);
    assert.ok(hits.length > 50 && hits.length < walkers.length / 2 - 50, `${hits.length} hits`);
  });
}

test('the fern rule decides as sim/ does: which hits grow, where, and which only count', () => {
  const params = presetParams('fern', { drift: 0 });  // (no normal draws to share)
  // Seeds: ringed and not, one at the pane's edge (its slots off the pane are blocked and
  // keep counting), two 12 px apart (their spots meet: only the first of a tick is kept).
  const seeds = [380, 640, 200, 300, 560, 1000, 3, 900, 300, 500, 312, 500];
  const ringed = [true, false, true, false, false, false];
  const u = seeded(21), axes = ringed.map(() => u()), given = [...axes, ...Array(4000).fill(0.5)];
  const ice = new Skeleton(), index = new FreezingIndex(ice, W, H, params.hc, params.long_jumps);
  const growth = new FernGrowth(params, givenStream(given), ice, index, new Budget(index, params));
  for (let j = 0; j < seeds.length; j += 2) {
    ice.add(seeds[j], seeds[j + 1], -1, 0);
    growth.addSeed(ringed[j / 2]);
  }
  index.register(0, ice.count);
  const ticks = [], page = [], draw = seeded(22);
  for (let t = 0; t < 100; t++) {  // walkers within 1.2 hc of random crystals, 40 a tick
    const walkers = [], water = new Water(64);
    for (let k = 0; k < 40; k++) {
      const i = Math.floor(draw() * ice.count), a = 2 * Math.PI * draw(), d = 1.2 * params.hc * Math.sqrt(draw());
      walkers.push(Math.fround(ice.crystals[2 * i] + d * Math.cos(a)), Math.fround(ice.crystals[2 * i + 1] + d * Math.sin(a)));
      water.append(walkers[2 * k], walkers[2 * k + 1], 0);
    }
    ticks.push(walkers);
    const hits = new Int32Array(40), parents = new Int32Array(40);
    let n = 0;
    for (let k = 0; k < 40; k++) {
      const p = index.nearest(water.x[k], water.y[k], index.grid.key(water.x[k], water.y[k]));
      if (p >= 0) [hits[n], parents[n++]] = [k, p];
    }
    const grown = [], counted = growth.settle(hits, parents, n, water, grown), start = ice.count;
    const tick = { grown: [], parents: [], pts: [], counted: Array.from(hits.subarray(0, counted)).sort((a, b) => a - b) };
    for (let g = 0; g < grown.length; g += 4) {
      const [w, p, x, y] = grown.slice(g, g + 4), i = ice.add(x, y, p, 0);
      ice.link(i, ice.crystals[2 * p], ice.crystals[2 * p + 1], params.D);
      tick.grown.push(w);
      tick.parents.push(p);
      tick.pts.push(x, y);
    }
    index.register(start, ice.count);
    page.push(tick);
  }
  const sim = python({ kind: 'fern', preset: 'fern', overrides: { drift: 0 }, seeds, ringed, u: axes, ticks,
    width: W, height: H });
  page.forEach((tick, t) => assert.deepEqual(tick, sim[t], `tick ${t}`));
  const grew = page.reduce((s, tick) => s + tick.grown.length, 0);
  assert.ok(grew >= 30, `${grew} crystals grew in 100 ticks`);
});
