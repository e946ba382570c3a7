// One freezing index over the crystals (sim/index/freezing.py, search.py): the hash
// grid's candidate cells (Sec. 3.4.1), the paper's neighbour search (Sec. 3.4.3), the
// clearance rings of the long jumps, and the queries the rules and placement ask.

import { Clearance } from './clearance.js';
import { CellLists, HashGrid } from './grid.js';

export class FreezingIndex {
  /** Where the live crystals of `ice` (read, never written) are: each is listed in
   * every cell its freezing disc (radius hc) meets. */
  constructor(ice, width, height, hc, longJumps) {
    this.ice = ice;
    this.width = width;
    this.height = height;
    this.hc = hc;
    this.hc2 = Math.fround(Math.fround(hc) * Math.fround(hc));
    this.apart2 = Math.fround(Math.fround(hc / 2) * Math.fround(hc / 2));
    this.grid = new HashGrid(width, height, hc);
    this.candidates = new CellLists(this.grid.size);  // Fig. 3d: state = count > 0
    this.clearance = longJumps ? new Clearance(this.grid, width, height) : null;
    this.found = new Int32Array(64);  // crystalsInBox's answer
    // nearestIn's and boxCells' answers, made here (one object shape from the start, which
    // the compiled simulation is specialised for)
    this.nearestId = -1;
    this.box = new Int32Array(0);
    this.near2 = new Float64Array(0);
    this.far2 = new Float64Array(0);
  }

  clear() {
    this.candidates.clear();
    if (this.clearance) this.clearance.clear();
  }

  /** Sec. 3.4.1: list crystals [start, end) in the cells their freezing discs reach. */
  register(start, end) {
    const c = this.ice.crystals, grid = this.grid, lists = this.candidates;
    for (let i = start; i < end; i++) {
      const n = grid.discCells(c[2 * i], c[2 * i + 1], this.hc);
      for (let j = 0; j < n; j++) {
        const cell = grid.cells[j];
        if (lists.insert(cell, i) && this.clearance) this.clearance.lower(cell);
      }
    }
  }

  /** Melted crystals leave their cells. */
  remove(dead) {
    const c = this.ice.crystals, grid = this.grid;
    for (const i of dead) {
      const n = grid.discCells(c[2 * i], c[2 * i + 1], this.hc);
      for (let j = 0; j < n; j++) this.candidates.remove(grid.cells[j], i);
    }
  }

  /** Sec. 3.4.3 for a walker at float32 (x, y) in cell `key`: the nearest crystal listed
   * there (the lowest index among equals) if it lies within hc (d^2 < hc^2 in float32,
   * as sim/ computes it), else -1. */
  nearest(x, y, key) {
    const n = this.candidates.count[key];
    if (n === 0) return -1;
    const d2 = this.nearestIn(x, y, key, n);
    return d2 < this.hc2 ? this.nearestId : -1;
  }

  /** The squared distance (float32) from (x, y) to the nearest live crystal listed in
   * its cell (Infinity if none); any crystal within hc of a point is listed there. */
  nearestD2(x, y) {
    const key = this.grid.key(x, y), n = this.candidates.count[key];
    return n === 0 ? Infinity : this.nearestIn(x, y, key, n);
  }

  nearestIn(x, y, key, n) {
    const c = this.ice.crystals, items = this.candidates.items, base = key * this.candidates.width;
    let best = Infinity, id = -1;
    for (let j = 0; j < n; j++) {
      const i = items[base + j];
      const dx = Math.fround(c[2 * i] - x), dy = Math.fround(c[2 * i + 1] - y);
      const d2 = Math.fround(Math.fround(dx * dx) + Math.fround(dy * dy));
      if (d2 < best) {
        best = d2;
        id = i;
      }
    }
    this.nearestId = id;
    return best;
  }

  /** On the screen and in no candidate cell. */
  free(x, y) {
    return x >= 0 && x < this.width && y >= 0 && y < this.height
      && this.candidates.count[this.grid.key(x, y)] === 0;
  }

  /** On the screen's far edges and at least hc / 2 from every live crystal. */
  glass(x, y) {
    return x < this.width && y < this.height && this.nearestD2(x, y) >= this.apart2;
  }

  /** Ascending indices of the live crystals listed in the cells under a px box (a
   * superset of those inside it), as an Int32Array view valid until the next call. */
  crystalsInBox(x0, y0, x1, y1) {
    const [c0, c1, r0, r1] = this.grid.span(x0, y0, x1, y1);
    const lists = this.candidates;
    let n = 0;
    for (let row = r0; row <= r1; row++) {
      for (let col = c0; col <= c1; col++) {
        const cell = row * this.grid.cols + col, k = lists.count[cell];
        if (n + k > this.found.length) this.widenFound(n + k);
        this.found.set(lists.items.subarray(cell * lists.width, cell * lists.width + k), n);
        n += k;
      }
    }
    const sorted = this.found.subarray(0, n).sort();
    let m = 0;
    for (let j = 0; j < n; j++) if (j === 0 || sorted[j] !== sorted[j - 1]) sorted[m++] = sorted[j];
    return sorted.subarray(0, m);
  }

  widenFound(need) {
    let size = this.found.length;
    while (size < need) size *= 2;
    const found = new Int32Array(size);
    found.set(this.found);
    this.found = found;
  }

  /** Ascending indices (a fresh Int32Array) of the live crystals closer than `radius`
   * to (x, y). */
  crystalsNear(x, y, radius) {
    const ids = this.crystalsInBox(x - radius, y - radius, x + radius, y + radius);
    const c = this.ice.crystals, out = [];
    for (const i of ids) if (Math.hypot(c[2 * i] - x, c[2 * i + 1] - y) < radius) out.push(i);
    return Int32Array.from(out);
  }

  /** The cells under the disc's bounding box into `this.box` (flat indices), with the
   * squared distance from (cx, cy) to each one's nearest point (`this.near2`) and farthest
   * (`this.far2`); returns how many. Typed arrays kept between calls: nothing allocated. */
  boxCells(cx, cy, r) {
    const [c0, c1, r0, r1] = this.grid.span(cx - r, cy - r, cx + r, cy + r);
    const s = this.grid.cell, n = Math.max(0, (c1 - c0 + 1) * (r1 - r0 + 1));
    if (this.box.length < n) {
      this.box = new Int32Array(2 * n);
      this.near2 = new Float64Array(2 * n);
      this.far2 = new Float64Array(2 * n);
    }
    let k = 0;
    for (let row = r0; row <= r1; row++) {
      const y0 = row * s, ny = Math.min(Math.max(cy, y0), y0 + s) - cy;
      const fy = Math.max(Math.abs(y0 - cy), Math.abs(y0 + s - cy));
      for (let col = c0; col <= c1; col++, k++) {
        const x0 = col * s, nx = Math.min(Math.max(cx, x0), x0 + s) - cx;
        const fx = Math.max(Math.abs(x0 - cx), Math.abs(x0 + s - cx));
        this.box[k] = row * this.grid.cols + col;
        this.near2[k] = nx * nx + ny * ny;
        this.far2[k] = fx * fx + fy * fy;
      }
    }
    return k;
  }
}
