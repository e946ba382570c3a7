// The worker's tick takes shortcuts (docs/local-sim.md, "Its tick"); each is held here to
// the plain way it stands for, bit for bit: the height grid's raise against every vertex
// of its stencil measured with Math.hypot, the encoder's diff of a delta's changed
// vertices against a diff of all its rows, a clearance's cell by a product against the
// float32 quotient, the generator's fill against its draws one by one.

import assert from "node:assert/strict";
import { test } from "node:test";

import { cellOf } from "../../app/web/local/clearance.js";
import { Encoder } from "../../app/web/local/encode.js";
import { Frost } from "../../app/web/local/frost.js";
import { FrostGeometry } from "../../app/web/local/geometry.js";
import { HeightGrid, falloff } from "../../app/web/local/heightgrid.js";
import { float32Of, seeded } from "../../app/web/local/random.js";
import { presetParams } from "./simoracle.mjs";

const FERN = presetParams("fern");
const TOUCHES = [[380, 640], [200, 300], [560, 1000]];

// The raise the plain way: every vertex of the stencil, each distance by Math.hypot; the
// uncapped sums.
function plainRaise(params, width, height, points) {
  const grid = new HeightGrid(params, width, height), gs = grid.spacing, hc = params.hc;
  const sum = new Float64Array(grid.rows * grid.cols);
  for (const [x, y] of points) {
    const r0 = Math.round(y / gs), c0 = Math.round(x / gs);
    for (let r = r0 - grid.reach - 1; r <= r0 + grid.reach + 1; r++) {
      for (let c = c0 - grid.reach - 1; c <= c0 + grid.reach + 1; c++) {
        const d = Math.hypot(c * gs - x, r * gs - y);
        if (d < hc && r >= 0 && r < grid.rows && c >= 0 && c < grid.cols) {
          sum[r * grid.cols + c] += params.bump * falloff(d, hc);
        }
      }
    }
  }
  return sum;
}

// The raise of `points` on a `width` x `height` px grid: its sums and heights as the plain one's.
function raisesAsPlain(points, width = 200, height = 120) {
  const grid = new HeightGrid(FERN, width, height);
  for (const [x, y] of points) grid.point(x, y);
  grid.finish();
  const sum = plainRaise(FERN, width, height, points);
  const heights = sum.map((s) => { const h = Math.min(s, FERN.max_height); return h < 1e-6 ? 0 : h; });
  assert.ok(sum.some((s) => s > 0));
  assert.deepEqual(grid.sum, sum);
  assert.deepEqual(Float64Array.from(grid.heights), Float64Array.from(heights, Math.fround));
}

test("the height grid's raise skips only vertices outside hc: every sum as the plain raise's", () => {
  const uniform = seeded(7);
  raisesAsPlain(Array.from({ length: 400 }, () => [uniform() * 200, uniform() * 120]));
  // A vertex a hair inside hc of its point (bumps too small for a height, not for a sum),
  // across a row or along a column, and one exactly hc away.
  const rim = [];
  for (let k = 0; k < 6; k++) {
    const gx = 32 * k + 8, gy = 16 + 4 * k;
    rim.push([gx + FERN.hc * (1 - 1e-10), gy], [gx, gy + 40 - FERN.hc * (1 - 1e-12)], [gx + 12, gy + 80 + FERN.hc]);
  }
  raisesAsPlain(rim);
});

// Every delta of a growing, melting frost encoded twice: the worker's way (heights viewed
// in the grid, the changed vertices diffed) and the plain way (heights copied, every
// height of the rows diffed).
test("a delta's message from its changed vertices is the message from all its rows, byte for byte", () => {
  const frost = new Frost(FERN, { seed: 3 });
  const viewed = new FrostGeometry(FERN, { views: true }), copied = new FrostGeometry(FERN);
  const quick = new Encoder(copied.cols, copied.rows), plain = new Encoder(copied.cols, copied.rows);
  let shortcuts = 0;
  const both = (make) => {
    const delta = make(viewed), a = Buffer.from(quick.delta(delta));
    const b = Buffer.from(plain.delta({ ...make(copied), changed: null }));
    assert.ok(a.equals(b), `tick ${delta.tick}: ${a.length} bytes, all rows' ${b.length}`);
    if (delta.changed && delta.changed.length < (delta.rows[1] - delta.rows[0]) * copied.cols) shortcuts++;
  };
  const tick = () => {
    const added = frost.step();
    both((geometry) => geometry.update(frost, added));
  };
  both((geometry) => geometry.reset());
  for (const [x, y] of TOUCHES) frost.touch(x, y);
  for (let t = 0; t < 120; t++) {
    if (t === 80) {
      const melted = frost.melt(380, 668, 8);
      both((geometry) => geometry.melt(frost, melted));
    }
    tick();
  }
  assert.ok(shortcuts > 100, `only ${shortcuts} deltas took the shortcut`);
  // After a reset of the encoder's alone its grid is not the geometry's: all rows again.
  tick();
  plain.bare(frost.tick, true);
  quick.bare(frost.tick, true);
  tick();
});

test("a geometry's deltas keep their heights through the next ticks unless it was made for views", () => {
  const frost = new Frost(FERN, { seed: 3 });
  for (const [x, y] of TOUCHES) frost.touch(x, y);
  const copied = new FrostGeometry(FERN), viewed = new FrostGeometry(FERN, { views: true });
  const added = frost.step(), kept = copied.update(frost, added), seen = viewed.update(frost, added);
  const first = Float32Array.from(kept.heights);
  assert.deepEqual(seen.heights, first);
  for (let t = 0; t < 5; t++) {
    const next = frost.step();
    copied.update(frost, next);
    viewed.update(frost, next);
  }
  assert.deepEqual(kept.heights, first);
  assert.notDeepEqual(seen.heights, first);  // (the grid's rows now)
});

// float32's neighbours of v, `k` steps each way.
function neighbours(v, k) {
  const f = new Float32Array([v]), bits = new Int32Array(f.buffer), out = [];
  for (let d = -k; d <= k; d++) {
    const b = new Int32Array([bits[0] + d]);
    out.push(new Float32Array(b.buffer)[0]);
  }
  return out;
}

test("a walker's clearance cell by the product is the float32 quotient's, whole multiples included", () => {
  const uniform = seeded(11);
  for (const s of [14, 10, 6, 7.5, Math.fround(4.6), Math.fround(2 * Math.PI)]) {
    const values = Array.from({ length: 20000 }, () => Math.fround(uniform() * 1400));
    for (let k = 0; k * s < 1400; k++) values.push(...neighbours(Math.fround(k * s), 3));
    for (const v of values) {
      assert.equal(cellOf(v, s, 1 / s), Math.trunc(Math.fround(v / s)), `${v} / ${s}`);
    }
  }
});

test("a generator's fill gives the draws of as many calls, and goes on where they would", () => {
  const filled = seeded(21), called = seeded(21), out = new Float32Array(5000);
  for (const n of [1, 7, 4999, 0, 12]) {
    filled.fill(out, n);
    for (let i = 0; i < n; i++) assert.equal(out[i], float32Of(called()), `draw ${i} of ${n}`);
    assert.equal(filled(), called());
  }
});
