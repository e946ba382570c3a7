// Growth rules (sim/rules/fern.py): where a walker that reached ice leaves its crystal.
// `PaperGrowth` is Sec. 3.4.3 as written: every one freezes where it stands. `FernGrowth`
// adds grains and hit counters (docs/method.md, 6): six slots a crystal, a seed's all
// tips, any other's straight on (a tip) and +-60 degrees (sides); a slot grows its child
// one hc along its axis on its tip_hits-th (side_hits-th) hit; a touch's ringed seed
// counts its hits together until its first child. Walkers whose hit only counted go back
// to the pool. Per-crystal state lives in typed arrays beside the skeleton's.

import { room } from './arrays.js';
import { FRAME_PX, chilled, edgeDistance, rint } from './pane.js';
import { normal } from './random.js';

const SIXTH = Math.PI / 3;
const TIP = 0, SIDE = 1, CLOSED = 2;
// A non-seed crystal's slots from its own axis: straight on, +60, +120, back, -120, -60.
const SLOT_KIND = [TIP, SIDE, CLOSED, CLOSED, CLOSED, SIDE];
const HITS_CAP = 1 << 20;  // a blocked slot keeps counting: capped

export class PaperGrowth {
  clear() {}

  addSeed() {}

  /** Every hit grows where its walker stands: `grown` holds [walker, parent, x, y]. */
  settle(hits, parents, n, water, grown) {
    for (let j = 0; j < n; j++) grown.push(hits[j], parents[j], water.x[hits[j]], water.y[hits[j]]);
    return 0;
  }

  melted() {}
}

export class FernGrowth {
  constructor(params, uniform, ice, index, budget) {
    this.uniform = uniform;
    this.budget = budget;
    this.ice = ice;
    this.index = index;
    this.L = params.hc;
    this.drift = params.drift * Math.PI / 180;
    this.gap = params.side_gap;
    this.need = [...chilled(params), -1];  // (window mode: scaled by its temperature)
    // Fronds (sim/rules/fronds.py): rule 1's branch order, rule 4's colder frame.
    this.orderHits = params.order_hits ?? 1;
    this.maxOrder = params.max_order ?? 0;
    this.frameChill = params.frame_chill ?? 0;
    this.fronds = this.orderHits !== 1 || this.maxOrder > 0 || this.frameChill > 0;
    this.width = index.width;
    this.height = index.height;
    this.axis = new Float64Array(256);  // radians: direction of slot 0
    this.slot = new Int8Array(256);  // which slot of its parent holds each crystal (-1 none)
    this.seed = new Uint8Array(256);  // a seed: six tip slots
    this.ringed = new Uint8Array(256);  // a touch's seed with a ring: first hits pooled
    this.child = new Int32Array(6 * 256);  // each slot's child, -1 if empty
    this.hits = new Int32Array(6 * 256);
    this.order = new Int8Array(256);  // branch order
    this.stamp = new Int32Array(6 * 256);  // the settle that last counted each slot
    this.settles = 0;
    this.cand = [];  // this settle's due hits: walker, parent, slot, side, axis
    this.n = 0;
  }

  clear() {
    this.n = 0;
  }

  /** A new crystal's row (a seed's: six tips, its grain drawn in [0, 60) degrees). */
  append(axis, slot, seed, order, ringed) {
    const i = this.n++;
    for (const name of ['axis', 'slot', 'seed', 'ringed', 'order']) this[name] = room(this[name], this.n);
    for (const name of ['child', 'hits', 'stamp']) this[name] = room(this[name], this.n, 6);
    this.axis[i] = axis;
    this.slot[i] = slot;
    this.seed[i] = seed;
    this.ringed[i] = ringed;
    this.order[i] = order;
    this.child.fill(-1, 6 * i, 6 * i + 6);
    this.hits.fill(0, 6 * i, 6 * i + 6);
    this.stamp.fill(-1, 6 * i, 6 * i + 6);
  }

  addSeed(ringed) {
    this.append(this.uniform() * SIXTH, -1, 1, 0, ringed ? 1 : 0);
  }

  fresh(p) {
    if (!this.ringed[p]) return false;
    for (let k = 0; k < 6; k++) if (this.child[6 * p + k] >= 0) return false;
    return true;
  }

  /** The hits (walkers `hits[j]` within hc of crystals `parents[j]`, j < n, in walker
   * order) of a tick: those that grow go to `grown` as [walker, parent, x, y] (their
   * crystals are the skeleton's next); returns how many only counted (left in
   * `hits[0, returned)`, to be placed again). */
  settle(hits, parents, n, water, grown) {
    const c = this.ice.crystals, cand = this.cand, settle = ++this.settles;
    cand.length = 0;
    // A slot is due on the hit that reaches its need; one blocked before (its count past
    // the need) is due on its first hit of a tick.
    let counted = 0;
    for (let j = 0; j < n; j++) {
      const p = parents[j], w = hits[j];
      const turn = (Math.atan2(water.y[w] - c[2 * p + 1], water.x[w] - c[2 * p]) - this.axis[p]) / SIXTH;
      const k = ((rint(turn) % 6) + 6) % 6;
      const kind = this.seed[p] ? TIP : SLOT_KIND[k];
      const need = this.fronds ? this.frondNeed(this.need[kind], kind === SIDE, this.order[p], c[2 * p], c[2 * p + 1])
        : this.need[kind];
      if (need > 0 && this.child[6 * p + k] < 0) {  // an open, empty slot: its hit counts
        const key = 6 * p + (this.fresh(p) ? 0 : k), first = this.stamp[key] !== settle;
        this.stamp[key] = settle;
        const now = this.hits[key];
        this.hits[key] = Math.min(now + 1, HITS_CAP);
        if (first ? now >= need - 1 : now === need - 1) {
          cand.push(w, p, k, SLOT_KIND[k] === SIDE && !this.seed[p], this.axis[p] + k * SIXTH);
          continue;
        }
      }
      hits[counted++] = w;
    }
    return this.grow(hits, counted, grown);
  }

  /** The hits a slot needs under frond rules 1 and 4 (sim/rules/fronds.py): its kind's
   * `need` x order_hits^order / (1 + frame_chill e^(-d / FRAME_PX)), d its crystal's (at
   * x, y) distance to the edge, rounded, at least 1; -1 (closed) for a closed slot and
   * a side slot of a crystal of order max_order or more. */
  frondNeed(need, side, order, x, y) {
    if (need <= 0 || (this.maxOrder && side && order >= this.maxOrder)) return -1;
    let scale = 1;
    if (this.orderHits !== 1) scale *= this.orderHits ** order;
    if (this.frameChill) scale /= 1 + this.frameChill * Math.exp(-edgeDistance(x, y, this.width, this.height) / FRAME_PX);
    return Math.max(1, rint(need * scale));
  }

  /** The hits a slot needs from now on: the weather's glass at `temperature` (window
   * mode); the hits counted so far are kept. */
  chilledTo(params, temperature) {
    this.need = [...chilled(params, temperature), -1];
  }

  /** The due hits' spots (one hc from the parent along the slot's axis), kept where on
   * the screen, at least hc / 2 from the tick's ice and from the spots kept before it,
   * clear of same-side branches (side_gap) and within the cells' cap; the rest count. */
  grow(hits, counted, grown) {
    const cand = this.cand, c = this.ice.crystals, index = this.index, kept = [];
    for (let m = 0; m < cand.length; m += 5) {
      const p = cand[m + 1], k = cand[m + 2], angle = cand[m + 4];
      const x = Math.fround(c[2 * p] + this.L * Math.cos(angle));
      const y = Math.fround(c[2 * p + 1] + this.L * Math.sin(angle));
      let ok = x >= 0 && x < index.width && y >= 0 && y < index.height
        && index.nearestD2(x, y) >= index.apart2 && !(cand[m + 3] && this.gap > 1 && !this.gapClear(p, k));
      for (let s = 0; ok && s < kept.length; s += 3) ok = Math.hypot(x - kept[s], y - kept[s + 1]) >= this.L / 2;
      if (ok) kept.push(x, y, m);
      else hits[counted++] = cand[m];
    }
    const room = this.budget.roomFor(kept, 3), fresh = [];
    let next = this.ice.count;
    for (let s = 0; s < kept.length; s += 3) {
      const m = kept[s + 2], w = cand[m], p = cand[m + 1], k = cand[m + 2];
      if (!room[s / 3]) {
        hits[counted++] = w;
        continue;
      }
      if (this.fresh(p)) fresh.push(p);  // (before its first child is set)
      this.child[6 * p + k] = next++;
      grown.push(w, p, kept[s], kept[s + 1]);
      const side = cand[m + 3] ? 1 : 0, turn = normal(this.uniform) * this.drift;
      this.append(cand[m + 4] + turn, k, 0, Math.min(this.order[p] + side, 127), 0);
    }
    for (const p of fresh) this.hits.fill(0, 6 * p, 6 * p + 6);  // its pooled count starts over
    return counted;
  }

  /** No side child in slot k within side_gap - 1 links up or down the stem of `p`. */
  gapClear(p, k) {
    const { child, slot } = this, parent = this.ice.parents;
    let up = p, down = p;
    for (let step = 0; step < this.gap - 1; step++) {
      up = up >= 0 && slot[up] === 0 ? parent[up] : -1;
      down = down >= 0 ? child[6 * down] : -1;
      if ((up >= 0 && child[6 * up + k] >= 0) || (down >= 0 && child[6 * down + k] >= 0)) return false;
    }
    return true;
  }

  /** A melt: a melted crystal frees its parent's slot (whose count starts over), its own
   * slots go with it, its orphans hang from no slot, and the live crystals at the melt's
   * `edge` open all six slots, as a seed's (docs/method.md 5.4), or under the frond rules
   * keep their own (their stems grow on across the clearing); either way they go back to
   * branch order 0. `parents`: as before the melt. */
  melted(dead, parents, orphans, edge) {
    for (const d of dead) {
      const p = parents[d];
      if (p >= 0) {
        this.child[6 * p + this.slot[d]] = -1;
        this.hits[6 * p + this.slot[d]] = 0;
      }
    }
    for (const d of dead) {
      this.child.fill(-1, 6 * d, 6 * d + 6);
      this.hits.fill(0, 6 * d, 6 * d + 6);
    }
    for (const o of orphans) this.slot[o] = -1;
    for (const e of edge) {
      if (!this.fronds) this.seed[e] = 1;
      this.order[e] = 0;
    }
  }
}
