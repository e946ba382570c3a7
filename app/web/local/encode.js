// The page's own frost as `frost serve` sends it: a FrostGeometry delta packed into the
// binary geometry message of docs/protocol.md, byte for byte as app/serve/protocol.py's
// Encoder writes it, so the renderer reads the phone's frost and the server's alike.

import {
  FLAG_CLEAR_BOX, FLAG_RESET, FLAG_SNAPSHOT, FLAG_SNAPSHOT_END, HEADER_BYTES, LOOKS, RUN_BYTES,
  SUBPIXEL, VERSION, VERTEX_BYTES, floatToHalf,
} from "../protocol.js";

const GEOMETRY = 1;  // the binary message type
// Unchanged heights between two changed ones are sent along (2 bytes each) rather than
// starting a new run (8 bytes) when there are at most this many (protocol.RUN_GAP).
export const RUN_GAP = 4;
// A snapshot's features are cut into messages of at most this many vertices, whole
// triangles each (protocol.PART_VERTICES).
export const PART_VERTICES = 3 * 21845;

// Round half to even, as numpy's rint.
export function rint(v) {
  const r = Math.round(v);
  return r - v === 0.5 && r % 2 !== 0 ? r - 1 : r;
}

// The height grid as the renderer holds it (half floats), kept to diff each delta against:
// a delta's heights go out as runs of the values that changed.
export class Encoder {
  constructor(cols, rows) {
    this.grid = [cols, rows];
    this.heights = new Uint16Array(rows * cols);  // row-major half-float bits
    this.look = "paper";
    this.heightScale = 16.0;
    // The float32 bits each half of `heights` was made from: a height whose float is
    // unchanged keeps its half, so a delta converts only the floats that changed (a
    // tick's rows span every area grown, tens of thousands of heights; a few hundred change).
    this._floatBits = new Int32Array(rows * cols);
    this._runs = new Int32Array(2 * rows * cols);  // (start, count) pairs
    // Whether this grid is the geometry's outside a delta's `changed` (every delta since
    // the geometry's last reset came here): then a delta's heights are diffed at those
    // vertices only, not across all its rows.
    this._follows = false;
  }

  reset() {
    this.heights.fill(0);
    this._floatBits.fill(0);  // (+0.0's bits: half 0)
  }

  // One message (an ArrayBuffer) for `delta` (`reset`: the renderer clears first).
  delta(delta, reset = false) {
    const resets = reset || delta.reset;
    if (resets) this.reset();
    this.look = delta.look;
    this.heightScale = delta.heightScale;
    const cols = this.grid[0];
    const lo = delta.rows[0] * cols, n = (delta.rows[1] - delta.rows[0]) * cols;
    if (resets) this._follows = delta.reset;  // (a reset of the page's alone: the geometry's grid stays)
    const changed = this._follows && !resets ? delta.changed : null;
    const nruns = changed ? this._diffAt(delta.heights, lo, changed) : this._diff(delta.heights, lo, n);
    return message(resets ? FLAG_RESET : 0, delta.look, delta.tick, this.grid, delta.heightScale,
      this._runs.subarray(0, 2 * nruns), this.heights, delta.features, delta.clearBox);
  }

  // A message with no change (a reset alone).
  bare(tick, reset) {
    if (reset) {
      this.reset();
      this._follows = false;
    }
    return message(reset ? FLAG_RESET : 0, this.look, tick, this.grid, this.heightScale,
      this._runs.subarray(0, 0), this.heights, new Float32Array(0), null);
  }

  // The whole frost a renderer must hold: a reset, every height (one run; `heights`, half
  // bits, default this grid's now) and `features`, cut into parts of at most
  // `partVertices` vertices: a list of ArrayBuffers.
  snapshot(tick, features, look, heightScale, heights = null, partVertices = PART_VERTICES) {
    heights = heights ?? this.heights;
    const nverts = features.length / 6;
    const parts = [];
    const whole = Int32Array.of(0, heights.length), none = whole.subarray(0, 0);
    for (let at = 0; at < nverts || parts.length === 0; at += partVertices) {
      const last = at + partVertices >= nverts;
      const flags = FLAG_SNAPSHOT | (at === 0 ? FLAG_RESET : 0) | (last ? FLAG_SNAPSHOT_END : 0);
      const chunk = features.subarray(6 * at, 6 * Math.min(at + partVertices, nverts));
      parts.push(message(flags, look, tick, this.grid, heightScale, at === 0 ? whole : none,
        heights, chunk, null));
    }
    return parts;
  }

  // Runs covering every changed height of the `n` float32 `values` at `lo` (changed ones
  // at most RUN_GAP apart share a run), written into this.heights; the number of runs.
  _diff(values, lo, n) {
    const old = this.heights, seen = this._floatBits;
    const bits = new Int32Array(values.buffer, values.byteOffset, n);
    let nruns = 0;
    for (let i = 0; i < n; i++) {
      const b = bits[i];
      if (b === seen[lo + i]) continue;  // the same float, so the same half
      seen[lo + i] = b;
      const half = floatToHalf(values[i]);
      if (old[lo + i] === half) continue;  // (a height is never -0)
      old[lo + i] = half;
      nruns = this._extend(nruns, lo + i);
    }
    return nruns;
  }

  // _diff's runs where only the vertices `changed` (flat, ascending, within the rows at
  // `lo`) can differ: the same runs, without a look at the rest.
  _diffAt(values, lo, changed) {
    const old = this.heights, seen = this._floatBits;
    const bits = new Int32Array(values.buffer, values.byteOffset, values.length);
    let nruns = 0;
    for (let k = 0; k < changed.length; k++) {
      const v = changed[k], i = v - lo, b = bits[i];
      if (b === seen[v]) continue;
      seen[v] = b;
      const half = floatToHalf(values[i]);
      if (old[v] === half) continue;
      old[v] = half;
      nruns = this._extend(nruns, v);
    }
    return nruns;
  }

  // The changed height at `v` in the last run (at most RUN_GAP past its end) or a new
  // one; the number of runs.
  _extend(nruns, v) {
    const runs = this._runs;
    if (nruns > 0 && v - runs[2 * nruns - 2] - runs[2 * nruns - 1] <= RUN_GAP) {
      runs[2 * nruns - 1] = v + 1 - runs[2 * nruns - 2];
      return nruns;
    }
    runs[2 * nruns] = v;
    runs[2 * nruns + 1] = 1;
    return nruns + 1;
  }
}

// `delta`'s message through `encoder` (its grid of half floats, kept between calls).
export function encodeDelta(delta, encoder, reset = false) {
  return encoder.delta(delta, reset);
}

// The bytes of one message: header, runs, their values from the grid `heights` (padded to
// 4 bytes), vertices.
function message(flags, look, tick, grid, heightScale, runs, heights, features, box) {
  let nvalues = 0;
  for (let r = 1; r < runs.length; r += 2) nvalues += runs[r];
  const nverts = features.length / 6;
  const verts = HEADER_BYTES + runs.length * 4 + Math.ceil(nvalues / 2) * 4;
  const buffer = new ArrayBuffer(verts + nverts * VERTEX_BYTES);
  const v = new DataView(buffer);
  if (box) flags |= FLAG_CLEAR_BOX;
  v.setUint8(0, VERSION);
  v.setUint8(1, GEOMETRY);
  v.setUint8(2, flags);
  v.setUint8(3, LOOKS.indexOf(look));
  v.setUint32(4, tick >>> 0, true);
  v.setUint16(8, grid[0], true);
  v.setUint16(10, grid[1], true);
  v.setFloat32(12, heightScale, true);
  v.setUint32(16, runs.length / 2, true);
  v.setUint32(20, nverts, true);
  for (let i = 0; i < 4; i++) v.setFloat32(24 + 4 * i, box ? box[i] : 0, true);
  let at = HEADER_BYTES;
  for (let r = 0; r < runs.length; r++, at += 4) v.setUint32(at, runs[r], true);
  for (let r = 0; r < runs.length; r += 2) {
    for (let i = runs[r], end = runs[r] + runs[r + 1]; i < end; i++, at += 2) {
      v.setUint16(at, heights[i], true);
    }
  }
  packVertices(v, verts, features);
  return buffer;
}

// Feature vertices (x, y, z, nx, ny, nz each) as 12-byte records at `at`: x, y in 1/16 px,
// z a half float, 2 padding bytes, the normal times 127, a padding byte.
function packVertices(v, at, features) {
  for (let f = 0; f < features.length; f += 6, at += VERTEX_BYTES) {
    v.setInt16(at, clip(rint(features[f] * SUBPIXEL), -32768, 32767), true);
    v.setInt16(at + 2, clip(rint(features[f + 1] * SUBPIXEL), -32768, 32767), true);
    v.setUint16(at + 4, floatToHalf(features[f + 2]), true);
    for (let k = 0; k < 3; k++) v.setInt8(at + 8 + k, clip(rint(features[f + 3 + k] * 127), -127, 127));
  }
}

function clip(value, lo, hi) {
  return Math.min(Math.max(value, lo), hi);
}
