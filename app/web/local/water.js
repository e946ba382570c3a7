// The walkers (sim/core/water.py): one pool of water particles, x and y (px, float32) and
// the area of each, in array order (oldest first).

import { room } from './arrays.js';

export class Water {
  constructor(capacity) {
    this.x = new Float32Array(capacity);
    this.y = new Float32Array(capacity);
    this.area = new Int32Array(capacity);
    this.drop = new Uint8Array(capacity);  // walkers marked to leave at the next `sweep`
    this.n = 0;
    // counts' answer, made here: every field a constructor makes keeps one object shape,
    // which the compiled simulation is specialised for
    this.perArea = new Int32Array(16);
  }

  clear() {
    this.n = 0;
  }

  append(x, y, area) {
    const i = this.n++;
    if (this.n > this.x.length) {
      this.x = room(this.x, this.n);
      this.y = room(this.y, this.n);
      this.area = room(this.area, this.n);
      this.drop = room(this.drop, this.n);
    }
    this.x[i] = x;
    this.y[i] = y;
    this.area[i] = area;
    this.drop[i] = 0;
  }

  /** Removes the walkers marked in `drop` (their order stays); returns how many left. */
  sweep() {
    const { x, y, area, drop } = this;
    let m = 0;
    for (let i = 0; i < this.n; i++) {
      if (drop[i]) {
        drop[i] = 0;
        continue;
      }
      x[m] = x[i];
      y[m] = y[i];
      area[m] = area[i];
      m++;
    }
    const gone = this.n - m;
    this.n = m;
    return gone;
  }

  /** Walkers of each area: `counts[a]` for a < areas (a reused Int32Array). */
  counts(areas) {
    if (this.perArea.length < areas) this.perArea = new Int32Array(Math.max(16, 2 * areas));
    const c = this.perArea;
    c.fill(0, 0, areas);
    for (let i = 0; i < this.n; i++) c[this.area[i]]++;
    return c;
  }
}
