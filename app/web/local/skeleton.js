// The ice skeleton (sim/core/skeleton.py): crystals with parent links, upsample particles
// and chain segments, in flat typed arrays. Rows are only appended (a melt marks them
// dead), and a link's rows are appended together in crystal order, so each row's crystal
// ascends and a melt finds the rows of a link by binary search.

import { lowerBound, room } from './arrays.js';

export class Skeleton {
  constructor() {
    this.crystals = new Float32Array(2 * 256);  // x, y of each crystal (seeds included)
    this.parents = new Int32Array(256);  // -1 for a seed
    this.area = new Int32Array(256);  // the area whose water became each crystal
    this.crystalAlive = new Uint8Array(256);
    this.upsampled = new Float32Array(2 * 256);
    this.upsampledLink = new Int32Array(256);
    this.upsampledAlive = new Uint8Array(256);
    this.segments = new Float32Array(4 * 256);  // x0, y0, x1, y1 along each chain
    this.segmentsLink = new Int32Array(256);
    this.segmentsAlive = new Uint8Array(256);
    // A double from the start: a field that holds a small integer first and a fraction
    // later changes the skeleton's object shape, and the code compiled for the old one
    // (a frost grown before: the worker's warm-up) is thrown away mid-growth.
    this.longestLink = NaN;
    this.clear();
  }

  clear() {
    this.count = 0;
    this.alive = 0;  // crystals not melted
    this.upsampledCount = 0;
    this.segmentCount = 0;
    this.longestLink = 0;  // a crystal's children lie within this of it
  }

  /** A live crystal at float32 (x, y); returns its index. */
  add(x, y, parent, area) {
    const i = this.count++;
    if (2 * this.count > this.crystals.length) {
      this.crystals = room(this.crystals, this.count, 2);
      this.parents = room(this.parents, this.count);
      this.area = room(this.area, this.count);
      this.crystalAlive = room(this.crystalAlive, this.count);
    }
    this.crystals[2 * i] = x;
    this.crystals[2 * i + 1] = y;
    this.parents[i] = parent;
    this.area[i] = area;
    this.crystalAlive[i] = 1;
    this.alive++;
    return i;
  }

  /** Eq. 3-4 for the link of crystal `i` from (px, py): Nu = floor(|q - p| / spacing);
   * if Nu >= 2 the Nu - 1 points p + (k / Nu)(q - p) split it into a chain of Nu
   * segments (docs/method.md 4.5), else it is one segment. */
  link(i, px, py, spacing) {
    const qx = this.crystals[2 * i], qy = this.crystals[2 * i + 1];
    const dx = qx - px, dy = qy - py, length = Math.hypot(dx, dy);
    const nu = Math.floor(length / spacing), pieces = nu >= 2 ? nu : 1;
    if (length > this.longestLink) this.longestLink = length;
    this.reserve(this.upsampledCount + pieces - 1, this.segmentCount + pieces);
    let ax = px, ay = py;
    for (let k = 1; k <= pieces; k++) {
      const t = k / pieces, bx = k === pieces ? qx : px + t * dx, by = k === pieces ? qy : py + t * dy;
      const s = this.segmentCount++;
      this.segments[4 * s] = ax;
      this.segments[4 * s + 1] = ay;
      this.segments[4 * s + 2] = bx;
      this.segments[4 * s + 3] = by;
      this.segmentsLink[s] = i;
      this.segmentsAlive[s] = 1;
      if (k < pieces) {
        const u = this.upsampledCount++;
        this.upsampled[2 * u] = bx;
        this.upsampled[2 * u + 1] = by;
        this.upsampledLink[u] = i;
        this.upsampledAlive[u] = 1;
      }
      ax = bx;
      ay = by;
    }
  }

  reserve(points, segments) {
    this.upsampled = room(this.upsampled, points, 2);
    this.upsampledLink = room(this.upsampledLink, points);
    this.upsampledAlive = room(this.upsampledAlive, points);
    this.segments = room(this.segments, segments, 4);
    this.segmentsLink = room(this.segmentsLink, segments);
    this.segmentsAlive = room(this.segmentsAlive, segments);
  }

  /** Kills the live segments and upsample particles of the links of `crystals`;
   * returns [segments, upsample particles] killed (Int32Arrays). */
  cut(crystals) {
    return [killRows(this.segmentsLink, this.segmentsAlive, this.segmentCount, crystals),
      killRows(this.upsampledLink, this.upsampledAlive, this.upsampledCount, crystals)];
  }

  /** The live crystals no live crystal grows from (the ice's thin edges), ascending (an
   * Int32Array). */
  tips() {
    const n = this.count, alive = this.crystalAlive, parents = this.parents, hasChild = new Uint8Array(n);
    for (let i = 0; i < n; i++) if (alive[i] && parents[i] >= 0) hasChild[parents[i]] = 1;
    let m = 0;
    for (let i = 0; i < n; i++) if (alive[i] && !hasChild[i]) m++;
    const out = new Int32Array(m);
    for (let i = 0, k = 0; i < n; i++) if (alive[i] && !hasChild[i]) out[k++] = i;
    return out;
  }

  /** The live segments of the links of `crystals` (an Int32Array). */
  liveSegments(crystals) {
    return liveRows(this.segmentsLink, this.segmentsAlive, this.segmentCount, crystals);
  }
}

function liveRows(link, alive, n, crystals) {
  const out = [];
  for (const c of crystals) {
    for (let r = lowerBound(link, n, c); r < n && link[r] === c; r++) if (alive[r]) out.push(r);
  }
  return Int32Array.from(out);
}

function killRows(link, alive, n, crystals) {
  const rows = liveRows(link, alive, n, crystals);
  for (const r of rows) alive[r] = 0;
  return rows;
}
