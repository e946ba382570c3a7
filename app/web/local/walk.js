// The walk of Eq. 2 (Sec. 3.4.2; sim/core/walk.py): every walker moves a (cos t, sin t),
// a ~ U[0, step], t ~ U[0, 2 pi), in float32 as sim/ stores it; with long jumps (fern rule
// 3) a walker whose clearance exceeds the step jumps that far instead.

import { drawInto } from './random.js';

const TWO_PI = Math.fround(2 * Math.PI);

/** Draws of one walk: all the lengths' uniforms, then all the angles' (sim/'s order). */
export function drawWalk(uniform, m, scratch) {
  drawInto(uniform, scratch, 2 * m);
}

/** Moves every walker of `water` by one step of Eq. 2 from the uniforms `u` (`drawWalk`'s:
 * u[i] the length's, u[m + i] the angle's); `jumps`: each walker's clearance (long jumps,
 * `Clearance.radii`) or null. Marks in `left` (returns how many) the walkers now off the
 * screen or outside their area. */
export function walkWater(water, areas, step, jumps, u, size, left) {
  const m = water.n, { x, y, area } = water, rows = areas.rows, step32 = Math.fround(step);
  const [w, h] = size;
  let gone = 0;
  for (let i = 0; i < m; i++) {
    const a5 = 5 * area[i], cx = rows[a5], cy = rows[a5 + 1], r = rows[a5 + 2];
    let a = Math.fround(u[i] * step32);
    const theta = Math.fround(u[m + i] * TWO_PI);
    const c = Math.fround(Math.cos(theta)), s = Math.fround(Math.sin(theta));
    let nx, ny;
    if (jumps) {
      // (sim/ takes the jump and the step as float64 here: the product is not rounded)
      if (jumps[i] > step) a = jumps[i];
      nx = Math.fround(x[i] + a * c);
      ny = Math.fround(y[i] + a * s);
    } else {
      nx = Math.fround(x[i] + Math.fround(a * c));
      ny = Math.fround(y[i] + Math.fround(a * s));
    }
    x[i] = nx;
    y[i] = ny;
    const ox = Math.fround(nx - cx), oy = Math.fround(ny - cy);
    const out = Math.fround(Math.fround(ox * ox) + Math.fround(oy * oy)) > Math.fround(r * r);
    const off = out || nx < 0 || nx >= w || ny < 0 || ny >= h ? 1 : 0;
    left[i] = off;
    gone += off;
  }
  return gone;
}
