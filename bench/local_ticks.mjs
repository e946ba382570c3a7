// The page's own simulation's tick time in Node: `node bench/local_ticks.mjs [seed] [--cold]`,
// with `sim/`'s beside it (the same touches and ticks, through the checkout's Python).
// The fern preset, three and ten touches at the spots `frost bench sim --section fern`
// uses (app/bench/fern.py TOUCHES), 250 ticks each; prints the median and the 99th
// percentile of a tick in ms, by the wall clock and in the process's CPU time (which a
// loaded machine's other work does not lengthen). The parameters come from sim/params.py
// through the checkout's Python (FROST_PYTHON, default .venv/bin/python), as the page gets
// them served.

import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { Frost } from '../app/web/local/frost.js';
import { quantile, timeTicks } from './ticks.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const PYTHON = process.env.FROST_PYTHON || path.join(ROOT, '.venv/bin/python');
const TOUCHES = [[380, 640], [190, 320], [570, 960], [570, 320], [190, 960], [380, 200], [380, 1080],
  [120, 640], [640, 640], [380, 420]];
const TICKS = 250;

function fernParams() {
  const code = 'import json; from sim.params import Params; print(json.dumps(Params.preset("fern").as_dict()))';
  return JSON.parse(execFileSync(PYTHON, ['-c', code], { cwd: ROOT, encoding: 'utf-8' }));
}

// sim/'s ticks on the same touches, by the wall clock and in CPU time (time.process_time).
const SIM_TICKS = `
import json, sys, time
from app.bench.fern import TOUCHES
from sim import FrostSim, Params
touches, seed, ticks = (int(v) for v in sys.argv[1:4])
sim = FrostSim(Params.preset("fern"), seed=seed)
for x, y in TOUCHES[:touches]:
    sim.touch(x, y)
wall, cpu = [], []
for _ in range(ticks):
    t0, c0 = time.perf_counter(), time.process_time()
    sim.step()
    wall.append(1e3 * (time.perf_counter() - t0))
    cpu.append(1e3 * (time.process_time() - c0))
print(json.dumps([wall, cpu, len(sim.crystals)]))
`;

function simTicks(touches, runSeed) {
  const out = execFileSync(PYTHON, ['-c', SIM_TICKS, String(touches), String(runSeed), String(TICKS)],
    { cwd: ROOT, encoding: 'utf-8' });
  return JSON.parse(out);
}

const params = fernParams(), seed = Number(process.argv[2] || 0);
console.log(`the page's simulation in Node ${process.version} and sim/: fern, ${TICKS} ticks a run, ms a tick`);
// A worker grows frost for as long as the page is open: the first ticks of each code path,
// which the engine compiles (and may compile again), are left out of the figures by a
// warm-up run of every case on another seed. `--cold` measures without it.
const cold = process.argv.includes('--cold');
for (const touches of cold ? [] : [3, 10]) grow(touches, seed + 1000);

function grow(touches, runSeed, wall = [], cpu = []) {
  const frost = new Frost(params, { seed: runSeed });
  for (const [x, y] of TOUCHES.slice(0, touches)) frost.touch(x, y);
  timeTicks(() => frost.step(), TICKS, wall, cpu);
  return frost;
}

const figures = (s) => `median ${quantile(s, 0.5).toFixed(2)} p99 ${quantile(s, 0.99).toFixed(2)}`;
const sorted = (values) => [...values].sort((a, b) => a - b);
for (const touches of [3, 10]) {
  const wall = [], cpu = [], frost = grow(touches, seed, wall, cpu);
  console.log(`${String(touches).padStart(2)} touches, page: wall ${figures(sorted(wall))}; CPU `
    + `${figures(sorted(cpu))} (${frost.count} crystals, ${frost.waterCount} walkers)`);
  const [simWall, simCpu, crystals] = simTicks(touches, seed);
  console.log(`${String(touches).padStart(2)} touches, sim/: wall ${figures(sorted(simWall))}; CPU `
    + `${figures(sorted(simCpu))} (${crystals} crystals)`);
}
