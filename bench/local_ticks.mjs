// The page's own simulation's tick time in Node: `node bench/local_ticks.mjs [seed] [--cold]`.
// The fern preset, three and ten touches at the spots `frost bench sim --section fern`
// uses (app/bench/fern.py TOUCHES), 250 ticks each; prints the median and the 99th
// percentile of a tick in ms, by the wall clock and in the process's CPU time (which a
// loaded machine's other work does not lengthen). The parameters come from sim/params.py through the
// checkout's Python (FROST_PYTHON, default .venv/bin/python), as the page gets them served.

import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { Frost } from '../app/web/local/frost.js';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const PYTHON = process.env.FROST_PYTHON || path.join(ROOT, '.venv/bin/python');
const TOUCHES = [[380, 640], [190, 320], [570, 960], [570, 320], [190, 960], [380, 200], [380, 1080],
  [120, 640], [640, 640], [380, 420]];
const TICKS = 250;

function fernParams() {
  const code = 'import json; from sim.params import Params; print(json.dumps(Params.preset("fern").as_dict()))';
  return JSON.parse(execFileSync(PYTHON, ['-c', code], { cwd: ROOT, encoding: 'utf-8' }));
}

function quantile(sorted, q) {
  return sorted[Math.min(sorted.length - 1, Math.ceil(q * sorted.length) - 1)];
}

const params = fernParams(), seed = Number(process.argv[2] || 0);
// A worker grows frost for as long as the page is open: the first ticks of each code path,
// which the engine compiles (and may compile again), are left out of the figures by a
// warm-up run of every case on another seed. `--cold` measures without it.
const cold = process.argv.includes('--cold');
for (const touches of cold ? [] : [3, 10]) grow(touches, seed + 1000);

function grow(touches, runSeed, wall = [], cpu = []) {
  const frost = new Frost(params, { seed: runSeed });
  for (const [x, y] of TOUCHES.slice(0, touches)) frost.touch(x, y);
  for (let t = 0; t < TICKS; t++) {
    const t0 = performance.now(), c0 = process.cpuUsage();
    frost.step();
    const c = process.cpuUsage(c0);
    wall.push(performance.now() - t0);
    cpu.push((c.user + c.system) / 1000);
  }
  return frost;
}

for (const touches of [3, 10]) {
  const wall = [], cpu = [], frost = grow(touches, seed, wall, cpu);
  const [w, c] = [wall.sort((a, b) => a - b), cpu.sort((a, b) => a - b)];
  const figures = (s) => `median ${quantile(s, 0.5).toFixed(2)} p99 ${quantile(s, 0.99).toFixed(2)}`;
  console.log(`${String(touches).padStart(2)} touches: wall ${figures(w)}; CPU ${figures(c)} `
    + `(${frost.count} crystals, ${frost.waterCount} walkers)`);
}
