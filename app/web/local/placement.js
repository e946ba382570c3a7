// Where walkers are placed in their areas (Sec. 3.4.2; sim/core/placement.py): uniform
// draws in the area's annulus outside candidate cells, a few rounds, then its free cells
// directly (at most CELL_WORK a tick), so a full area costs one look at its cells and
// nothing loops without bound.

import { float32Of } from './random.js';

const TWO_PI = Math.fround(2 * Math.PI);
// Draws a walker takes among its area's free cells before it is dropped.
export const CELL_TRIES = 8;
// Walkers one tick may place from cells; the rest find no spot and are dropped.
export const CELL_WORK = 400;

export class Placer {
  constructor(uniform, index, areas, params) {
    this.uniform = uniform;
    this.index = index;
    this.areas = areas;
    this.launch = params.launch;
    this.grow = params.grow;
    this.cellWork = CELL_WORK;  // cell placements left in this tick
    this.plans = new Map();  // area -> its cells while the ice stays as it is
    this.plansKey = '';
    this.full = new Map();  // areas whose annulus was last seen with no free cell
    this.x = 0;  // the spot `place` found
    this.y = 0;
  }

  clear() {
    this.plans.clear();
    this.full.clear();
    this.plansKey = '';
  }

  /** A uniform spot of `area`'s annulus, on the screen, outside candidate cells, into
   * (this.x, this.y); false where there is none. `many`: the walker is one of over 1 024
   * placed together (fewer disc draws before the cells, as sim/ does); `ice` says when
   * the ice last changed. */
  place(area, many, ice) {
    if (!this.full.get(area)) {
      const tries = (many ? 3 : 4) + (this.launch ? 16 : 0);
      if (this.discSpot(area, tries)) return true;
    }
    if (this.cellWork <= 0) return false;
    this.cellWork--;
    return this.cellSpot(area, ice);
  }

  discSpot(area, tries) {
    const a = this.areas.rows, [inner, outer] = this.areas.shell(area, this.launch);
    const cx = a[5 * area], cy = a[5 * area + 1];
    const i2 = Math.fround(inner * inner), span = Math.fround(Math.fround(outer * outer) - i2);
    for (let t = 0; t < tries; t++) {
      const r = Math.fround(Math.sqrt(Math.fround(i2 + Math.fround(float32Of(this.uniform()) * span))));
      const th = Math.fround(float32Of(this.uniform()) * TWO_PI);
      const x = Math.fround(cx + Math.fround(r * Math.fround(Math.cos(th))));
      const y = Math.fround(cy + Math.fround(r * Math.fround(Math.sin(th))));
      if (this.index.free(x, y)) {
        this.x = x;
        this.y = y;
        return true;
      }
    }
    return false;
  }

  /** A spot from the area's cells (`plan`): a uniform cell, a uniform point in it, kept
   * if it lies in the annulus (anywhere in the disc on glass) and on the screen. */
  cellSpot(area, ice) {
    const plan = this.plan(area, ice), n = plan.cells.length;
    if (n === 0) return false;
    const a = this.areas.rows, cx = a[5 * area], cy = a[5 * area + 1], rOut = a[5 * area + 2];
    const index = this.index, cols = index.grid.cols, s = index.grid.cell;
    for (let t = 0; t < CELL_TRIES; t++) {
      const cell = plan.cells[Math.min(Math.floor(float32Of(this.uniform()) * n), n - 1)];
      const px = (cell % cols + float32Of(this.uniform())) * s;
      const py = (Math.floor(cell / cols) + float32Of(this.uniform())) * s;
      const d2 = (px - cx) ** 2 + (py - cy) ** 2;
      if (d2 > rOut * rOut || (!plan.glass && d2 < plan.rIn * plan.rIn)) continue;
      const x = Math.fround(px), y = Math.fround(py);
      if (px >= index.width || py >= index.height || x >= index.width || y >= index.height) continue;
      if (plan.glass && index.nearestD2(x, y) < index.apart2) continue;
      this.x = x;
      this.y = y;
      return true;
    }
    return false;
  }

  /** The cells an area's water is drawn from when its disc draws fail: its annulus's
   * free cells; in growth mode, else its whole disc's free cells, else any cell of its
   * disc, where a spot must be glass. Kept until the ice changes. */
  plan(area, ice) {
    if (ice !== this.plansKey) {
      this.plans.clear();
      this.plansKey = ice;
    }
    let plan = this.plans.get(area);
    if (plan) return plan;
    const a = this.areas.rows, cx = a[5 * area], cy = a[5 * area + 1], rOut = a[5 * area + 2];
    let rIn = a[5 * area + 3];
    const count = this.index.candidates.count, annulus = [], free = [], disc = [];
    this.index.boxCells(cx, cy, rOut, (cell, near2, far2) => {
      if (near2 > rOut * rOut) return;
      disc.push(cell);
      if (count[cell] !== 0) return;
      free.push(cell);
      if (far2 >= rIn * rIn) annulus.push(cell);
    });
    let cells = annulus, glass = false;
    const full = annulus.length === 0;
    if (full && this.grow) {
      rIn = 0;
      cells = free;
      if (free.length === 0) {
        cells = disc;
        glass = true;
      }
    }
    plan = { cells: Int32Array.from(cells), rIn, glass };
    this.plans.set(area, plan);
    this.full.set(area, full);
    return plan;
  }
}

/** A uniform point of the ring from hc to 2 hc around (cx, cy), float32, as [x, y]. */
export function ringSpot(uniform, cx, cy, hc) {
  const r = hc * Math.sqrt(1 + 3 * uniform()), th = TWO_PI * uniform();
  return [Math.fround(cx + r * Math.cos(th)), Math.fround(cy + r * Math.sin(th))];
}
