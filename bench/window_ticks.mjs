// The phone's worker tick for a preset in Node: `node bench/window_ticks.mjs [preset] [ticks]
// [seed] [--cold]` (default: window, 2 250 ticks, seed 0). Runs LocalRun as the worker does
// (its warm-up first, unless --cold; then the whole tick: the step, its geometry and its
// encoding), the fern with three touches at frost bench sim's spots; prints the median and
// the 99th percentile of a tick in ms by the wall clock and in the process's CPU time, and
// the crystals and the cells' cover at the end.

import { readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { LocalRun, warmUp } from '../app/web/local/run.js';
import { quantile, timeTicks } from './ticks.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const CONFIG = JSON.parse(readFileSync(path.join(ROOT, 'app/web/local/params.json'), 'utf-8'));
const args = process.argv.slice(2).filter((a) => !a.startsWith('--'));
const preset = args[0] || 'window', ticks = Number(args[1] || 2250), seed = Number(args[2] || 0);

if (!process.argv.includes('--cold')) warmUp(CONFIG);
const run = new LocalRun(CONFIG, () => {}, { seed, preset });
run.hello();
if (preset !== 'window') {
  for (const [x, y] of [[380, 640], [190, 320], [570, 960]]) run.input({ type: 'touch', phase: 'down', id: 0, x, y });
}
const { wall, cpu } = timeTicks(() => run.tick(), ticks);
const grid = run.frost.index.grid, held = new Set();
for (let i = 0; i < run.frost.count; i++) {
  if (run.frost.crystalAlive[i]) held.add(grid.key(run.frost.crystals[2 * i], run.frost.crystals[2 * i + 1]));
}
for (const [name, v] of [['wall', wall], ['cpu', cpu]]) {
  const s = [...v].sort((a, b) => a - b);
  console.log(`${preset} seed ${seed}, ${ticks} ticks, ${name}: median ${quantile(s, 0.5).toFixed(2)} ms, p99 ${quantile(s, 0.99).toFixed(2)} ms, max ${s.at(-1).toFixed(2)} ms`);
}
console.log(`crystals ${run.frost.alive}, cells held ${(held.size / grid.size).toFixed(3)}`);
