// The server's binary geometry messages (docs/protocol.md), decoded into the deltas the
// renderer applies: the same fields as sim.look.geometry.GeometryDelta.

export const VERSION = 1;
export const HEADER_BYTES = 40;
export const RUN_BYTES = 8;
export const VERTEX_BYTES = 12;
export const SUBPIXEL = 16;  // feature x, y are sent in 1/16 px
export const FLAG_RESET = 1;
export const FLAG_CLEAR_BOX = 2;
export const FLAG_SNAPSHOT = 4;
export const FLAG_SNAPSHOT_END = 8;
export const LOOKS = ["paper", "glass"];

// IEEE half (its 16 bits) -> number; exact.
export function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const exp = (h >> 10) & 0x1f;
  const frac = h & 0x3ff;
  if (exp === 0) return sign * frac * 2 ** -24;
  if (exp === 31) return frac ? NaN : sign * Infinity;
  return sign * (1024 + frac) * 2 ** (exp - 25);
}

// number -> IEEE half bits, rounded to nearest even (as numpy's astype(float16)).
const f32 = new Float32Array(1);
const u32 = new Uint32Array(f32.buffer);
export function floatToHalf(value) {
  f32[0] = value;
  const x = u32[0];
  const sign = (x >>> 16) & 0x8000;
  const exp = (x >>> 23) & 0xff;
  let mant = x & 0x7fffff;
  if (exp === 0xff) return sign | 0x7c00 | (mant ? 0x200 : 0);
  const e = exp - 127 + 15;  // the half's biased exponent
  if (e >= 31) return sign | 0x7c00;  // too big: infinity
  if (e <= 0) {  // a subnormal half (or zero)
    if (e < -10) return sign;
    mant |= 0x800000;
    const shift = 14 - e;  // 24 - 10 + (1 - e) - 1
    const half = 1 << (shift - 1);
    let bits = mant >>> shift;
    const rest = mant & ((1 << shift) - 1);
    bits += rest + (bits & 1) > half ? 1 : 0;  // to nearest, ties to even (as below)
    return sign | bits;
  }
  let bits = (e << 10) | (mant >>> 13);
  const rest = mant & 0x1fff;
  // To nearest, ties to even: up past the half, or at it when odd. (One sum that every
  // call runs: a step run only on an exact tie, first met deep into a growth, would throw
  // the compiled encoder away.) It may carry into the exponent.
  bits += rest + (bits & 1) > 0x1000 ? 1 : 0;
  return sign | bits;
}

export class ProtocolError extends Error {}

// How a message is read (`READ`): "typed", through typed arrays over it, which read in the
// machine's byte order (little-endian, as the wire, on every phone and desktop sold today),
// the half floats through Float16Array (exact, as halfToFloat; Chromium 135, Firefox 129,
// Safari 18.2); else "view", through a DataView and halfToFloat.
export const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
export const READ = LITTLE_ENDIAN && typeof Float16Array === "function" ? "typed" : "view";

// One binary message -> {tick, reset, snapshot, snapshotEnd, look, heightScale, grid
// ([cols, rows]), runs ([[start, count], ...]: flat row-major indices into the grid),
// heights (Float32Array: the runs' values in order), clearBox ([x0, y0, x1, y1] px or null),
// features (Float32Array of vertices x, y, z, nx, ny, nz)}. `read`: how (READ's choices;
// typed arrays read a snapshot's 150 000 vertices in a third of a DataView's time).
export function decodeDelta(buffer, read = READ) {
  if (buffer.byteLength < HEADER_BYTES) throw new ProtocolError(`message of ${buffer.byteLength} bytes is shorter than its header`);
  const v = new DataView(buffer);
  const version = v.getUint8(0), type = v.getUint8(1), flags = v.getUint8(2), look = v.getUint8(3);
  if (version !== VERSION || type !== 1) throw new ProtocolError(`unknown message version ${version} type ${type}`);
  if (look >= LOOKS.length) throw new ProtocolError(`unknown look ${look}`);
  const tick = v.getUint32(4, true);
  const grid = [v.getUint16(8, true), v.getUint16(10, true)];
  const heightScale = v.getFloat32(12, true);
  const nruns = v.getUint32(16, true), nverts = v.getUint32(20, true);
  const box = [24, 28, 32, 36].map((o) => v.getFloat32(o, true));
  let at = HEADER_BYTES;
  if (buffer.byteLength < at + nruns * RUN_BYTES) throw new ProtocolError("message shorter than its runs");
  const runs = [];
  let nvalues = 0;
  for (let i = 0; i < nruns; i++, at += RUN_BYTES) {
    const run = [v.getUint32(at, true), v.getUint32(at + 4, true)];
    if (run[0] + run[1] > grid[0] * grid[1]) throw new ProtocolError("a run reaches past the grid");
    runs.push(run);
    nvalues += run[1];
  }
  const need = at + Math.ceil(nvalues / 2) * 4 + nverts * VERTEX_BYTES;
  if (buffer.byteLength !== need) throw new ProtocolError(`message of ${buffer.byteLength} bytes, its header says ${need}`);
  // (the header and runs are whole multiples of 8 bytes, the heights padded to 4: every
  // field below is aligned for its typed array)
  let heights;
  if (read === "typed") {
    heights = new Float32Array(new Float16Array(buffer, at, nvalues));
  } else {
    heights = new Float32Array(nvalues);
    for (let i = 0; i < nvalues; i++) heights[i] = halfToFloat(v.getUint16(at + 2 * i, true));
  }
  at += Math.ceil(nvalues / 2) * 4;
  const features = new Float32Array(nverts * 6);
  if (read === "typed") {
    // A vertex is 6 16-bit words (x, y, z, pad, n) and its normal bytes 8-10 of 12.
    const words = new Int16Array(buffer, at, nverts * 6), bytes = new Int8Array(buffer, at, nverts * 12);
    const zs = new Float16Array(buffer, at, nverts * 6);
    for (let i = 0, f = 0, b = 8; i < nverts; i++, f += 6, b += 12) {
      features[f] = words[f] / SUBPIXEL;
      features[f + 1] = words[f + 1] / SUBPIXEL;
      features[f + 2] = zs[f + 2];
      features[f + 3] = bytes[b] / 127;
      features[f + 4] = bytes[b + 1] / 127;
      features[f + 5] = bytes[b + 2] / 127;
    }
  } else {
    for (let i = 0; i < nverts; i++, at += VERTEX_BYTES) {
      const f = i * 6;
      features[f] = v.getInt16(at, true) / SUBPIXEL;
      features[f + 1] = v.getInt16(at + 2, true) / SUBPIXEL;
      features[f + 2] = halfToFloat(v.getUint16(at + 4, true));
      features[f + 3] = v.getInt8(at + 8) / 127;
      features[f + 4] = v.getInt8(at + 9) / 127;
      features[f + 5] = v.getInt8(at + 10) / 127;
    }
  }
  return {
    tick, reset: !!(flags & FLAG_RESET), snapshot: !!(flags & FLAG_SNAPSHOT),
    snapshotEnd: !!(flags & FLAG_SNAPSHOT_END), look: LOOKS[look], heightScale, grid,
    runs, heights, clearBox: flags & FLAG_CLEAR_BOX ? box : null, features,
  };
}
