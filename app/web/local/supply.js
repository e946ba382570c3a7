// The water supply (sim/core/supply.py, budget.py): walkers placed, topped up within the
// water budget, returned by melts, and the ring of water a touch brings its seed.

import { room } from './arrays.js';
import { ringSpot } from './placement.js';
import { TOUCH_TRIES } from './shared.js';

// Draws for each walker a touch brings to its ring.
export { TOUCH_TRIES };

export class Supply {
  constructor(params, uniform, water, areas, placer, index, pane) {
    this.pane = pane;  // its pool's size (window mode; else `humidity`)
    this.params = params;
    this.uniform = uniform;
    this.water = water;
    this.areas = areas;
    this.placer = placer;
    this.index = index;
    this.picks = new Int32Array(64);  // waterSeed's walkers of the area
    this.owed = new Int32Array(16);  // walkers owed to each area, placed first next tick
    this.clear();
  }

  clear() {
    this.created = this.frozen = this.dropped = 0;
    this.owed.fill(0);
  }

  /** Walkers owed to their areas, to be placed in a later tick. */
  get waiting() {
    return sum(this.owed);
  }

  owe(area) {
    this.owed = room(this.owed, Math.max(this.areas.n, area + 1));
    this.owed[area]++;
  }

  /** `k` walkers of `area`: new ones (counted created once placed or owed; one with no
   * spot at all is never created), or `repaid` owed ones (created already: one with no
   * spot at all is dropped). The placer's `owe` keeps those it could not place this
   * tick owed. */
  spawn(area, k, many, ice, repaid = false) {
    const { water, placer } = this;
    for (let j = 0; j < k; j++) {
      if (placer.place(area, many, ice)) {
        water.append(placer.spot[0], placer.spot[1], area);
        if (!repaid) this.created++;
      } else if (placer.owe) {
        this.owe(area);
        if (!repaid) this.created++;
      } else if (repaid) {
        this.dropped++;
      }
    }
  }

  /** Places walker `i` again in its area; false (it is marked to drop) where it found
   * no spot: it is then owed to its area (placed in a later tick) or, with no spot
   * left at all, dropped. */
  relocate(i, many, ice) {
    const { water, placer } = this;
    if (placer.place(water.area[i], many, ice)) {
      water.x[i] = placer.spot[0];
      water.y[i] = placer.spot[1];
      return true;
    }
    water.drop[i] = 1;
    if (placer.owe) this.owe(water.area[i]);
    else this.dropped++;
    return false;
  }

  /** At a tick's start: the owed walkers are placed again within the water budget
   * (what it has no room for stays owed), those cut again stay owed; an area whose ice
   * all melted, or with no glass left, is owed nothing (its owed are dropped). */
  repay(ice) {
    const { owed, placer, areas } = this, n = Math.min(owed.length, areas.n);
    let roomLeft = Math.max(0, this.params.water_budget - this.water.n);
    for (let a = 0; a < n; a++) {
      if (owed[a] === 0) continue;
      if (areas.ice[a] === 0 || placer.isBare(a, ice)) {
        this.dropped += owed[a];
        owed[a] = 0;
        continue;
      }
      const k = Math.min(owed[a], roomLeft);
      roomLeft -= k;
      owed[a] -= k;
      this.spawn(a, k, k > 1024, ice, true);
    }
  }

  /** At a tick's end, for a kept pool (replenish, growth mode): a pool short of
   * `humidity` (its owed walkers counted in it) is topped up within the water budget
   * wherever its area still has ice and glass; nothing is trimmed from other pools. */
  topUp(ice) {
    const { water, params, areas, placer } = this, n = areas.n, counts = water.counts(n);
    this.owed = room(this.owed, n);
    let roomLeft = params.water_budget - water.n - this.waiting;
    for (let a = 0; a < n && roomLeft > 0; a++) {
      if (areas.ice[a] === 0 || placer.isBare(a, ice)) continue;
      const k = Math.min(Math.max(0, params.humidity - counts[a] - this.owed[a]), roomLeft);
      roomLeft -= k;
      this.spawn(a, k, k > 1024, ice);
    }
  }

  /** Tops the pools of `areas` (distinct) up to `humidity` within `water_budget`; when
   * the budget is spent, the areas holding more than a fair share give theirs up first
   * (each keeps its oldest walkers). */
  fill(areas, ice) {
    const { water, params } = this, n = this.areas.n;
    const counts = water.counts(n), pool = this.pane.pool(params.humidity);
    this.owed = room(this.owed, n);
    const owed = this.owed;  // owed walkers are the pool's too
    let roomLeft = params.water_budget - water.n - this.waiting;
    const want = areas.map((a) => Math.max(0, pool - counts[a] - owed[a]));
    if (sum(want) > roomLeft) {
      let holding = 0;
      for (let a = 0; a < n; a++) if (counts[a] > 0 || areas.includes(a)) holding++;
      const share = Math.floor(params.water_budget / holding);
      areas.forEach((a, j) => { want[j] = Math.min(want[j], Math.max(0, share - counts[a] - owed[a])); });
      roomLeft += this.trim(counts, areas, sum(want) - roomLeft, share);
    }
    let given = 0;
    areas.forEach((a, j) => {
      const k = Math.min(want[j], Math.max(0, roomLeft - given));
      given += want[j];
      this.spawn(a, k, k > 1024, ice);
    });
  }

  /** Cuts the pools other than `areas` to a common level no lower than `share` so that
   * up to `need` walkers go; returns how many went. */
  trim(counts, areas, need, share) {
    if (need <= 0) return 0;
    const n = this.areas.n, others = Array.from(counts.subarray(0, n));
    for (const a of areas) others[a] = 0;
    const limit = level(others, need, share), water = this.water, seen = new Int32Array(n);
    for (let i = 0; i < water.n; i++) {
      const a = water.area[i];
      if (!areas.includes(a) && seen[a]++ >= limit) water.drop[i] = 1;
    }
    const cut = water.sweep();
    this.dropped += cut;
    return cut;
  }

  /** Melted crystals' water (one entry per crystal: its area) goes back to its area,
   * never above `humidity` nor the budget; an area with no ice left loses its pool; a
   * kept pool (replenish, growth mode, the pane) is topped up. */
  returned(deadAreas, ice) {
    const { water, params, areas } = this;
    for (let i = 0; i < water.n; i++) if (areas.ice[water.area[i]] === 0) water.drop[i] = 1;
    this.dropped += water.sweep();
    const back = [...new Set(deadAreas)].filter((a) => areas.ice[a] > 0).sort((p, q) => p - q);
    if (params.replenish || params.grow || this.pane.on) {
      this.fill(back, ice);
      return;
    }
    const counts = water.counts(areas.n);
    let roomLeft = Math.max(0, params.water_budget - water.n);
    for (const a of back) {
      const melted = deadAreas.filter((d) => d === a).length;
      const k = Math.min(melted, Math.max(0, params.humidity - counts[a]), roomLeft);
      roomLeft -= k;
      this.spawn(a, k, false, ice);
    }
  }

  /** A touch brings `touch_water` walkers to glass around its seed at (sx, sy): uniform
   * in the ring from hc to 2 hc, on the screen, at least hc / 2 from every live crystal
   * and no nearer to any crystal than to the seed. While the area's pool is short of
   * `humidity` and the budget has room it brings new walkers, and moves random ones of
   * its own pool for the rest; one with no such spot in TOUCH_TRIES draws stays. */
  waterSeed(sx, sy, area) {
    const { water, params } = this, want = params.touch_water;
    let mine = 0;
    for (let i = 0; i < water.n; i++) {
      if (water.area[i] !== area) continue;
      this.picks = room(this.picks, mine + 1);
      this.picks[mine++] = i;
    }
    this.owed = room(this.owed, this.areas.n);  // owed walkers are the pool's and the budget's too
    const fresh = Math.max(0, Math.min(want, this.pane.pool(params.humidity) - mine - this.owed[area],
      params.water_budget - water.n - this.waiting));
    const moved = Math.min(mine, want - fresh);
    for (let j = 0; j < moved; j++) {  // a random `moved` of the area's walkers (Fisher-Yates)
      const k = j + Math.min(Math.floor(this.uniform() * (mine - j)), mine - j - 1);
      [this.picks[j], this.picks[k]] = [this.picks[k], this.picks[j]];
    }
    for (let j = 0; j < moved + fresh; j++) {
      const spot = this.besideSeed(sx, sy);
      if (!spot) continue;
      if (j < moved) {
        water.x[this.picks[j]] = spot[0];
        water.y[this.picks[j]] = spot[1];
      } else {
        water.append(spot[0], spot[1], area);
        this.created++;
      }
    }
  }

  besideSeed(sx, sy) {
    const index = this.index, hc = this.params.hc;
    for (let t = 0; t < TOUCH_TRIES; t++) {
      const [x, y] = ringSpot(this.uniform, sx, sy, hc);
      if (!(x >= 0 && x < index.width && y >= 0 && y < index.height)) continue;
      const d2 = index.nearestD2(x, y);
      if (d2 >= index.apart2 && (x - sx) ** 2 + (y - sy) ** 2 <= d2) return [x, y];
    }
    return null;
  }
}

function sum(values) {
  let s = 0;
  for (const v of values) s += v;
  return s;
}

/** The highest level >= floor such that cutting every count down to it frees at least
 * `need` (or `floor` itself if even that frees less): a water-filling cut. */
export function level(counts, need, floor) {
  const freed = (cut) => sum(counts.map((c) => Math.max(c - cut, 0)));
  let lo = floor, hi = Math.max(0, ...counts);
  if (freed(lo) < need) return lo;
  while (lo < hi) {
    const mid = Math.floor((lo + hi + 1) / 2);
    if (freed(mid) >= need) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}
