// The page's simulation held to sim/ by what the frost is (docs/local-sim.md's parity
// table): the two draw different random numbers, so each figure is compared over several
// seeds, sim/ grown in the same test through the checkout's Python. Each tolerance is the
// table's; a figure out of it fails with both values.

import test from 'node:test';

import { bothGrown, held, medianOf, within, withinFactor } from './parity.mjs';
import { growPage, median, presetParams, python, tapWaits } from './simoracle.mjs';

test('fern: crystals after 25, 100 and 400 ticks, the first arm and the fronds\' shape', () => {
  const { sim, page } = bothGrown('fern', [25, 100, 400], 500);
  for (const tick of [25, 100, 400]) {
    withinFactor(`crystals at tick ${tick} (median)`, medianOf(page, (r) => r.counts[tick]),
      medianOf(sim, (r) => r.counts[tick]), 1.25);
  }
  within('ticks to the seed\'s first child (median)', medianOf(page, (r) => r.first_child),
    medianOf(sim, (r) => r.first_child), 2);
  within('six-fold order S6 at tick 500 (median)', medianOf(page, (r) => r.measures.s6),
    medianOf(sim, (r) => r.measures.s6), 0.15);
  within('links straight on at tick 500 (median share)', medianOf(page, (r) => r.measures.straight),
    medianOf(sim, (r) => r.measures.straight), 0.04);
  within('mass-radius dimension at tick 500 (median)', medianOf(page, (r) => r.measures.dimension),
    medianOf(sim, (r) => r.measures.dimension), 0.08);
  within('link length, px (mean)', medianOf(page, (r) => r.measures.link),
    medianOf(sim, (r) => r.measures.link), 0.05);
  held();
});

test('fern: the page bench\'s 32 taps, 0.7 s apart: ticks to each seed\'s first child', () => {
  const seeds = [0, 1, 2, 3], params = presetParams('fern');
  const sim = python({ kind: 'taps', preset: 'fern', taps: 32, seeds });
  const page = seeds.map((seed) => tapWaits(params, seed, sim.spots, sim.gap_s, sim.never));
  const grew = (runs) => runs.flat().filter((w) => w < sim.never).sort((a, b) => a - b);
  const p95 = (w) => w[Math.ceil(0.95 * w.length) - 1], never = (runs) => runs.flat().length - grew(runs).length;
  within('ticks to the first child (median)', median(grew(page)), median(grew(sim.waits)), 1);
  within('ticks to the first child (95th percentile)', p95(grew(page)), p95(grew(sim.waits)), 2);
  within('taps whose seed never grows (of 128)', never(page), never(sim.waits), 6);
  held();
});

test('a warm finger at the centre at tick 150 and the regrowth, fern and c-2', () => {
  const seeds = [0, 1, 2, 3, 4], melt = [150, 380, 640, 60];
  for (const name of ['fern', 'c-2']) {
    const params = presetParams(name);
    const sim = python({ kind: 'grow', preset: name, seeds, ticks: [300], measure_at: 0, melt, live_at: ['151', '300'] });
    const page = seeds.map((seed) => growPage(params, seed, { ticks: [300], melt, liveAt: [151, 300] }));
    for (const [what, key, factor] of [['crystals melted', 'melted', 1.15], ['live crystals a tick after', '151', 1.1],
      ['live crystals at tick 300', '300', 1.1], ['crystals grown back inside the melted disc by tick 300', 'inside', 1.3]]) {
      withinFactor(`${name}: ${what} (median)`, medianOf(page, (r) => r.live[key]), medianOf(sim, (r) => r.live[key]), factor);
    }
  }
  held();
});

test('the paper\'s c-2: the chain reaction\'s crystals, first crystal and dimension', () => {
  const { sim, page } = bothGrown('c-2', [25, 100, 400], 500);
  withinFactor('crystals at tick 100 (median)', medianOf(page, (r) => r.counts[100]),
    medianOf(sim, (r) => r.counts[100]), 1.05);
  withinFactor('crystals at tick 400 (median)', medianOf(page, (r) => r.counts[400]),
    medianOf(sim, (r) => r.counts[400]), 1.02);
  within('ticks to the first crystal (median)', medianOf(page, (r) => r.first_child),
    medianOf(sim, (r) => r.first_child), 5);
  within('mass-radius dimension at tick 500 (median)', medianOf(page, (r) => r.measures.dimension),
    medianOf(sim, (r) => r.measures.dimension), 0.15);
  held();
});
