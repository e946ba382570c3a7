// The walk with long jumps (fern rule 3: local/walk.js against sim/core/walk.py, fed the
// same uniforms and clearances): a walker jumps its clearance only where the clearance
// exceeds the step size; below it (above or below its own random step) it walks.

import assert from 'node:assert/strict';
import test from 'node:test';

import { float32Of, seeded } from '../../app/web/local/random.js';
import { python, walkPage } from './simoracle.mjs';

const W = 760, H = 1280;

/** The float32 units in the last place between a and b (both float32 values). */
function ulps(a, b) {
  const f = new Float32Array([a, b]), i = new Int32Array(f.buffer);
  return Math.abs(i[0] - i[1]);
}

test('with long jumps a walker jumps only a clearance above the step size, as in sim/', () => {
  const m = 3000, step = 5, area = [380, 640, 400], u = seeded(23);
  const xy = [], jump = new Float64Array(m);
  for (let j = 0; j < m; j++) {
    const a = 2 * Math.PI * u(), d = 300 * Math.sqrt(u());
    xy.push(Math.fround(380 + d * Math.cos(a)), Math.fround(640 + d * Math.sin(a)));
    // a third each: below the step, the step itself (no jump: "exceeds"), up to 6 steps
    jump[j] = [step * u(), step, step * (1 + 5 * u())][j % 3];
  }
  const draws = Array.from({ length: 2 * m }, () => float32Of(u()));
  const want = python({ kind: 'walk', xy, u: draws, area, step, width: W, height: H, jump: Array.from(jump) });
  const { water, left } = walkPage(xy, area, step, draws, jump, [W, H]);

  // What the test covers: walkers whose clearance lies between their random step and the
  // step size (they walk), and walkers whose clearance exceeds the step (they jump).
  let between = 0, jumped = 0;
  for (let j = 0; j < m; j++) {
    const a = Math.fround(draws[j] * step);
    if (jump[j] > a && jump[j] <= step) between++;
    if (jump[j] > step) jumped++;
    // (numpy's float32 cos and sin may differ from the correctly rounded ones by one unit in
    // the last place, and a long jump multiplies that: within 4 units of sim/'s float32; 1 seen)
    const dx = ulps(water.x[j], want.x[j]), dy = ulps(water.y[j], want.y[j]);
    assert.ok(dx <= 4 && dy <= 4, `walker ${j} (clearance ${jump[j]}, step drawn ${a}): ` +
      `(${water.x[j]}, ${water.y[j]}) against sim/'s (${want.x[j]}, ${want.y[j]})`);
    // and by its own length: the walk's length or the clearance, as the rule says
    const moved = Math.hypot(water.x[j] - xy[2 * j], water.y[j] - xy[2 * j + 1]);
    const length = jump[j] > step ? jump[j] : a;
    assert.ok(Math.abs(moved - length) <= 1e-3 * Math.max(1, length), `walker ${j} moved ${moved}, not ${length}`);
  }
  assert.ok(between >= m / 3, `${between} walkers' clearances lie between their step and the step size`);
  assert.ok(jumped >= m / 4, `${jumped} walkers jump`);
  assert.deepEqual(left, want.left);
});
