// The frost's geometry in the page (sim/look/geometry.py): a tick's new particles raise
// the bumpy height grid (Fig. 7, heightgrid.js) and bring their sharp features (Fig. 6:
// four triangles per segment; the glass look: ridges.js), as a delta the renderer applies
// (encode.js packs it as the server's message). Nothing here walks the whole ice but
// `redraw`.
//
// What it reads of the page's Frost (frost.js, the names of sim/'s FrostSim in camelCase,
// arrays flattened): tick, count, crystals, parents, crystalAlive, upsampled,
// upsampledLink, upsampledAlive, upsampledCount, segments, segmentsLink, segmentsAlive,
// segmentCount, and segmentsNear(box, reach) for a melt.

import { lowerBound } from "./arrays.js";
import { HeightGrid } from "./heightgrid.js";
import { PipeRidges, topHeight, widest } from "./ridges.js";

const f = Math.fround;
export const VERTS_PER_SEGMENT = 12;
const EMPTY = new Float32Array(0);

// The px the feature texture's 8-bit height 1.0 stands for (geometry.feature_scale).
export function featureScale(params) {
  const bound = params.look === "glass" ? topHeight(params)
    : params.feature_height * (params.hc + params.step);
  return Math.max(16.0, Math.ceil(bound));
}

// Vertices of the paper's features of segments `ids` (indices into `segments`, x0 y0 x1
// y1 each): triangles (p,s1,m), (s1,q,m), (q,s2,m), (s2,p,m), each with its own normal
// toward the viewer (sharp ridges), in float64 as numpy, stored as float32.
export function featureTriangles(segments, ids, width, height) {
  const out = new Float32Array(ids.length * VERTS_PER_SEGMENT * 6);
  let o = 0;
  for (const s of ids) {
    const px = segments[4 * s], py = segments[4 * s + 1];
    const qx = segments[4 * s + 2], qy = segments[4 * s + 3];
    const dx = qx - px, dy = qy - py;
    const mx = 0.5 * (px + qx), my = 0.5 * (py + qy);
    // (-dy, dx) is d turned by 90 degrees and L long: m +/- width x that, no division.
    POINTS.set(P, px, py, 0);
    POINTS.set(Q, qx, qy, 0);
    POINTS.set(M, mx, my, height * Math.hypot(dx, dy));
    POINTS.set(S1, mx - width * -dy, my - width * dx, 0);
    POINTS.set(S2, mx + width * -dy, my + width * dx, 0);
    for (let t = 0; t < 12; t += 3) o = face(out, o, ORDER[t], ORDER[t + 1], ORDER[t + 2]);
  }
  return out;
}

// The five points of one segment's feature, x y z each (float64).
const P = 0, Q = 1, M = 2, S1 = 3, S2 = 4;
const ORDER = [P, S1, M, S1, Q, M, Q, S2, M, S2, P, M];
const POINTS = {
  xyz: new Float64Array(15),
  set(i, x, y, z) {
    this.xyz[3 * i] = x;
    this.xyz[3 * i + 1] = y;
    this.xyz[3 * i + 2] = z;
  },
};

// Triangle (a, b, c) of POINTS with its normal, written at out[o]; the next o.
function face(out, o, a, b, c) {
  const p = POINTS.xyz;
  a *= 3;
  b *= 3;
  c *= 3;
  const ux = p[b] - p[a], uy = p[b + 1] - p[a + 1], uz = p[b + 2] - p[a + 2];
  const vx = p[c] - p[a], vy = p[c + 1] - p[a + 1], vz = p[c + 2] - p[a + 2];
  let nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  if (nz < 0) { nx = -nx; ny = -ny; nz = -nz; }  // winding varies: face the viewer
  const size = Math.sqrt(nx * nx + ny * ny + nz * nz);
  if (size === 0) { nx = 0; ny = 0; nz = 1; }  // a zero-length segment lies flat
  else { nx /= size; ny /= size; nz /= size; }
  vertex(out, o, p, a, nx, ny, nz);
  vertex(out, o + 6, p, b, nx, ny, nz);
  vertex(out, o + 12, p, c, nx, ny, nz);
  return o + 18;
}

function vertex(out, o, p, k, nx, ny, nz) {
  out[o] = p[k];
  out[o + 1] = p[k + 1];
  out[o + 2] = p[k + 2];
  out[o + 3] = nx;
  out[o + 4] = ny;
  out[o + 5] = nz;
}

// The px box [x0, y0, x1, y1] around the vertices `verts` (6 floats each) or points
// `xy` (2 each) and discs of radius `reach` at particles `pts` (2 each): float32 as numpy
// takes them; null if there are none.
function bounds(verts, stride, pts, reach) {
  if (verts.length === 0 && pts.length === 0) return null;
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  for (let i = 0; i < verts.length; i += stride) grow(box, verts[i], verts[i + 1], verts[i], verts[i + 1]);
  for (let i = 0; i < pts.length; i += 2) {
    grow(box, f(pts[i] - reach), f(pts[i + 1] - reach), f(pts[i] + reach), f(pts[i + 1] + reach));
  }
  return box;
}

function grow(box, x0, y0, x1, y1) {
  box[0] = Math.min(box[0], x0);
  box[1] = Math.min(box[1], y0);
  box[2] = Math.max(box[2], x1);
  box[3] = Math.max(box[3], y1);
}

// The live segments of `frost` whose feature (reaching width x their length beside them)
// meets `box`: of those segmentsNear finds, in its order.
function segmentsIn(frost, box, width) {
  const near = frost.segmentsNear(box, width), seg = frost.segments;
  const w = f(width), out = [];
  for (const s of near) {
    const x0 = seg[4 * s], y0 = seg[4 * s + 1], x1 = seg[4 * s + 2], y1 = seg[4 * s + 3];
    const dx = f(x1 - x0), dy = f(y1 - y0);
    const reach = f(w * f(Math.sqrt(dx * dx + dy * dy)));
    if (f(Math.max(x0, x1) + reach) >= box[0] && f(Math.min(x0, x1) - reach) <= box[2]
        && f(Math.max(y0, y1) + reach) >= box[1] && f(Math.min(y0, y1) - reach) <= box[3]) {
      out.push(s);
    }
  }
  return out;
}

// The whole of a melt whose crystals Frost.melt returned: frost.melted (nothing, for a
// melt that took none).
function meltedOf(frost, crystals) {
  if (crystals.length === 0) return { crystals, upsampled: crystals, segments: crystals, orphans: crystals };
  if (frost.melted?.crystals !== crystals) throw new Error("geometry.melt: not the frost's last melt");
  return frost.melted;
}

// The height grid and sharp features of a growing frost; each call returns a delta:
// {tick, rows: [lo, hi), heights (Float32Array of those rows), features (Float32Array of
// vertices x, y, z, nx, ny, nz), reset, clearBox ([x0, y0, x1, y1] px or null), look,
// heightScale}, as sim/'s GeometryDelta, and `changed`: the grid's vertices (flat,
// ascending) whose heights it may change, the rest of its rows as the last delta left
// them (null in a reset: all of them).
export class FrostGeometry {
  // views: each delta's heights a view of the grid's rows, good until the next call (the
  // worker encodes each delta at once: a copy of most of the grid a tick was a tenth of
  // its geometry's time), not a copy.
  constructor(params, { width = 760, height = 1280, views = false } = {}) {
    this.params = params;
    this.views = views;
    this.grid = new HeightGrid(params, width, height);
    this.rows = this.grid.rows;
    this.cols = this.grid.cols;
    this.heightScale = featureScale(params);
    this.ridges = params.look === "glass" ? new PipeRidges(params) : null;
  }

  // Flat glass again; the delta tells the renderer to drop everything.
  reset() {
    this.grid.clear();
    if (this.ridges) this.ridges = new PipeRidges(this.params);
    return this._delta(0, [0, this.rows], EMPTY, { reset: true });
  }

  // The whole live ice drawn anew: a reset delta of every height row and every live
  // feature. Costs O(ice), once.
  redraw(frost) {
    this.reset();
    const grid = this.grid, c = frost.crystals, u = frost.upsampled;
    for (let i = 0; i < frost.count; i++) if (frost.crystalAlive[i]) grid.point(c[2 * i], c[2 * i + 1]);
    for (let i = 0; i < frost.upsampledCount; i++) {
      if (frost.upsampledAlive[i]) grid.point(u[2 * i], u[2 * i + 1]);
    }
    grid.finish();
    let feats;
    if (this.ridges) feats = this.ridges.grow(frost, 0, frost.count);
    else feats = this._features(frost, 0, frost.segmentCount);
    return this._delta(frost.tick, [0, this.rows], feats, { reset: true });
  }

  // One tick: the grid raised around crystals added.start .. added.end - 1 and the
  // upsample particles of their links, and their features.
  update(frost, added) {
    const up = this._rowsOf(frost.upsampledLink, frost.upsampledCount, added);
    const grid = this.grid, c = frost.crystals, u = frost.upsampled;
    for (let i = added.start; i < added.end; i++) grid.point(c[2 * i], c[2 * i + 1]);
    for (let i = up[0]; i < up[1]; i++) grid.point(u[2 * i], u[2 * i + 1]);
    const rows = grid.finish();
    let feats;
    if (this.ridges) feats = this.ridges.grow(frost, added.start, added.end);
    else feats = this._features(frost, ...this._rowsOf(frost.segmentsLink, frost.segmentCount, added));
    return this._delta(frost.tick, rows, feats);
  }

  // A melt taken out of the ice: its particles' bumps subtracted, its features wiped in a
  // box and the survivors in that box sent again. `melted`: {crystals, upsampled,
  // segments, orphans} as sim/'s Melted, or the crystals Frost.melt returned (the rest
  // read from frost.melted). Costs O(ice near the melt).
  melt(frost, melted) {
    if (ArrayBuffer.isView(melted)) melted = meltedOf(frost, melted);
    const pts = this._meltedPoints(frost, melted);
    const rows = this.grid.finish(-1.0);
    if (this.ridges) return this._meltRidges(frost, melted, pts, rows);
    const { feature_width: width, feature_height: height } = this.params;
    const dead = featureTriangles(frost.segments, melted.segments, width, height);
    const box = bounds(dead, 6, pts, this.params.hc);
    const feats = box ? featureTriangles(frost.segments, segmentsIn(frost, box, width), width, height)
      : EMPTY;
    return this._delta(frost.tick, rows, feats, { clearBox: box });
  }

  // The melted particles' positions (x, y each), each taken into the raise under way.
  _meltedPoints(frost, melted) {
    const pts = new Float32Array(2 * (melted.crystals.length + melted.upsampled.length));
    let o = 0;
    for (const [ids, xy] of [[melted.crystals, frost.crystals], [melted.upsampled, frost.upsampled]]) {
      for (const i of ids) {
        pts[o] = xy[2 * i];
        pts[o + 1] = xy[2 * i + 1];
        this.grid.point(pts[o], pts[o + 1]);
        o += 2;
      }
    }
    return pts;
  }

  // The glass look's melt: the box holds the cut links (of the melted crystals and of
  // their children) and the links above them that thinned; every live ridge meeting it
  // is sent again.
  _meltRidges(frost, melted, pts, rows) {
    const thinner = this.ridges.melt(frost, melted.crystals);
    const c = frost.crystals, parents = frost.parents, ends = [...melted.orphans, ...thinner];
    for (const t of thinner) ends.push(parents[t]);
    for (const d of melted.crystals) if (parents[d] >= 0) ends.push(parents[d]);
    const reach = 2.0 * widest(this.params.hc) + 1.0;  // a ridge's cap reaches w past its end
    const corners = new Float32Array(4 * ends.length);  // each end's box, lo and hi
    ends.forEach((e, i) => {
      corners[4 * i] = f(c[2 * e] - reach);
      corners[4 * i + 1] = f(c[2 * e + 1] - reach);
      corners[4 * i + 2] = f(c[2 * e] + reach);
      corners[4 * i + 3] = f(c[2 * e + 1] + reach);
    });
    const box = bounds(corners, 2, pts, this.params.hc);
    let feats = EMPTY;
    if (box) {
      const links = [...new Set(Array.from(frost.segmentsNear(box, 1.0), (s) => frost.segmentsLink[s]))]
        .filter((l) => frost.crystalAlive[l] && parents[l] >= 0).sort((a, b) => a - b);
      feats = this.ridges.triangles(frost, Int32Array.from(links));
    }
    return this._delta(frost.tick, rows, feats, { clearBox: box });
  }

  // The paper's features of the live segments in rows [start, end).
  _features(frost, start, end) {
    const ids = [];
    for (let s = start; s < end; s++) if (frost.segmentsAlive[s]) ids.push(s);
    return featureTriangles(frost.segments, ids, this.params.feature_width, this.params.feature_height);
  }

  // The rows [first, end) of a link table (`link`: each row's crystal, ascending, n rows)
  // that belong to the crystals of `added`.
  _rowsOf(link, n, added) {
    return [lowerBound(link, n, added.start), lowerBound(link, n, added.end)];
  }

  _delta(tick, rows, features, { reset = false, clearBox = null } = {}) {
    const grid = this.grid.heights, lo = rows[0] * this.cols, hi = rows[1] * this.cols;
    return {
      tick, rows, heights: this.views ? grid.subarray(lo, hi) : grid.slice(lo, hi), features,
      reset, clearBox, look: this.params.look, heightScale: this.heightScale,
      changed: reset ? null : this.grid.changed,
    };
  }
}
