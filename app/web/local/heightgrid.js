// The bumpy height grid of Fig. 7 (sim/look/geometry.py's FrostGeometry._raise): every
// particle raises the grid vertices within hc of it by bump x falloff, capped at
// max_height. A raise costs O(its particles): a fixed stencil around each, and only the
// vertices it touched are summed and capped.

// Bump weight at distance d from a particle: (1 - (d/hc)^2)^2 inside hc, else 0 (zero
// slope at the rim: no creases where freezing areas end).
export function falloff(d, radius) {
  const u = Math.max(1.0 - (d * d) / (radius * radius), 0.0);
  return u * u;
}

// Round half to even, as numpy's rint.
function rint(v) {
  const r = Math.round(v);
  return r - v === 0.5 && r % 2 !== 0 ? r - 1 : r;
}

export class HeightGrid {
  constructor(params, width, height) {
    this.spacing = params.grid_spacing | 0;
    this.rows = Math.floor(height / this.spacing) + 1;
    this.cols = Math.floor(width / this.spacing) + 1;
    this.hc = params.hc;
    this.bump = params.bump;
    this.maxHeight = params.max_height;
    // Vertices that can lie within hc of a particle, around the vertex nearest it.
    this.reach = Math.ceil(params.hc / this.spacing) + 1;
    // Squared distances past this are outside hc whatever the rounding (a margin of 1e-9
    // of hc squared; Math.hypot is within an ulp of the true distance).
    this.past = this.hc * this.hc * (1 + 1e-9);
    const cells = this.rows * this.cols;
    this.heights = new Float32Array(cells);
    // The uncapped sum of the bumps, so a melt takes a particle's share back out exactly.
    this.sum = new Float64Array(cells);
    this._add = new Float64Array(cells);  // one raise's bumps, per vertex, in point order
    this._touched = new Int32Array(cells);  // the vertices one raise touched, in order
    this._marked = new Uint8Array(cells);  // 1 for those
    this._ntouched = 0;
    this._lo = Infinity;
    this._hi = -1;
    this.changed = new Int32Array(0);  // the last raise's vertices (`finish`)
  }

  clear() {
    this.heights.fill(0);
    this.sum.fill(0);
  }

  // Add one particle's bumps to the raise under way.
  point(x, y) {
    const gs = this.spacing, reach = this.reach, hc = this.hc, past = this.past;
    const r0 = rint(Math.fround(y / gs)), c0 = rint(Math.fround(x / gs));
    for (let r = r0 - reach; r <= r0 + reach; r++) {
      if (r < 0 || r >= this.rows) continue;
      const dy = r * gs - y;
      for (let c = c0 - reach; c <= c0 + reach; c++) {
        const dx = c * gs - x;
        // Most of the stencil lies well outside hc: only the rest pays for Math.hypot
        // (sim/'s np.hypot's distance, which a square root of the squares may miss by an ulp).
        if (dx * dx + dy * dy > past || c < 0 || c >= this.cols) continue;
        const d = Math.hypot(dx, dy);
        if (!(d < hc)) continue;
        const v = r * this.cols + c;
        if (!this._marked[v]) {
          this._marked[v] = 1;
          this._touched[this._ntouched++] = v;
        }
        this._add[v] += this.bump * falloff(d, hc);
        if (r < this._lo) this._lo = r;
        if (r > this._hi) this._hi = r;
      }
    }
  }

  // The raise's bumps added (sign -1: taken back) and capped; its dirty rows [lo, hi)
  // ([0, 0] if it touched none). `changed` holds the vertices it touched, ascending: the
  // only heights of those rows that can differ from before it.
  finish(sign = 1.0) {
    const add = this._add, sum = this.sum, heights = this.heights, top = this.maxHeight;
    for (let i = 0; i < this._ntouched; i++) {
      const v = this._touched[i];
      sum[v] += sign * add[v];
      const h = Math.min(sum[v], top);
      heights[v] = h < 1e-6 ? 0.0 : h;
      add[v] = 0;
      this._marked[v] = 0;
    }
    const rows = this._hi < 0 ? [0, 0] : [this._lo, this._hi + 1];
    this.changed = this._touched.slice(0, this._ntouched).sort();
    this._ntouched = 0;
    this._lo = Infinity;
    this._hi = -1;
    return rows;
  }
}
