// The glass look's sharp features (sim/look/ridges.py): one tapered ridge per crystal ->
// child link, its half-width growing with the cube root of the crystals it carries (the
// pipe model), quantized in levels; a link is sent again only when its level rises, and
// a melt takes the melted crystals out of every count above them. Float32 as numpy
// computes it (Math.fround after each operation), so the ridges match sim/'s bit for bit.

const f = Math.fround;
export const VERTS_PER_LINK = 24;  // 8 triangles: two body faces and a cap each side at each end
const MIN_HALF_WIDTH = 0.9;  // px: a tip's ridge is about 2 px wide
const EDGE_PAD = 0.75;  // px the faces run on past the edge, below the glass (anti-aliasing)
const MAX_HALF_WIDTH = 0.7;  // x hc: a trunk never swells over its neighbours' freezing areas
const LEVELS_PER_DOUBLING = 2;  // width levels per doubling of the carried count
const TILT = f(0.18);  // spread of the random tilt per ridge face (sparkle)

// Corners: 0 P top, 1 Q top, 2 Q+, 3 P+, 4 Q-, 5 P-, 6 Q tip, 7 P tip; faces: two each side
// of the body, a cap each side at each end; each face falls away along (FACE_T t + FACE_N n).
const FACES = [0, 1, 2, 0, 2, 3, 0, 1, 4, 0, 4, 5, 1, 2, 6, 1, 4, 6, 0, 3, 7, 0, 5, 7];
const FACE_T = [0, 0, 0, 0, 1, 1, -1, -1];
const FACE_N = [1, 1, -1, -1, 1, -1, 1, -1];

// The widest half-width a ridge can have, px.
export function widest(hc) {
  return Math.max(MAX_HALF_WIDTH * hc, MIN_HALF_WIDTH);
}

// The highest a ridge can stand, px (twice feature_height per px of half-width).
export function topHeight(params) {
  return 2.0 * params.feature_height * widest(params.hc);
}

// Thickness level of a link carrying `carried` crystals: floor(2 log2 n), 0 for a tip, no
// higher than the level whose width reaches the cap.
export function widthLevel(carried, hc) {
  const top = Math.ceil(3.0 * LEVELS_PER_DOUBLING * Math.log2(widest(hc) / MIN_HALF_WIDTH));
  return Math.min(Math.floor(LEVELS_PER_DOUBLING * Math.log2(Math.max(carried, 1))), top);
}

// Half-width of a link at `level`, px (float32).
export function halfWidth(level, hc) {
  return f(Math.min(MIN_HALF_WIDTH * 2 ** (level / (3.0 * LEVELS_PER_DOUBLING)), widest(hc)));
}

// bits 32..63 of the 64-bit product a * b (a < 2^31, b < 2^32), exactly in doubles.
function mulHigh(a, b) {
  const low = a * (b & 0xffff), high = a * (b >>> 16);
  const mid = (high % 65536) * 65536 + low;  // < 2^48: exact
  return (Math.floor(high / 65536) + Math.floor(mid / 4294967296)) >>> 0;
}

const GOLDEN_LO = 0x7f4a7c15, GOLDEN_HI = 0x9e3779b9, MIX_LO = 0x1ce4e5b9;

// The tilt of one face in [-1, 1) twice, written at out[at], out[at + 1]: ridges.py's
// _jitter (a hash of the key: a redrawn ridge keeps its glints). Only bits 11..26 of each
// 64-bit product are kept, so 32-bit arithmetic reaches them.
export function jitter(key, out, at) {
  const lo = Math.imul(key, GOLDEN_LO) >>> 0;
  const hi = (mulHigh(key, GOLDEN_LO) + Math.imul(key, GOLDEN_HI)) >>> 0;
  const h = ((lo >>> 11) | (hi << 21)) >>> 0;  // low 32 bits of (key * golden) >> 11
  const h2 = Math.imul(h, MIX_LO) >>> 11;
  out[at] = f((h & 0xffff) / 32768.0 - 1.0);
  out[at + 1] = f((h2 & 0xffff) / 32768.0 - 1.0);
}

const corner = new Float32Array(16);  // x, y of the 8 corners of one ridge
const normal = new Float32Array(24);  // nx, ny, nz of its 8 faces
const tilt = new Float32Array(2);

function setCorner(i, x, y) {
  corner[2 * i] = x;
  corner[2 * i + 1] = y;
}

// Vertices (x, y, z, nx, ny, nz) of the ridge from (px, py) to (qx, qy), half-width w
// (float32), flanks' slope `slope`, glints seeded by `id`, written at out[o].
export function ridge(out, o, px, py, qx, qy, w, slope, id) {
  const dx = f(qx - px), dy = f(qy - py);
  const length = f(Math.sqrt(dx * dx + dy * dy));
  const tx = length > 0 ? f(dx / length) : 1, ty = length > 0 ? f(dy / length) : 0;
  const nx = -ty, ny = tx;
  const pad = f(w + EDGE_PAD);
  const wtx = f(pad * tx), wty = f(pad * ty), wnx = f(pad * nx), wny = f(pad * ny);
  setCorner(0, px, py);
  setCorner(1, qx, qy);
  setCorner(2, f(qx + wnx), f(qy + wny));
  setCorner(3, f(px + wnx), f(py + wny));
  setCorner(4, f(qx - wnx), f(qy - wny));
  setCorner(5, f(px - wnx), f(py - wny));
  setCorner(6, f(qx + wtx), f(qy + wty));
  setCorner(7, f(px - wtx), f(py - wty));
  const s32 = f(slope), top = f(s32 * w), below = f(-slope * EDGE_PAD);
  for (let k = 0; k < 8; k++) {
    jitter(id * 8 + k, tilt, 0);
    const fx = f(s32 * f(FACE_T[k] * tx + FACE_N[k] * nx));
    const fy = f(s32 * f(FACE_T[k] * ty + FACE_N[k] * ny));
    const ex = f(fx + f(TILT * tilt[0])), ey = f(fy + f(TILT * tilt[1]));
    const size = f(Math.sqrt(f(f(f(ex * ex) + f(ey * ey)) + 1)));
    normal[3 * k] = f(ex / size);
    normal[3 * k + 1] = f(ey / size);
    normal[3 * k + 2] = f(1 / size);
  }
  for (let v = 0; v < 24; v++, o += 6) {
    const c = FACES[v], k = (v / 3) | 0;
    out[o] = corner[2 * c];
    out[o + 1] = corner[2 * c + 1];
    out[o + 2] = c < 2 ? top : below;
    out[o + 3] = normal[3 * k];
    out[o + 4] = normal[3 * k + 1];
    out[o + 5] = normal[3 * k + 2];
  }
}

// The carried counts and drawn levels of every link; turns a tick's new crystals (or a
// melt) into the ridges to send. Reads of the frost: count, crystals, parents, crystalAlive.
export class PipeRidges {
  constructor(params) {
    this.hc = params.hc;
    this.slope = 2.0 * params.feature_height;  // ridge height per px of half-width
    this.carried = new Int32Array(0);  // crystals each crystal's link carries
    this.drawn = new Int32Array(0);  // level each link was last sent at (-1: never)
    this._marked = new Uint8Array(0);  // 1 for the crystals in `_touched`
    this._touched = new Int32Array(0);
    this._ntouched = 0;
  }

  // Count crystals [start, end) into every link above them; the ridges (Float32Array of
  // vertices) of the new links and of those that thickened.
  grow(frost, start, end) {
    this._extend(frost.count);
    const parents = frost.parents, alive = frost.crystalAlive;
    for (let i = start; i < end; i++) if (alive[i]) this.carried[i] = 1;
    for (let i = start; i < end; i++) {
      if (!alive[i]) continue;
      this._touch(i);
      if (parents[i] >= 0) this._climb(parents, parents[i], 1);
    }
    const links = this._take(), drawn = this.drawn;
    let n = 0;
    for (const link of links) {
      if (alive[link] && parents[link] >= 0 && widthLevel(this.carried[link], this.hc) > drawn[link]) {
        links[n++] = link;
      }
    }
    return this.triangles(frost, links.subarray(0, n));
  }

  // Take the melted crystals `dead` out of the counts above them (the frost's melt has cut
  // their children loose already); the links whose level fell, to be drawn again.
  melt(frost, dead) {
    this._extend(frost.count);
    const parents = frost.parents, alive = frost.crystalAlive;
    const gone = new Set(dead);
    const amounts = Array.from(dead, (d) => -this.carried[d]);
    dead.forEach((d, i) => {
      const up = parents[d];
      if (up >= 0 && !gone.has(up)) this._climb(parents, up, amounts[i]);
    });
    for (const d of dead) this.drawn[d] = -1;
    const touched = this._take();
    let n = 0;
    for (const link of touched) {
      if (alive[link] && parents[link] >= 0 && widthLevel(this.carried[link], this.hc) < this.drawn[link]) {
        touched[n++] = link;
      }
    }
    return touched.slice(0, n);
  }

  // The ridges of `links` (child crystal indices) at their levels now, marked drawn.
  triangles(frost, links) {
    const out = new Float32Array(links.length * VERTS_PER_LINK * 6);
    const c = frost.crystals, parents = frost.parents;
    links.forEach((link, i) => {
      const level = widthLevel(this.carried[link], this.hc);
      this.drawn[link] = level;
      const tail = parents[link];
      ridge(out, i * VERTS_PER_LINK * 6, c[2 * tail], c[2 * tail + 1], c[2 * link], c[2 * link + 1],
        halfWidth(level, this.hc), this.slope, link);
    });
    return out;
  }

  // Room for `n` crystals.
  _extend(n) {
    if (n <= this.carried.length) return;
    const size = Math.max(n, 2 * this.carried.length);
    const carried = new Int32Array(size), drawn = new Int32Array(size).fill(-1);
    carried.set(this.carried);
    drawn.set(this.drawn);
    this.carried = carried;
    this.drawn = drawn;
    const marked = new Uint8Array(size), touched = new Int32Array(size);
    touched.set(this._touched.subarray(0, this._ntouched));
    this._marked = marked;
    this._touched = touched;
  }

  // Add `amount` to the count of every crystal from `from` up to its root, each touched.
  _climb(parents, from, amount) {
    for (let i = from; i >= 0; i = parents[i]) {
      this.carried[i] += amount;
      this._touch(i);
    }
  }

  _touch(i) {
    if (this._marked[i]) return;
    this._marked[i] = 1;
    this._touched[this._ntouched++] = i;
  }

  // The crystals touched, ascending (a view, until the next call); the marks cleared.
  _take() {
    const touched = this._touched.subarray(0, this._ntouched).sort();
    for (const i of touched) this._marked[i] = 0;
    this._ntouched = 0;
    return touched;
  }
}
