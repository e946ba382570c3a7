// The frosted window (docs/method.md, sections 7 and 8): the pane's seeds along the frame
// and on the glass, and its one pool of water. sim/rules/window_mode.py (`Pane`: water on
// free glass within BAND cell rings of the ice), sim/rules/openglass.py (`OpenGlass`: frond
// rules 2-4's water on open glass, the humidity field, the colder frame), the pane's choice
// (sim/rules/pane_choice.py) and the temperature's chill of the hit counts. Placement asks
// the pane one walker at a time (`placeOne`): each walker takes its first good one of TRIES
// draws, the law sim/ draws by all at once.

import { normal } from './random.js';

// Temperature at which the preset's hit counts apply unchanged, degrees C below freezing.
export const REFERENCE_C = 10;
// Water lands in free cells at most this many cell rings beyond the ice (window mode alone).
export const BAND = 3;
// Walkers per band cell (window mode alone): the pool is min(humidity, DENSITY x band cells).
export const DENSITY = 2.5;
// Draws per walker among the pane's cells before it is dropped (sim's GLASS_TRIES).
export const TRIES = 8;
// Walkers per far cell of open glass (frond rule 2).
export const FAR_DENSITY = 8;
// Where the frame's chill is this share of its most or more, water lands beside the ice.
export const FRAME_NEAR = 0.7;
// Size of the humidity field's blobs, px (the blur's sigma is half of it).
export const BLOB_PX = 200;
// Decay length of the frame's chill, px (sim/rules/fronds.py FRAME_PX).
export const FRAME_PX = 150;

/** Round half to even (numpy's rint; Python's round of a float). */
export function rint(t) {
  const r = Math.round(t);
  return r - t === 0.5 && r % 2 !== 0 ? r - 1 : r;
}

/** The hit counts the growth rule uses (window_mode.chill): scaled by REFERENCE_C /
 * temperature, rounded, at least 1; the parameters as they are without window mode. */
export function chilled(params, temperature = params.temperature) {
  if (!params.window_frost) return [params.tip_hits, params.side_hits];
  const scale = REFERENCE_C / temperature;
  return [Math.max(1, rint(params.tip_hits * scale)), Math.max(1, rint(params.side_hits * scale))];
}

/** Each point's distance to the nearest edge of a width x height screen, px. */
export function edgeDistance(x, y, width, height) {
  return Math.min(Math.min(x, width - x), Math.min(y, height - y));
}

/** Touch mode: water belongs to the touches' areas. */
export class NoPane {
  constructor() {
    this.on = false;
  }

  clear() {}

  start() { return null; }

  melted() {}

  pool(humidity) { return humidity; }

  chilled() {}
}

/** Window mode's pane (see the module doc): its seeds, its pool, where its water goes. */
export class Pane {
  constructor(params, uniform, index, ice) {
    this.on = true;
    this.params = params;
    this.uniform = uniform;
    this.index = index;
    this.ice = ice;
    this.own = new Int32Array(index.grid.size);  // live crystals whose own cell each cell is
    this.band = new Int32Array(index.grid.size);
    this.spot = new Float32Array(2);  // placeOne's answer
    this.clear();
  }

  clear() {
    this.own.fill(0);
    this.seen = 0;
    this.melts = 0;  // crystals melted so far (with the count: the ice's state)
    this.key = -1;
    this.bandSize = 0;
  }

  /** The pane-wide area's centre and radius, and the frame's and the glass's seeds (x, y
   * interleaved). */
  start() {
    const { width: w, height: h } = this.index, p = this.params;
    return { area: [w / 2, h / 2, Math.hypot(w, h) / 2 + 1],
      sites: [...frameSites(this.uniform, w, h, p.frame_sites), ...paneSites(this.uniform, w, h, p.pane_sites)] };
  }

  /** Melted crystals leave their cells' counts (those counted so far). */
  melted(dead) {
    this.melts += dead.length;
    const c = this.ice.crystals, grid = this.index.grid;
    for (const d of dead) if (d < this.seen) this.own[grid.key(c[2 * d], c[2 * d + 1])]--;
  }

  chilled() {}  // (without the frond rules the pool keeps to the band's density)

  iceKey() {
    return this.ice.count * 4294967296 + this.melts;
  }

  /** The live crystals grown since the last look counted in their own cells. */
  ownCounts() {
    const c = this.ice.crystals, alive = this.ice.crystalAlive, grid = this.index.grid, n = this.ice.count;
    for (let i = this.seen; i < n; i++) if (alive[i]) this.own[grid.key(c[2 * i], c[2 * i + 1])]++;
    this.seen = n;
    return this.own;
  }

  /** Cells within BAND rings of a candidate cell holding no crystal of their own, when the
   * ice changed. */
  update() {
    const key = this.iceKey();
    if (key === this.key) return;
    this.key = key;
    const own = this.ownCounts(), clearance = this.index.clearance, size = this.index.grid.size;
    let n = 0;
    for (let cell = 0; cell < size; cell++) if (clearance.ring(cell) <= BAND && own[cell] === 0) this.band[n++] = cell;
    this.bandSize = n;
  }

  pool(humidity) {
    this.update();
    return Math.min(humidity, Math.trunc(DENSITY * this.bandSize));
  }

  /** A spot of glass in a uniform cell of the band into `this.spot`; false where TRIES
   * draws found none. */
  placeOne() {
    this.update();
    const n = this.bandSize, u = this.uniform;
    for (let t = 0; n && t < TRIES; t++) {
      const cell = this.band[Math.min(Math.floor(Math.fround(u()) * n), n - 1)];
      if (this.tryIn(cell, Math.fround(u()), Math.fround(u()))) return true;
    }
    return false;
  }

  /** The point at (a, b) of cell `cell` (float32, as sim/ computes it) if it is glass. */
  tryIn(cell, a, b) {
    const grid = this.index.grid, s = Math.fround(grid.cell), cols = grid.cols;
    const x = Math.fround(Math.fround(cell % cols + a) * s), y = Math.fround(Math.fround(Math.floor(cell / cols) + b) * s);
    if (!this.index.glass(x, y)) return false;
    this.spot[0] = x;
    this.spot[1] = y;
    return true;
  }
}

/** Frond rules 2 and 3 (and rule 4's water): the pane's pool on open glass. */
export class OpenGlass extends Pane {
  constructor(params, uniform, index, ice) {
    super(params, uniform, index, ice);
    const size = index.grid.size;
    this.farRings = params.water_far;
    this.nearWeight = params.near_water;
    this.vapour = new Float64Array(size).fill(1);
    this.chill = new Float64Array(size).fill(1);
    this.rings = new Int16Array(size).fill(params.water_far);  // far enough, per cell
    this.wet = new Uint8Array(size);
    this.dist = new Int16Array(size);
    this.grown = new Uint8Array(size);
    this.spread = new Uint8Array(size);
    this.cells = new Int32Array(size);
    this.cumulative = new Float64Array(size);
    // Colder glass takes more vapour: the supply follows the temperature.
    this.supply = params.temperature / REFERENCE_C;
  }

  clear() {
    super.clear();
    if (!this.wet) return;  // (Pane's constructor: the arrays come next)
    this.wet.fill(0);
    this.vapour.fill(1);
    this.chill.fill(1);
    this.rings.fill(this.farRings);
    this.count = 0;
    this.area = 0;
  }

  start() {
    const p = this.params, grid = this.index.grid;
    if (p.vapour_var) this.vapour = humidityField(this.uniform, grid.rows, grid.cols, grid.cell, p.vapour_var);
    if (p.frame_chill) {
      this.chill = frameWeight(grid, this.index.width, this.index.height, p.frame_chill);
      // By the colder frame water freezes beside the ice (as without the fronds).
      for (let c = 0; c < grid.size; c++) this.rings[c] = (this.chill[c] - 1) / p.frame_chill >= FRAME_NEAR ? 0 : this.farRings;
    }
    return super.start();
  }

  /** The weather's glass: the supply follows its `temperature`, times `supply`. */
  chilled(temperature, supply) {
    this.supply = temperature / REFERENCE_C * supply;
  }

  /** The cells whose crystals melted stay wet until they hold a crystal again. */
  melted(dead) {
    super.melted(dead);
    const c = this.ice.crystals, grid = this.index.grid;
    for (const d of dead) this.wet[grid.key(c[2 * d], c[2 * d + 1])] = 1;
  }

  pool(humidity) {
    this.update();
    return Math.trunc(this.supply * Math.min(humidity, FAR_DENSITY * this.area));
  }

  /** A spot of glass in a cell drawn by weight into `this.spot`; false where TRIES draws
   * found none. */
  placeOne() {
    this.update();
    const n = this.count, u = this.uniform, cum = this.cumulative;
    if (n === 0) return false;
    const total = cum[n - 1];
    for (let t = 0; t < TRIES; t++) {
      const target = u() * total;
      let lo = 0, hi = n;  // searchsorted(..., side="right")
      while (lo < hi) {
        const mid = (lo + hi) >> 1;
        if (cum[mid] <= target) lo = mid + 1;
        else hi = mid;
      }
      if (this.tryIn(this.cells[Math.min(lo, n - 1)], u(), u())) return true;
    }
    return false;
  }

  /** sim's `_draw`: the point in float64, stored float32. */
  tryIn(cell, a, b) {
    const grid = this.index.grid, s = grid.cell, cols = grid.cols;
    const x = Math.fround((cell % cols + a) * s), y = Math.fround((Math.floor(cell / cols) + b) * s);
    if (!this.index.glass(x, y)) return false;
    this.spot[0] = x;
    this.spot[1] = y;
    return true;
  }

  /** Far and near cells and their cumulative weights, when the ice changed. */
  update() {
    const key = this.iceKey();
    if (key === this.key) return;
    this.key = key;
    const grid = this.index.grid, size = grid.size, own = this.ownCounts();
    const dist = ringDistance(this.index.candidates.count, grid.rows, grid.cols, this.farRings, this);
    const { rings, wet, vapour, chill, nearWeight, cells, cumulative } = this;
    let n = 0, far = 0, near = 0, total = 0;
    for (let c = 0; c < size; c++) {
      const d = dist[c];
      const isFar = d >= rings[c] && (d > 0 || own[c] === 0);
      if (wet[c] && own[c] !== 0) wet[c] = 0;
      const isNear = !isFar && (d > 0 || wet[c] === 1);
      let w = 0;
      if (isFar) {
        far++;
        w = chill[c] * vapour[c];
      } else if (isNear) {
        near++;
        w = chill[c] * nearWeight;
      }
      if (w > 0) {
        total += w;
        cells[n] = c;
        cumulative[n++] = total;
      }
    }
    this.count = n;
    this.area = far + nearWeight * near;
  }
}

/** Per flat cell the Chebyshev distance in cells to the nearest cell with `count` > 0 (0
 * for one), at most `cap`, into `work.dist` (`work.grown`, `work.spread`: scratch). */
export function ringDistance(count, rows, cols, cap, work) {
  const size = rows * cols, dist = work.dist;
  let grown = work.grown, spread = work.spread;
  for (let c = 0; c < size; c++) grown[c] = count[c] > 0 ? 1 : 0;
  dist.fill(0);
  for (let step = 0; step < cap; step++) {
    for (let c = 0; c < size; c++) dist[c] += grown[c] ? 0 : 1;
    if (step === cap - 1) break;
    dilate(grown, spread, rows, cols);
    [grown, spread] = [spread, grown];
  }
  work.grown = grown;
  work.spread = spread;
  return dist;
}

/** `mask` grown by one cell in every direction (8 neighbours) into `out`. */
function dilate(mask, out, rows, cols) {
  for (let r = 0; r < rows; r++) {
    const r0 = Math.max(0, r - 1), r1 = Math.min(rows - 1, r + 1);
    for (let c = 0; c < cols; c++) {
      const c0 = Math.max(0, c - 1), c1 = Math.min(cols - 1, c + 1);
      let v = 0;
      for (let rr = r0; rr <= r1 && !v; rr++) for (let cc = c0; cc <= c1; cc++) if (mask[rr * cols + cc]) { v = 1; break; }
      out[r * cols + c] = v;
    }
  }
}

/** Per cell 1 + chill x e^(-d / FRAME_PX), d its centre's distance to the screen's edge. */
export function frameWeight(grid, width, height, chill) {
  const out = new Float64Array(grid.size);
  for (let c = 0; c < grid.size; c++) {
    const x = Math.min((c % grid.cols + 0.5) * grid.cell, width);
    const y = Math.min((Math.floor(c / grid.cols) + 0.5) * grid.cell, height);
    out[c] = 1 + chill * Math.exp(-edgeDistance(x, y, width, height) / FRAME_PX);
  }
  return out;
}

/** A flat per-cell log-normal weight of mean about 1: white noise blurred to blobs of
 * about BLOB_PX, standardised, exp(sqrt(var) z - var / 2). */
export function humidityField(uniform, rows, cols, cell, variance) {
  const z = new Float64Array(rows * cols);
  for (let k = 0; k < z.length; k++) z[k] = normal(uniform);
  const sigma = BLOB_PX / 2 / cell, br = blur(rows, sigma), bc = blur(cols, sigma);
  const across = new Float64Array(rows * cols), out = new Float64Array(rows * cols);
  for (let r = 0; r < rows; r++) {  // z @ bc^T
    for (let c = 0; c < cols; c++) {
      let s = 0;
      for (let k = 0; k < cols; k++) s += z[r * cols + k] * bc[c * cols + k];
      across[r * cols + c] = s;
    }
  }
  for (let r = 0; r < rows; r++) {  // br @ (z @ bc^T)
    for (let c = 0; c < cols; c++) {
      let s = 0;
      for (let k = 0; k < rows; k++) s += br[r * rows + k] * across[k * cols + c];
      out[r * cols + c] = s;
    }
  }
  let mean = 0;
  for (const v of out) mean += v;
  mean /= out.length;
  let sq = 0;
  for (const v of out) sq += (v - mean) ** 2;
  const std = Math.max(Math.sqrt(sq / out.length), 1e-12), root = Math.sqrt(variance);
  for (let k = 0; k < out.length; k++) out[k] = Math.exp(root * (out[k] - mean) / std - variance / 2);
  return out;
}

/** n x n Gaussian smoothing matrix, rows normalised. */
function blur(n, sigma) {
  const k = new Float64Array(n * n);
  for (let i = 0; i < n; i++) {
    let s = 0;
    for (let j = 0; j < n; j++) s += (k[i * n + j] = Math.exp(-0.5 * ((i - j) / sigma) ** 2));
    for (let j = 0; j < n; j++) k[i * n + j] /= s;
  }
  return k;
}

/** Sites along the border, per100 per 100 px of it on average: one uniform in each of
 * equal stretches, half a px inside the screen (x, y interleaved). */
export function frameSites(uniform, width, height, per100) {
  const perimeter = 2 * (width + height), n = rint(per100 * perimeter / 100), out = [];
  const w = width - 1, h = height - 1, e = 0.5;
  for (let i = 0; i < n; i++) {
    const t = (i + uniform()) * (perimeter / n) * (2 * (w + h)) / perimeter;
    let x, y;
    if (t < w) [x, y] = [t, 0];
    else if (t < w + h) [x, y] = [w, t - w];
    else if (t < 2 * w + h) [x, y] = [2 * w + h - t, h];
    else [x, y] = [0, 2 * (w + h) - t];
    out.push(Math.min(Math.max(x, e), w + 1 - e), Math.min(Math.max(y, e), h + 1 - e));
  }
  return out;
}

/** Scratch and dust: n sites uniform on the glass (x, y interleaved). */
export function paneSites(uniform, width, height, n) {
  const out = [];
  for (let i = 0; i < n; i++) out.push(uniform() * width, uniform() * height);
  return out;
}

/** The pane of window mode (open glass with `water_far`), else none. */
export function makePane(params, uniform, index, ice) {
  if (params.water_far) return new OpenGlass(params, uniform, index, ice);
  return params.window_frost ? new Pane(params, uniform, index, ice) : new NoPane();
}
