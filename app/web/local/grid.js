// The hash grid of Sec. 3.3 (sim/index/grid.py) and its cells' crystal lists
// (sim/core/buffers.py CellLists): cells of side 2 hc, Eq. 1 rounded up.

// A crystal is listed in every cell its freezing disc reaches, widened by this many px,
// so float32 rounding of a walker's cell can never hide a crystal within hc.
export const CELL_MARGIN = 1e-2;

export class HashGrid {
  constructor(width, height, hc) {
    this.cell = 2 * hc;
    this.cols = Math.ceil(width / this.cell);  // N, Eq. 1a
    this.rows = Math.ceil(height / this.cell);  // M, Eq. 1b
    this.size = this.cols * this.rows;
    this.inverseCell = Math.fround(1 / this.cell);
    this.cells = new Int32Array(9);  // discCells' answer (at most 3 x 3 with the margin)
  }

  /** The cell (row-major) of an on-screen float32 point, as sim/ computes it: the
   * float32 product with 1 / cell, truncated, clamped to the last column and row. */
  key(x, y) {
    let kx = Math.fround(x * this.inverseCell) | 0;
    let ky = Math.fround(y * this.inverseCell) | 0;
    if (kx > this.cols - 1) kx = this.cols - 1;
    if (ky > this.rows - 1) ky = this.rows - 1;
    return ky * this.cols + kx;
  }

  /** The cells whose rectangle meets the open disc of `radius` (+ CELL_MARGIN) around
   * (x, y), row-major, into `this.cells`; returns how many. */
  discCells(x, y, radius) {
    const r = radius + CELL_MARGIN, s = this.cell, r2 = r * r;
    const nx = Math.floor((x - r) / s), ny = Math.floor((y - r) / s);
    let n = 0;
    for (let j = 0; j < 3; j++) {
      const row = ny + j;
      if (row < 0 || row >= this.rows) continue;
      const gy = Math.max(Math.max(row * s - y, 0), y - (row + 1) * s);
      for (let i = 0; i < 3; i++) {
        const col = nx + i;
        if (col < 0 || col >= this.cols) continue;
        const gx = Math.max(Math.max(col * s - x, 0), x - (col + 1) * s);
        if (gy * gy + gx * gx < r2) this.cells[n++] = row * this.cols + col;
      }
    }
    return n;
  }

  /** [col0, col1, row0, row1] (inclusive, clipped) of the cells under a px box. */
  span(x0, y0, x1, y1) {
    return [Math.max(Math.floor(x0 / this.cell), 0), Math.min(Math.floor(x1 / this.cell), this.cols - 1),
      Math.max(Math.floor(y0 / this.cell), 0), Math.min(Math.floor(y1 / this.cell), this.rows - 1)];
  }
}

/** For every cell, the ascending indices of the crystals listed in it: `count[cell]`
 * and `items[cell * width + j]`; the width doubles when a cell overflows. */
export class CellLists {
  constructor(nCells, width = 8) {
    this.count = new Int32Array(nCells);
    this.width = width;
    this.items = new Int32Array(nCells * width);
    this.countBound = 0;  // at least the largest count (removals leave it high)
  }

  /** Lists `id` in `cell` (ids come ascending: a new crystal's index is the largest);
   * returns true where the cell listed nothing before. */
  insert(cell, id) {
    const n = this.count[cell];
    if (n >= this.width) this.widen();
    this.items[cell * this.width + n] = id;
    this.count[cell] = n + 1;
    if (n + 1 > this.countBound) this.countBound = n + 1;
    return n === 0;
  }

  /** Takes `id` out of `cell`'s list (order kept). */
  remove(cell, id) {
    const base = cell * this.width, n = this.count[cell];
    let j = 0;
    while (j < n && this.items[base + j] !== id) j++;
    if (j === n) return;
    this.items.copyWithin(base + j, base + j + 1, base + n);
    this.count[cell] = n - 1;
  }

  clear() {
    this.count.fill(0);
    this.countBound = 0;
  }

  widen() {
    const width = this.width * 2, items = new Int32Array(this.count.length * width);
    for (let c = 0; c < this.count.length; c++) {
      const n = this.count[c];
      if (n) items.set(this.items.subarray(c * this.width, c * this.width + n), c * width);
    }
    this.items = items;
    this.width = width;
  }
}
