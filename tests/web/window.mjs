// What the Node tests of the page's frosted window share: the window preset grown by the
// page's Frost as tests/support/simoracle.py's `window` grows sim/'s (no touch: the
// pane's own seeds), its cells' cover, and sim/'s pane measures (app/bench/measures.py)
// of the skeleton the page grew.

import { spawn } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { Frost } from '../../app/web/local/frost.js';
import { python } from './simoracle.mjs';

const ROOT = process.env.FROST_ROOT || path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const PYTHON = process.env.FROST_PYTHON || path.join(ROOT, '.venv/bin/python');

/** sim/'s answer to `request` as a promise: the oracle runs beside the page's growth. */
export function pythonLater(request) {
  return new Promise((resolve, reject) => {
    const child = spawn(PYTHON, [path.join(ROOT, 'tests/support/simoracle.py')]);
    let out = '', err = '';
    child.stdout.on('data', (d) => { out += d; });
    child.stderr.on('data', (d) => { err += d; });
    child.on('close', (code) => (code === 0 ? resolve(JSON.parse(out.replace(/\bNaN\b/g, 'null')))
      : reject(new Error(`simoracle.py: ${err.slice(-2000)}`))));
    child.stdin.end(JSON.stringify(request));
  });
}

/** Share of the hash grid's cells holding a live crystal of `frost`. */
export function cover(frost) {
  const grid = frost.index.grid, held = new Uint8Array(grid.size);
  let n = 0;
  for (let i = 0; i < frost.count; i++) {
    if (!frost.crystalAlive[i]) continue;
    const k = grid.key(frost.crystals[2 * i], frost.crystals[2 * i + 1]);
    if (!held[k]) n++;
    held[k] = 1;
  }
  return n / grid.size;
}

/** The page's window (`params`) grown on a `size` pane from `seed`: the ticks to `coverTo`
 * of the cells (null past `most` ticks), and at `measureAt` the frost itself. */
export function growWindow(params, seed, { size = [760, 1280], coverTo = null, most = 0, measureAt = 0 } = {}) {
  const [width, height] = size, frost = new Frost(params, { width, height, seed });
  let reached = null;
  while (frost.tick < Math.max(measureAt, most)) {
    frost.step();
    if (coverTo !== null && reached === null && cover(frost) >= coverTo) {
      reached = frost.tick;
      if (frost.tick >= measureAt) break;
    }
    if (frost.tick === measureAt && (coverTo === null || reached !== null)) break;
  }
  return { frost, reached };
}

/** sim/'s pane measures (stem_lw, main_frac, pinnate, order, clear21, frame_mid, cells) of
 * the page's frost. */
export function paneMeasures(frost) {
  const n = frost.count, ups = [];
  for (let j = 0; j < frost.upsampledCount; j++) {
    if (frost.upsampledAlive[j]) ups.push(frost.upsampled[2 * j], frost.upsampled[2 * j + 1]);
  }
  return python({ kind: 'pane_measure', crystals: Array.from(frost.crystals.subarray(0, 2 * n)),
    parents: Array.from(frost.parents.subarray(0, n)), alive: Array.from(frost.crystalAlive.subarray(0, n)),
    upsampled: ups, width: frost.width, height: frost.height, hc: frost.params.hc });
}

/** sim/'s window grown from each of `seeds` (simoracle.py's `window`), as a promise. */
export function simWindow(seeds, request) {
  return pythonLater({ kind: 'window', seeds, ...request });
}
