// The page's own frost simulation: sim/core/frost.py's FrostSim in plain JavaScript, for
// the phone with no `frost serve` (docs/local-sim.md). A tick is: walk -> drop water in
// full cells -> crystallize (the nearest crystal within hc) and admit within the tick's
// budgets -> settle (the growth rule) -> link and upsample -> register the new crystals
// -> follow the ice (growth mode, launch circle) -> place again the walkers whose hits
// only counted -> top a kept pool up (the water a tick's budget cut is owed to its area
// and placed first in the next tick: session version 14), or the window's pane keeps its
// one pool full (./pane.js). Touches and melts (./touches.js) come between ticks. The
// newest session version's rules only; no objects per particle, nothing allocated per walker.

import { Areas } from './areas.js';
import { Budget, CELL_CAP } from './budget.js';
import { FernGrowth, PaperGrowth } from './fern.js';
import { FreezingIndex } from './index.js';
import { makePane } from './pane.js';
import { CELL_WORK, Placer } from './placement.js';
import { seeded } from './random.js';
import { Skeleton } from './skeleton.js';
import { Supply } from './supply.js';
import { Touches } from './touches.js';
import { drawWalk, walkWater } from './walk.js';
import { Water } from './water.js';

// The Params fields the simulation reads (sim/params.py; snake_case, as served).
const NEEDED = ['hc', 'D', 'humidity', 'water_budget', 'step', 'active_radius', 'grid_spacing',
  'replenish', 'grow', 'grains', 'drift', 'tip_hits', 'side_hits', 'side_gap', 'long_jumps',
  'launch', 'touch_water', 'window_frost'];

/** Why `params` cannot run here, or null. */
export function paramsProblem(params) {
  const missing = NEEDED.filter((name) => !(params && name in params));
  if (missing.length) return `parameters lack ${missing.join(', ')}`;
  const window = params.window_frost || params.water_far > 0;
  if (window && !params.grains) return 'window mode needs grains';
  if (window && ['frame_sites', 'pane_sites', 'temperature'].some((name) => !(name in params))) {
    return 'window mode lacks its frame_sites, pane_sites or temperature';
  }
  return null;
}

export class Frost extends Touches {
  constructor(params, { width = 760, height = 1280, seed = 1, uniform = null } = {}) {
    super();
    const problem = paramsProblem(params);
    if (problem) throw new Error(problem);
    this.params = params;
    this.width = width;
    this.height = height;
    this.uniform = uniform || seeded(seed);
    this.ice = new Skeleton();
    this.areas = new Areas();
    this.water = new Water(params.water_budget + params.touch_water);
    this.index = new FreezingIndex(this.ice, width, height, params.hc, params.long_jumps || params.window_frost);
    this.budget = new Budget(this.index, params);
    this.growth = params.grains
      ? new FernGrowth(params, this.uniform, this.ice, this.index, this.budget) : new PaperGrowth();
    this.pane = makePane(params, this.uniform, this.index, this.ice);
    this.placer = new Placer(this.uniform, this.index, this.areas, params, this.pane);
    this.supply = new Supply(params, this.uniform, this.water, this.areas, this.placer, this.index, this.pane);
    this.thawing = false;  // the weather's thaw (`setWeather`): no step grows
    this.hits = new Int32Array(1024);  // a tick's hits: walkers, their nearest crystals
    this.hitParents = new Int32Array(1024);
    this.grown = [];  // a tick's new crystals: walker, parent, x, y each
    this.scratch = new Float32Array(2 * this.water.x.length);  // a walk's uniforms
    this.left = new Uint8Array(this.water.x.length);  // walkers that left their area
    this.jumps = new Float64Array(this.water.x.length);  // their clearance (long jumps)
    this.size = [width, height];
    this.tick = 0;
    this.clear();
  }

  /** Empties the pane: no ice, no water, no areas; the tick count goes on. Window mode
   * starts its pane again: the pane-wide area, the frame's and the glass's seeds. */
  clear() {
    for (const part of [this.ice, this.areas, this.water, this.index, this.growth, this.placer, this.supply,
      this.pane]) {
      part.clear();
    }
    this.waterMelted = 0;
    this.melted = null;
    this.startPane();
    this.rowsAtTickEnd = [0, 0, 0];
    this.added = this.closeTick(0);
  }

  startPane() {
    const start = this.pane.start();
    if (!start) return;
    this.areas.open(...start.area);
    this.plant(start.sites, false);  // the pane's own seeds: its pool is theirs
  }

  /** The weather's glass from the next step on (sim/weather): window mode grows as if its
   * `temperature` (degrees below freezing) were `temperature` and its pane's water were
   * `supply` times as much; null: a thaw, whose steps grow nothing (the walkers wait where
   * they are; `meltTips` takes the ice back). Touch mode has no temperature: a thaw alone
   * acts. */
  setWeather(temperature, supply = 1) {
    this.thawing = temperature === null || temperature === undefined;
    if (this.thawing || !this.params.window_frost) return;
    if (!(Number.isFinite(temperature) && temperature > 0 && Number.isFinite(supply) && supply >= 0)) {
      throw new RangeError(`setWeather(${temperature}, ${supply}): a temperature above 0 and a supply of 0 or more`);
    }
    if (this.growth.chilledTo) this.growth.chilledTo(this.params, temperature);
    this.pane.chilled(temperature, supply);
  }

  /** One tick (the module doc's phases); returns the rows it added, touches since the
   * last tick included: { start, end } of the crystals, and `upsampled`, `segments`.
   * In a thaw nothing grows. */
  step() {
    if (this.thawing) {
      this.tick++;
      return this.closeTick(0);
    }
    this.placer.cellWork = CELL_WORK;
    this.supply.repay(this.iceState());  // the water last tick's cell work cut comes first
    this.walk();
    // (crystallize first: it may widen this.hits, and admit must see the wide arrays)
    const found = this.crystallize();
    const [n, dropped] = this.budget.admit(this.hits, this.hitParents, found, this.water);
    this.supply.dropped += dropped;
    const grown = this.grown;
    grown.length = 0;
    const counted = this.growth.settle(this.hits, this.hitParents, n, this.water, grown);
    const start = this.ice.count;
    this.link(grown);
    this.index.register(start, this.ice.count);
    this.followIce(start, this.ice.count);
    this.replace(counted, grown);
    this.water.sweep();
    // The pane keeps its pool full; a kept pool gets back what full cells and failed
    // placements took, while glass remains.
    if (this.pane.on) this.supply.fill([0], this.iceState());
    else if (this.params.replenish || this.params.grow) this.supply.topUp(this.iceState());
    this.tick++;
    return this.closeTick(grown.length / 4);
  }

  /** What changes when the ice does (placement's cached cells follow it): crystals
   * added and melted, as one number (a string made each tick, passed to every placement,
   * cost the tick a collection of young garbage every few ticks). */
  iceState() {
    return this.ice.count * 4294967296 + this.waterMelted;
  }

  walk() {
    const water = this.water, m = water.n;
    if (m === 0) return;
    if (this.scratch.length < 2 * m) this.scratch = new Float32Array(4 * m);
    if (this.left.length < m) {
      this.left = new Uint8Array(2 * m);
      this.jumps = new Float64Array(2 * m);
    }
    drawWalk(this.uniform, m, this.scratch);
    const clearance = this.params.long_jumps ? this.index.clearance : null;
    if (clearance) clearance.radii(water, this.areas.rows, this.jumps);
    const gone = walkWater(water, this.areas, this.params.step, clearance && this.jumps, this.scratch,
      this.size, this.left);
    const ice = this.iceState();
    for (let i = 0; gone && i < m; i++) if (this.left[i]) this.supply.relocate(i, gone > 1024, ice);
  }

  /** Sec. 3.4.3: the walkers within hc of a crystal, with their nearest, into
   * this.hits / this.hitParents (walker order); returns how many. Water in a full cell
   * (CELL_CAP crystals) is dropped: it arrived at finished ice. */
  crystallize() {
    const { water, index } = this, lists = index.candidates, full = lists.countBound >= CELL_CAP;
    let n = 0;
    for (let i = 0; i < water.n; i++) {
      if (water.drop[i]) continue;
      const key = index.grid.key(water.x[i], water.y[i]), listed = lists.count[key];
      if (listed === 0) continue;
      if (full && listed >= CELL_CAP) {
        water.drop[i] = 1;
        this.supply.dropped++;
        continue;
      }
      const p = index.nearest(water.x[i], water.y[i], key);
      if (p < 0) continue;
      if (n === this.hits.length) this.widenHits();
      this.hits[n] = i;
      this.hitParents[n++] = p;
    }
    return n;
  }

  widenHits() {
    const hits = new Int32Array(2 * this.hits.length), parents = new Int32Array(2 * this.hits.length);
    hits.set(this.hits);
    parents.set(this.hitParents);
    this.hits = hits;
    this.hitParents = parents;
  }

  /** Grown walkers become crystals linked to their parents, the links upsampled; with a
   * launch circle a crystal belongs to its parent's area, else to its water's. */
  link(grown) {
    const { ice, water, params } = this, c = ice.crystals;
    for (let g = 0; g < grown.length; g += 4) {
      const w = grown[g], p = grown[g + 1];
      const area = params.launch ? ice.area[p] : water.area[w];
      const px = c[2 * p], py = c[2 * p + 1];
      const i = ice.add(grown[g + 2], grown[g + 3], p, area);
      ice.link(i, px, py, params.D);
      this.areas.ice[area]++;
      water.drop[w] = 1;
    }
    this.supply.frozen += grown.length / 4;
  }

  /** Growth mode: each area's annulus rides on its ice front; a launch circle needs the
   * reach too (crystals [start, end)). */
  followIce(start, end) {
    const { params, areas, ice } = this;
    if (this.pane.on || !(params.grow || params.launch)) return;  // (the pane's area covers the screen)
    for (let i = start; i < end; i++) {
      areas.reachTo(ice.area[i], ice.crystals[2 * i], ice.crystals[2 * i + 1]);
      if (params.grow) areas.ride(ice.area[i], params.active_radius);
    }
  }

  /** Hits that only counted (`hits[0, counted)`) are placed again; a kept pool
   * (replenish, growth mode; not the pane's: it refills) gets its frozen water back as
   * new walkers. */
  replace(counted, grown) {
    const ice = this.iceState(), many = counted > 1024;
    for (let j = 0; j < counted; j++) this.supply.relocate(this.hits[j], many, ice);
    if (this.pane.on || !(this.params.replenish || this.params.grow)) return;
    for (let g = 0; g < grown.length; g += 4) this.supply.spawn(this.water.area[grown[g]], 1, false, ice);
  }

  closeTick(frozen) {
    const now = [this.ice.count, this.ice.upsampledCount, this.ice.segmentCount], was = this.rowsAtTickEnd;
    this.rowsAtTickEnd = now;
    this.added = { tick: this.tick, start: was[0], end: now[0], upsampled: [was[1], now[1]],
      segments: [was[2], now[2]], frozen };
    return this.added;
  }
}
