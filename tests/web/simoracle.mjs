// What the Node tests of the page's simulation share: `sim/` asked through the checkout's
// Python (tests/support/simoracle.py; FROST_PYTHON, set by tests/test_web_node.py), and
// the page's Frost grown the way the oracle grows sim/'s.

import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { Areas } from '../../app/web/local/areas.js';
import { Frost } from '../../app/web/local/frost.js';
import { drawWalk, walkWater } from '../../app/web/local/walk.js';
import { Water } from '../../app/web/local/water.js';

const ROOT = process.env.FROST_ROOT || path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const PYTHON = process.env.FROST_PYTHON || path.join(ROOT, '.venv/bin/python');
export const CENTRE = [380, 640];

/** One walk of the page's walkers at `xy` (float32, interleaved) in one area `area` (centre
 * x, y, radius) on a `size` screen, by the uniforms `draws`, with `jump` (each walker's
 * clearance) or null: the water moved and which walkers left ({water, left}). */
export function walkPage(xy, area, step, draws, jump, size) {
  const m = xy.length / 2, water = new Water(m), areas = new Areas();
  areas.open(...area);
  for (let j = 0; j < m; j++) water.append(xy[2 * j], xy[2 * j + 1], 0);
  const scratch = new Float32Array(2 * m), left = new Uint8Array(m);
  let at = 0;
  drawWalk(() => draws[at++], m, scratch);
  walkWater(water, areas, step, jump, scratch, size, left);
  return { water, left: [...left.keys()].filter((j) => left[j]) };
}

/** sim/'s answer to `request` (tests/support/simoracle.py). */
export function python(request) {
  const out = execFileSync(PYTHON, [path.join(ROOT, 'tests/support/simoracle.py')], {
    input: JSON.stringify(request), maxBuffer: 1 << 28, encoding: 'utf-8',
  });
  return JSON.parse(out.replace(/\bNaN\b/g, 'null'));
}

/** A preset's parameters as sim/params.py validates them (`overrides` applied). */
export function presetParams(preset, overrides = {}) {
  return python({ kind: 'params', preset, overrides });
}

/** One touch at `touch` grown by the page's Frost, as simoracle.py's `grow` grows sim/'s:
 * crystals at `ticks`, the tick of the seed's first child, and the live skeleton at
 * `measureAt` (or once `untilCrystals` crystals are reached); with `melt` ([tick, x, y, r])
 * a warm finger before that tick, and the live crystals at the ticks of `liveAt`. */
export function growPage(params, seed, { ticks = [], measureAt = 0, untilCrystals = 0, touch = CENTRE,
  melt = null, liveAt = [] } = {}) {
  const frost = new Frost(params, { seed });
  frost.touch(...touch);
  const counts = {}, live = {}, last = Math.max(measureAt, ...ticks);
  let first = null;
  while (frost.tick < last || (untilCrystals && frost.count < untilCrystals)) {
    if (melt && frost.tick === melt[0]) live.melted = frost.melt(...melt.slice(1)).length;
    frost.step();
    if (liveAt.includes(frost.tick)) live[frost.tick] = frost.crystalAlive.subarray(0, frost.count).reduce((a, b) => a + b, 0);
    if (first === null && frost.count > 1) first = frost.tick;
    if (ticks.includes(frost.tick)) counts[frost.tick] = frost.count;
    if (frost.tick === measureAt && !untilCrystals) break;
  }
  const skeleton = liveSkeleton(frost), c = skeleton.crystals;
  if (melt) {  // the live crystals that grew back inside the melted disc
    live.inside = 0;
    for (let j = 0; j < c.length; j += 2) live.inside += Math.hypot(c[j] - melt[1], c[j + 1] - melt[2]) < melt[3];
  }
  return { counts, first_child: first, live, frost, ...skeleton };
}

/** The live crystals (x, y interleaved) and their parents, renumbered among the live. */
export function liveSkeleton(frost) {
  const live = new Int32Array(frost.count).fill(-1), crystals = [], parents = [];
  for (let i = 0; i < frost.count; i++) {
    if (!frost.crystalAlive[i]) continue;
    live[i] = crystals.length / 2;
    crystals.push(frost.crystals[2 * i], frost.crystals[2 * i + 1]);
  }
  for (let i = 0; i < frost.count; i++) {
    if (frost.crystalAlive[i]) parents.push(frost.parents[i] >= 0 ? live[frost.parents[i]] : -1);
  }
  return { crystals, parents };
}

/** sim/'s measures (tests/support/simoracle.py) of a skeleton the page grew. */
export function measurePage(run, hc, centre = CENTRE) {
  return python({ kind: 'measure', crystals: run.crystals, parents: run.parents, centre, hc });
}

export function median(values) {
  const s = [...values].sort((a, b) => a - b), m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
}

/** A uniform stream handing out `values` in order (the shared seeded stream). */
export function givenStream(values) {
  let at = 0;
  return () => {
    if (at >= values.length) throw new Error(`the given stream has ${values.length} numbers`);
    return values[at++];
  };
}

/** The page bench's taps (spots x, y interleaved, one every `gapS` s) through the page's
 * Frost, as app/bench/taps.py's `waits` runs them through sim/: each tap's ticks to its
 * seed's first child, `never` where it has none by then. */
export function tapWaits(params, seed, spots, gapS, never) {
  const frost = new Frost(params, { seed }), taps = spots.length / 2;
  const tickOfTap = Array.from({ length: taps }, (_, k) => Math.floor(k * gapS * 25));
  const seeds = [], out = new Array(taps).fill(never);
  for (let tick = 0; tick < tickOfTap[taps - 1] + never; tick++) {
    tickOfTap.forEach((t, k) => {
      if (t !== tick) return;
      frost.touch(spots[2 * k], spots[2 * k + 1]);
      seeds.push([k, frost.count - 1, tick]);
    });
    frost.step();
    const waiting = seeds.filter(([k]) => out[k] === never);
    if (waiting.length === 0 && seeds.length === taps) break;
    if (waiting.length === 0) continue;
    const parents = new Set();
    for (let i = 0; i < frost.count; i++) if (frost.crystalAlive[i]) parents.add(frost.parents[i]);
    for (const [k, s, t] of waiting) if (parents.has(s) && frost.tick - t <= never) out[k] = frost.tick - t;
  }
  return out;
}
