// What the parity tests share (sim_parity*.test.mjs): a figure of the page's against
// sim/'s within a tolerance, the figures out of it gathered by a test and failed together.

import assert from 'node:assert/strict';

import { growPage, measurePage, median, presetParams, python } from './simoracle.mjs';

export const SEEDS = [0, 1, 2, 3, 4];

// The figures out of their tolerance in the test running now: a test checks every
// figure, then fails with all those out (`held`).
let out = [];

/** `page` within a factor `factor` of `sim` (both positive). */
export function withinFactor(what, page, sim, factor) {
  if (!(page <= sim * factor && page >= sim / factor)) {
    out.push(`${what}: the page's ${page} against sim/'s ${sim} (a factor ${factor} allowed)`);
  }
}

export function within(what, page, sim, tolerance) {
  if (!(Math.abs(page - sim) <= tolerance)) {
    out.push(`${what}: the page's ${page} against sim/'s ${sim} (${tolerance} allowed)`);
  }
}

export function held() {
  const failed = out;
  out = [];
  assert.deepEqual(failed, []);
}

/** Both simulations' runs of one touch at the centre of preset `name`, seeds SEEDS:
 * crystals at `ticks`, the first child's tick, the measures at `measureAt`. */
export function bothGrown(name, ticks, measureAt, seeds = SEEDS) {
  const params = presetParams(name);
  const sim = python({ kind: 'grow', preset: name, seeds, ticks, measure_at: measureAt });
  const page = seeds.map((seed) => {
    const run = growPage(params, seed, { ticks, measureAt });
    return { ...run, measures: measurePage(run, params.hc) };
  });
  return { sim, page };
}

export const medianOf = (runs, pick) => median(runs.map(pick));
