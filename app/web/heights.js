// The ice pass's height grid: the heights mirrored as the deltas bring them, and a
// half-float RGB texture of them (height, slope x, slope y by central differences, worked
// out for the dirty rows only).

import { floatToHalf } from "./protocol.js";
import { texture } from "./programs.js";

export class HeightGrid {
  // grid: [cols, rows] of vertices, spacing px apart.
  constructor(gl, grid, spacing) {
    this.gl = gl;
    this.gridSize = grid;
    this.spacing = spacing;
    this.grid = new Float32Array(grid[0] * grid[1]);  // mirror of the heights, row-major
    this.texels = new Uint16Array(grid[0] * grid[1] * 3);  // mirror of the texture
    // The same bytes as half floats, where the browser has them (rounded to nearest even,
    // as floatToHalf: a third of the time for a whole grid)
    this.halves = typeof Float16Array === "function" ? new Float16Array(this.texels.buffer) : null;
    this.texture = texture(gl, grid[0], grid[1], gl.RGB16F, gl.LINEAR);
  }

  // A delta's runs of heights into the grid and the texture. `iced(c, r)` is told each
  // vertex that gets ice, `damage(x0, y0, x1, y1)` each px box (y down) whose pixels change.
  apply(delta, iced, damage) {
    const [cols, rows] = this.gridSize;
    if (delta.grid[0] !== cols || delta.grid[1] !== rows) {
      throw new Error(`a delta for a ${delta.grid} grid, the page holds ${this.gridSize}`);
    }
    const touched = new Uint8Array(rows);
    let k = 0;
    for (const [start, count] of delta.runs) {
      for (let i = start; i < start + count; i++, k++) {
        const h = delta.heights[k];
        if (h > 0 && this.grid[i] === 0) iced(i % cols, Math.floor(i / cols));
        this.grid[i] = h;
      }
      // A vertex's height changes its neighbours' slopes, and bilinear filtering spreads
      // each texel one grid cell further: two cells each way (and a px).
      // A run that wraps onto later rows: its first row's end, the whole rows between
      // and its last row's start.
      const s = this.spacing, r0 = Math.floor(start / cols), r1 = Math.floor((start + count - 1) / cols);
      const c0 = start % cols, c1 = (start + count - 1) % cols;
      const cells = (ca, ra, cb, rb) => damage((ca - 2) * s - 1, (ra - 2) * s - 1, (cb + 2) * s + 1, (rb + 2) * s + 1);
      if (r1 === r0) cells(c0, r0, c1, r0);
      else {
        cells(c0, r0, cols - 1, r0);
        if (r1 > r0 + 1) cells(0, r0 + 1, cols - 1, r1 - 1);
        cells(0, r1, c1, r1);
      }
      for (let r = r0; r <= r1; r++) touched[r] = 1;
    }
    // Each block of touched rows, with one more each side (whose slopes they change).
    for (let r = 0; r < rows; r++) {
      if (!touched[r]) continue;
      let end = r;
      while (end + 1 < rows && touched[end + 1]) end++;
      this.uploadRows(r - 1, end + 2);
      r = end;
    }
  }

  // Height and slope (per px; numpy.gradient's central differences, one-sided at the
  // grid's edges) of grid rows lo..hi-1 into the texture.
  uploadRows(lo, hi) {
    const gl = this.gl;
    const [cols, rows] = this.gridSize;
    lo = Math.max(lo, 0);
    hi = Math.min(hi, rows);
    if (hi <= lo) return;
    const g = this.grid, h = this.spacing;
    const at = (r, c) => g[r * cols + c];
    const texels = this.texels, halves = this.halves;
    const fr = Math.fround;
    for (let r = lo; r < hi; r++) {
      const [ra, rb, dy] = r === 0 ? [0, 1, h] : r === rows - 1 ? [r - 1, r, h] : [r - 1, r + 1, 2 * h];
      for (let c = 0; c < cols; c++) {
        const [ca, cb, dx] = c === 0 ? [0, 1, h] : c === cols - 1 ? [c - 1, c, h] : [c - 1, c + 1, 2 * h];
        const o = (r * cols + c) * 3;
        // (each a float32 first, as the desktop's numpy: then one rounding to a half)
        const v = at(r, c), sx = fr(fr(at(r, cb) - at(r, ca)) / dx), sy = fr(fr(at(rb, c) - at(ra, c)) / dy);
        if (halves) {
          halves[o] = v;
          halves[o + 1] = sx;
          halves[o + 2] = sy;
        } else {
          texels[o] = floatToHalf(v);
          texels[o + 1] = floatToHalf(sx);
          texels[o + 2] = floatToHalf(sy);
        }
      }
    }
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, lo, cols, hi - lo, gl.RGB, gl.HALF_FLOAT,
      texels.subarray(lo * cols * 3, hi * cols * 3));
  }

  // No heights: a flat grid (every height and slope 0, no rows to work out).
  clear() {
    this.grid.fill(0);
    this.texels.fill(0);
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, ...this.gridSize, gl.RGB, gl.HALF_FLOAT, this.texels);
  }
}
