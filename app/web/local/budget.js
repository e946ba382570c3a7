// The budgets a tick keeps (sim/core/budget.py): the cells' cap (CELL_CAP crystals a
// cell may list) and the freezing work (FREEZE_WORK grid-vertex raises a tick).

import { CELL_CAP, FREEZE_WORK } from './shared.js';
export { CELL_CAP, FREEZE_WORK };

/** Grid vertices one new crystal may raise: its link's particles times the geometry
 * stencil (vertices `gridSpacing` apart within hc). */
export function workPerCrystal(hc, gridSpacing, spacing) {
  const reach = Math.ceil(hc / gridSpacing) + 1;
  const perLink = 1 + Math.max(0, Math.floor(hc / spacing) - 1);
  return perLink * (2 * reach + 1) ** 2;
}

export class Budget {
  constructor(index, params) {
    this.index = index;
    this.hc = params.hc;
    this.take = Math.max(1, Math.floor(FREEZE_WORK / workPerCrystal(params.hc, params.grid_spacing, params.D)));
    this.ranks = new Map();
  }

  /** The freezes (walkers `hits[j]` onto crystals `parents[j]`, j < n, walker order) a
   * tick takes: the first within FREEZE_WORK (the rest wait a tick as water), then those
   * whose discs keep every cell within CELL_CAP; a walker over the cap is marked to drop
   * from `water`. Compacts the arrays; returns [kept, dropped]. */
  admit(hits, parents, n, water) {
    n = Math.min(n, this.take);
    const lists = this.index.candidates;
    if (lists.countBound + n <= CELL_CAP) return [n, 0];  // no cell can fill up this tick
    const xy = new Float32Array(2 * n);
    for (let j = 0; j < n; j++) {
      xy[2 * j] = water.x[hits[j]];
      xy[2 * j + 1] = water.y[hits[j]];
    }
    const ok = this.roomFor(xy, 2);
    let m = 0;
    for (let j = 0; j < n; j++) {
      if (ok[j]) {
        hits[m] = hits[j];
        parents[m++] = parents[j];
      } else {
        water.drop[hits[j]] = 1;
      }
    }
    return [m, n - m];
  }

  /** Which new crystals at `xy` (x, y every `stride` numbers, in order) keep every cell
   * their freezing disc lists them in within CELL_CAP, counting the earlier ones. */
  roomFor(xy, stride) {
    const n = xy.length / stride, ok = new Uint8Array(n).fill(1), lists = this.index.candidates;
    if (lists.countBound + n <= CELL_CAP) return ok;
    const grid = this.index.grid, ranks = this.ranks;
    ranks.clear();
    for (let j = 0; j < n; j++) {
      const cells = grid.discCells(xy[stride * j], xy[stride * j + 1], this.hc);
      for (let c = 0; c < cells; c++) {
        const cell = grid.cells[c], rank = ranks.get(cell) || 0;
        ranks.set(cell, rank + 1);
        if (lists.count[cell] + rank >= CELL_CAP) ok[j] = 0;
      }
    }
    return ok;
  }
}
