// Where walkers are placed in their areas (Sec. 3.4.2; sim/core/placement.py): uniform
// draws in the area's annulus outside candidate cells, a few rounds, then its free cells
// directly (at most CELL_WORK a tick), so a full area costs one look at its cells and
// nothing loops without bound.

import { drawInto } from './random.js';
import { BARE_DRAWS, CELL_TRIES, CELL_WORK } from './shared.js';

const TWO_PI = Math.fround(2 * Math.PI);
// (CELL_TRIES: draws a walker takes among its area's free cells before it is dropped;
// CELL_WORK: walkers one tick may place from cells, the rest owed to their areas (`owe`)
// and placed first in the next tick; BARE_DRAWS: draws of an area's cells, all on ice,
// that show its disc has no glass left, its kept pool waiting for a melt, not topped up
// every tick in vain.)
export { BARE_DRAWS, CELL_TRIES, CELL_WORK };

export class Placer {
  constructor(uniform, index, areas, params, pane = null) {
    this.uniform = uniform;
    this.pane = pane && pane.on ? pane : null;  // window mode: the pane places its water
    this.index = index;
    this.areas = areas;
    this.launch = params.launch;
    this.grow = params.grow;
    this.cellWork = CELL_WORK;  // cell placements left in this tick
    this.plans = new Map();  // area -> its cells while the ice stays as it is
    this.plansKey = -1;
    this.full = new Map();  // areas whose annulus was last seen with no free cell
    this.bare = new Map();  // areas whose disc was last seen with no glass: the melts then
    this.owe = false;  // `place` found no spot, but the walker is owed, not dropped
    this.width = index.width;
    this.height = index.height;
    this.spot = new Float32Array(2);  // the spot `place` found (a field would box it)
    // Uniform draws taken a block at a time (float32, as sim/ draws them): a number
    // returned by a call for each draw would be boxed, thousands of times a tick.
    this.draws = new Float32Array(4096);
    this.at = this.draws.length;
  }

  /** The next `k` draws start at `this.at` (a fresh block where the last ran out). */
  take(k) {
    if (this.at + k > this.draws.length) {
      drawInto(this.uniform, this.draws);
      this.at = 0;
    }
    const at = this.at;
    this.at += k;
    return at;
  }

  clear() {
    this.plans.clear();
    this.full.clear();
    this.bare.clear();
    this.plansKey = -1;
  }

  /** A uniform spot of `area`'s annulus, on the screen, outside candidate cells, into
   * `this.spot`; false where there is none. `many`: the walker is one of over 1 024
   * placed together (fewer disc draws before the cells, as sim/ does); `ice` says when
   * the ice last changed. Where it finds no spot, `this.owe` says whether the walker is
   * owed to its area (the tick's cell work ran out, or its draws missed while the area
   * may still hold glass) rather than dropped (no free cell, no glass left). */
  place(area, many, ice) {
    this.owe = false;
    if (this.pane) {  // (no cell work: the pane's cells are its own)
      if (!this.pane.placeOne()) return false;
      this.spot[0] = this.pane.spot[0];
      this.spot[1] = this.pane.spot[1];
      return true;
    }
    if (!this.full.get(area)) {
      const tries = (many ? 3 : 4) + (this.launch ? 16 : 0);
      if (this.discSpot(area, tries)) return true;
    }
    if (this.cellWork <= 0) {
      this.owe = true;
      return false;
    }
    this.cellWork--;
    if (this.cellSpot(area, ice)) return true;
    this.owe = this.plans.get(area).cells.length > 0 && !this.isBare(area, ice);
    return false;
  }

  /** Area `area`'s disc was last seen with no glass, and nothing melted since. */
  isBare(area, ice) {
    return this.bare.get(area) === ice % 4294967296;
  }

  /** Growth mode: area `area`'s launch circle lies wholly beyond the screen (past its
   * farthest corner), so no draw on it lands on the screen. */
  beyondScreen(area) {
    if (!(this.grow && this.launch)) return false;
    const a = this.areas.rows, cx = a[5 * area], cy = a[5 * area + 1];
    const fx = Math.max(cx, this.width - cx), fy = Math.max(cy, this.height - cy);
    const ring = a[5 * area + 4] + this.launch;
    return ring * ring > fx * fx + fy * fy;
  }

  discSpot(area, tries) {
    this.areas.shell(area, this.launch);
    const a = this.areas.rows, inner = this.areas.inner, outer = this.areas.outer;
    const cx = a[5 * area], cy = a[5 * area + 1];
    const i2 = Math.fround(inner * inner), span = Math.fround(Math.fround(outer * outer) - i2);
    // (the count runs down in the loop's test, which every call runs: a step run only when
    // a draw misses, seen first deep into a growth, would throw the compiled placement away)
    while (tries-- > 0) {
      const at = this.take(2), u = this.draws;
      const r = Math.fround(Math.sqrt(Math.fround(i2 + Math.fround(u[at] * span))));
      const th = Math.fround(u[at + 1] * TWO_PI);
      const x = Math.fround(cx + Math.fround(r * Math.fround(Math.cos(th))));
      const y = Math.fround(cy + Math.fround(r * Math.fround(Math.sin(th))));
      if (this.index.free(x, y)) {
        this.spot[0] = x;
        this.spot[1] = y;
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
    if (this.cellDraw(plan, area)) {
      plan.misses = 0;
      return true;
    }
    // All on ice: BARE_DRAWS such draws in a row with no free cell left say no glass is.
    if (plan.glass && (plan.misses += CELL_TRIES) >= BARE_DRAWS) this.bare.set(area, ice % 4294967296);
    return false;
  }

  cellDraw(plan, area) {
    const n = plan.cells.length;
    const a = this.areas.rows, cx = a[5 * area], cy = a[5 * area + 1], rOut = a[5 * area + 2];
    const index = this.index, cols = index.grid.cols, s = index.grid.cell;
    for (let t = 0; t < CELL_TRIES; t++) {
      const at = this.take(3), u = this.draws;
      const cell = plan.cells[Math.min(Math.floor(u[at] * n), n - 1)];
      const px = (cell % cols + u[at + 1]) * s;
      const py = (Math.floor(cell / cols) + u[at + 2]) * s;
      const d2 = (px - cx) ** 2 + (py - cy) ** 2;
      if (d2 > rOut * rOut || (!plan.glass && d2 < plan.rIn * plan.rIn)) continue;
      const x = Math.fround(px), y = Math.fround(py);
      if (px >= index.width || py >= index.height || x >= index.width || y >= index.height) continue;
      if (plan.glass && index.nearestD2(x, y) < index.apart2) continue;
      this.spot[0] = x;
      this.spot[1] = y;
      return true;
    }
    return false;
  }

  /** The cells an area's water is drawn from when its disc draws fail: its annulus's
   * free cells; in growth mode, else its whole disc's free cells, else any cell of its
   * disc, where a spot must be glass. Kept until the ice changes. */
  plan(area, ice) {
    if (ice !== this.plansKey) {
      for (const plan of this.plans.values()) plan.fresh = false;
      this.plansKey = ice;
    }
    let plan = this.plans.get(area);
    if (plan && plan.fresh) return plan;
    const a = this.areas.rows, cx = a[5 * area], cy = a[5 * area + 1], rOut = a[5 * area + 2];
    const index = this.index, count = index.candidates.count, n = index.boxCells(cx, cy, rOut);
    if (!plan || plan.all.length < n) plan = { all: new Int32Array(2 * n) };
    // The box's cells sorted into three runs of `all`: the annulus's free cells from the
    // front, the disc's other free cells after them, the disc's cells with ice from the back.
    const { box, near2, far2 } = index, all = plan.all, rIn = a[5 * area + 3];
    let annulus = 0, free = 0, iced = all.length;
    for (let k = 0; k < n; k++) {
      if (near2[k] > rOut * rOut) continue;
      if (count[box[k]] !== 0) all[--iced] = box[k];
      else if (far2[k] >= rIn * rIn) all[annulus++] = box[k];
      else free++;
    }
    for (let k = 0, f = annulus; free && k < n; k++) {  // the disc's free cells inside the annulus
      if (near2[k] <= rOut * rOut && count[box[k]] === 0 && far2[k] < rIn * rIn) all[f++] = box[k];
    }
    const full = annulus === 0 || this.beyondScreen(area);
    Object.assign(plan, { fresh: true, cells: all.subarray(0, annulus), rIn, glass: false, misses: 0 });
    if (full && this.grow) {
      plan.rIn = 0;
      plan.cells = free ? all.subarray(0, free) : all.subarray(iced);
      plan.glass = free === 0;
    }
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
