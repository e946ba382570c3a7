// The page's simulation against sim/ where the two must agree number for number, fed the
// same numbers (docs/local-sim.md): one walk step from the same uniform draws, the
// candidate cells of the same crystals, and the crystallization of the same walkers.

import assert from 'node:assert/strict';
import test from 'node:test';

import { Areas } from '../../app/web/local/areas.js';
import { FreezingIndex } from '../../app/web/local/index.js';
import { float32Of, seeded } from '../../app/web/local/random.js';
import { Skeleton } from '../../app/web/local/skeleton.js';
import { drawWalk, walkWater } from '../../app/web/local/walk.js';
import { Water } from '../../app/web/local/water.js';
import { python } from './simoracle.mjs';

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
  const water = new Water(m), areas = new Areas();
  areas.open(...area);
  for (let j = 0; j < m; j++) water.append(xy[2 * j], xy[2 * j + 1], 0);
  const scratch = new Float32Array(2 * m), left = new Uint8Array(m);
  let at = 0;
  drawWalk(() => draws[at++], m, scratch);
  walkWater(water, areas, step, null, scratch, [W, H], left);
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
  const leftJs = [...left.keys()].filter((j) => left[j]);
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
