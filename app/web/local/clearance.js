// Long jumps (fern rule 3; sim/index/clearance.py): per hash cell, a lower bound of the
// distance to ice in whole cells (the Chebyshev rings to the nearest candidate cell,
// capped), so a walker far from ice jumps to its clearance circle in one step.

export const CAP = 8;
// Jumps stop this many px short of the bound (float32 rounding never lands one on ice).
const MARGIN = Math.fround(1e-2);

// Within this of a whole number, a product with 1 / cell may not truncate as the float32
// quotient does: well above the double product's error and the float32 rounding (2^-24 of
// a quotient below 2^7: under 1e-5), well below the share of walkers it sends the slow way.
const NEAR_WHOLE = 1e-4;

/** trunc(float32(v / s)), sim/'s cell of a coordinate v >= 0: by the product with
 * `inverse` (1 / s) where that cannot be wrong, else by the division (a division of a
 * walker's x and y took a quarter of the clearances' time). */
export function cellOf(v, s, inverse) {
  const t = v * inverse, q = Math.trunc(t), part = t - q;
  return part > NEAR_WHOLE && part < 1 - NEAR_WHOLE ? q : Math.trunc(Math.fround(v / s));
}

export class Clearance {
  constructor(grid, width, height, cap = CAP) {
    this.grid = grid;
    this.w = Math.fround(width);
    this.h = Math.fround(height);
    this.cap = cap;
    // The rings live on the grid padded by `cap` cells each side: lowering them needs
    // no bounds check.
    this.paddedCols = grid.cols + 2 * cap;
    this.padded = new Int16Array((grid.rows + 2 * cap) * this.paddedCols);
    this.origin = cap * this.paddedCols + cap;
    this.cell = Math.fround(grid.cell);
    // (k - 1) cells in px for each ring count k (float32 products, as sim/ keeps them)
    this.beyond = new Float64Array(cap + 1).map((_, k) => Math.fround((k - 1) * this.cell));
    this.clear();
  }

  clear() {
    this.padded.fill(this.cap);
  }

  /** The rings from flat cell `cell` to the nearest candidate cell (at most the cap). */
  ring(cell) {
    const cols = this.grid.cols;
    return this.padded[this.origin + Math.floor(cell / cols) * this.paddedCols + (cell % cols)];
  }

  /** `cell` just became a candidate cell: lower the rings around it. */
  lower(cell) {
    const cap = this.cap, pc = this.paddedCols, cols = this.grid.cols;
    const at = this.origin + Math.floor(cell / cols) * pc + (cell % cols);
    for (let oy = -cap; oy <= cap; oy++) {
      const row = at + oy * pc, ay = oy < 0 ? -oy : oy;
      for (let ox = -cap; ox <= cap; ox++) {
        const ring = Math.max(ay, ox < 0 ? -ox : ox);
        if (ring < this.padded[row + ox]) this.padded[row + ox] = ring;
      }
    }
  }

  /** The clearance in px of every walker of `water` (on-screen float32 positions, each
   * in its area of `rows`: centre x, y, outer radius) into `out`: 0 or less in and next to
   * candidate cells. One loop, nothing returned per walker (no number boxed). */
  radii(water, rows, out) {
    const s = this.cell, { x, y, area } = water, pc = this.paddedCols, rings = this.padded;
    const beyond = this.beyond, origin = this.origin, w = this.w, h = this.h, n = water.n;
    const inverse = 1 / s;
    for (let i = 0; i < n; i++) {
      const a5 = 5 * area[i], px = x[i], py = y[i];
      const ox = Math.fround(px - rows[a5]), oy = Math.fround(py - rows[a5 + 1]);
      const rim = Math.fround(rows[a5 + 2] - Math.fround(Math.sqrt(ox * ox + oy * oy)));
      const qx = cellOf(px, s, inverse), qy = cellOf(py, s, inverse);
      const fx = Math.fround(px - Math.fround(qx * s)), fy = Math.fround(py - Math.fround(qy * s));
      const border = Math.min(fx, Math.fround(s - fx), fy, Math.fround(s - fy));
      const rho = Math.max(beyond[rings[origin + qy * pc + qx]] + border, 0);
      const edge = Math.min(px, Math.fround(w - px), py, Math.fround(h - py));
      out[i] = Math.min(rho, rim, edge) - MARGIN;
    }
  }
}
