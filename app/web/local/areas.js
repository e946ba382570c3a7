// The active areas (Sec. 3.4.2; sim/core/areas.py): where each pool's water lives and how
// far its ice reaches. A row is (centre x, centre y, outer radius, inner radius, reach of
// its ice), float32; water lives in the annulus between the radii.

import { room } from './arrays.js';

export class Areas {
  constructor() {
    this.rows = new Float32Array(5 * 16);
    this.ice = new Int32Array(16);  // live crystals of each area
    this.n = 0;
    // shell's answer; doubles from the start (as Skeleton's longestLink)
    this.inner = NaN;
    this.outer = NaN;
  }

  clear() {
    this.n = 0;
  }

  /** The area of a touch at (x, y): the one whose disc holds it (nearest centre, lowest
   * index among equals), else a new one of `radius` opened there. */
  areaFor(x, y, radius) {
    const a = this.rows;
    let best = -1, bestD2 = Infinity;
    for (let i = 0; i < this.n; i++) {
      const dx = Math.fround(a[5 * i] - x), dy = Math.fround(a[5 * i + 1] - y);
      const d2 = Math.fround(Math.fround(dx * dx) + Math.fround(dy * dy));
      if (d2 <= Math.fround(a[5 * i + 2] * a[5 * i + 2]) && d2 < bestD2) {
        best = i;
        bestD2 = d2;
      }
    }
    return best >= 0 ? best : this.open(x, y, radius);
  }

  open(x, y, radius) {
    const i = this.n++;
    this.rows = room(this.rows, this.n, 5);
    this.ice = room(this.ice, this.n);
    this.rows.set([x, y, radius, 0, 0], 5 * i);
    this.ice[i] = 0;
    return i;
  }

  /** Widens area `i`'s reach to its crystal at (x, y). */
  reachTo(i, x, y) {
    const r = this.rows;
    const dx = Math.fround(x - r[5 * i]), dy = Math.fround(y - r[5 * i + 1]);
    const d = Math.fround(Math.sqrt(dx * dx + dy * dy));
    if (d > r[5 * i + 4]) r[5 * i + 4] = d;
  }

  /** Growth mode: area `i`'s annulus rides on its ice front, half an active radius either
   * side of its farthest crystal, so its water can still reach the ice. */
  ride(i, radius) {
    const r = this.rows, band = Math.fround(radius / 2), reach = r[5 * i + 4];
    r[5 * i + 2] = Math.max(radius, Math.fround(reach + band));
    r[5 * i + 3] = Math.max(0, Math.fround(reach - band));
  }

  /** The inner and outer radius water is placed between in area `i`, into (this.inner,
   * this.outer): with a launch circle (fern rule 4) both `launch` px beyond its farthest
   * ice while that lies inside it. (Fields, not an array: placement asks per walker.) */
  shell(i, launch) {
    const r = this.rows, outer = r[5 * i + 2], inner = r[5 * i + 3];
    const ring = launch ? Math.fround(r[5 * i + 4] + Math.fround(launch)) : Infinity;
    this.inner = ring < outer ? ring : inner;
    this.outer = ring < outer ? ring : outer;
  }
}
