// What the page's Frost does between ticks at a finger's word (sim/core/touches.py):
// touches plant seeds, each with its area's water; warm fingers melt ice and give its
// water back. And what it holds, as the geometry and the worker read it (sim/core/views.py).
// Bad input (off the pane, not finite) changes nothing.

import { MAX_MELT_RADIUS } from './shared.js';  // px (sim/screen.py)

/** The largest float32 below `size`: an on-screen float64 point stays on the screen. */
function below(size) {
  const f = new Float32Array([size]);
  new Int32Array(f.buffer)[0] -= 1;
  return f[0];
}

export class Touches {
  /** Plants a seed crystal at (x, y) px: it joins the area whose disc holds it (topping
   * its pool up to `humidity`) or opens one, and with `touch_water` brings a ring of water
   * around itself. Returns false, and nothing changes, off the pane, for a value not
   * finite, or where its seed would list a cell past the cells' cap. */
  touch(x, y) {
    return this.plant([x, y], true) > 0;
  }

  /** Seeds at the points `xy` (x, y interleaved), each as `touch` plants it, then one
   * top-up of the areas they joined, then (`water`, with `touch_water`) each seed's ring
   * of water: a touch, or the window pane's own seeds (no ring: the pane's pool is
   * theirs). Returns how many were planted. */
  plant(xy, water) {
    const { params, ice } = this, ringed = water && params.touch_water > 0, planted = [];
    for (let j = 0; j < xy.length; j += 2) {
      const x = xy[j], y = xy[j + 1];
      if (!(Number.isFinite(x) && Number.isFinite(y) && x >= 0 && x < this.width && y >= 0 && y < this.height)) {
        continue;
      }
      const fx = Math.min(Math.fround(x), below(this.width)), fy = Math.min(Math.fround(y), below(this.height));
      // (a typed array, as a tick's crystals come: an array here would cost the compiled tick)
      if (!this.budget.roomFor(Float32Array.of(fx, fy), 2)[0]) continue;
      const area = this.areas.areaFor(fx, fy, params.active_radius);
      const seed = ice.add(fx, fy, -1, area);
      this.areas.ice[area]++;
      this.growth.addSeed(ringed);
      this.index.register(seed, seed + 1);
      this.followIce(seed, seed + 1);  // a seed joining an area may lie beyond its ice
      planted.push(fx, fy, area);
    }
    const areas = [...new Set(planted.filter((_, k) => k % 3 === 2))].sort((a, b) => a - b);
    if (areas.length) this.supply.fill(areas, this.iceState());
    for (let k = 0; ringed && k < planted.length; k += 3) this.supply.waterSeed(planted[k], planted[k + 1], planted[k + 2]);
    return planted.length / 3;
  }

  /** A warm finger at (x, y): the crystals within `r` px melt and their water returns to
   * its area's pool; their links and their children's leave the skeleton (the children
   * become roots). Returns an Int32Array of the melted crystals; `this.melted` holds
   * them with the upsample particles, segments and orphans the melt removed. */
  melt(x, y, r) {
    const none = new Int32Array(0);
    const ok = [x, y, r].every(Number.isFinite) && r > 0 && r <= MAX_MELT_RADIUS
      && x >= 0 && x < this.width && y >= 0 && y < this.height;
    if (!ok) return none;
    const { ice, index } = this;
    const dead = index.crystalsNear(x, y, r);
    this.kill(dead);
    // A child lies within one link of its parent: look no further than that.
    const near = index.crystalsNear(x, y, r + ice.longestLink + 1);
    const gone = new Set(dead), parents = ice.parents;
    const orphans = near.filter((i) => gone.has(parents[i]));
    this.growth.melted(dead, parents, orphans, dead.length ? near : none);
    for (const o of orphans) parents[o] = -1;
    const [segments, upsampled] = ice.cut([...dead, ...orphans]);
    return this.returned({ crystals: dead, upsampled, segments, orphans });
  }

  /** The weather's thaw, one layer (sim/core/melting.py melt_tips): the live crystals no
   * live crystal grows from (the ice's thin edges) melt and their water returns, as a
   * warm finger's does; none has a child to orphan, and their parents, the new tips,
   * keep their slots as they were. Returns the melted crystals (`this.melted` as `melt`'s). */
  meltTips() {
    const dead = this.ice.tips(), none = new Int32Array(0);
    this.kill(dead);
    this.growth.melted(dead, this.ice.parents, none, none);
    const [segments, upsampled] = this.ice.cut([...dead]);
    return this.returned({ crystals: dead, upsampled, segments, orphans: none });
  }

  /** Crystals `dead` die and leave the index and the pane's counts. */
  kill(dead) {
    const ice = this.ice;
    for (const d of dead) ice.crystalAlive[d] = 0;
    ice.alive -= dead.length;
    this.pane.melted(dead);
    this.index.remove(dead);
  }

  /** The water of the crystals `melted` back in its areas' pools. */
  returned(melted) {
    const ice = this.ice, dead = melted.crystals;
    this.waterMelted += dead.length;
    const deadAreas = Array.from(dead, (d) => ice.area[d]);
    for (const a of deadAreas) this.areas.ice[a]--;
    this.supply.returned(deadAreas, this.iceState());
    this.melted = melted;
    return dead;
  }

  /** Replaces every walker by walkers at `xy` (x, y interleaved, px) in area `area`: exact
   * water for a test to start a tick from (a touch opens the area). */
  setWater(xy, area = 0) {
    this.water.clear();
    for (let j = 0; j < xy.length; j += 2) this.water.append(Math.fround(xy[j]), Math.fround(xy[j + 1]), area);
  }

  /** Indices of live segments whose points may lie within `reach` x their length beside
   * them of the px box [x0, y0, x1, y1] (a superset; sim/core/views.py segments_near). */
  segmentsNear(box, reach) {
    const pad = this.ice.longestLink * (1 + reach) + 1, [x0, y0, x1, y1] = box;
    return this.ice.liveSegments(this.index.crystalsInBox(x0 - pad, y0 - pad, x1 + pad, y1 + pad));
  }

  // ---- what the simulation holds (the arrays themselves; valid until the next tick) ----
  get count() { return this.ice.count; }  // crystals ever grown, melted ones included
  get alive() { return this.ice.alive; }  // crystals not melted
  get crystals() { return this.ice.crystals; }
  get parents() { return this.ice.parents; }
  get crystalAlive() { return this.ice.crystalAlive; }
  get crystalArea() { return this.ice.area; }
  get upsampledCount() { return this.ice.upsampledCount; }
  get upsampled() { return this.ice.upsampled; }
  get upsampledLink() { return this.ice.upsampledLink; }
  get upsampledAlive() { return this.ice.upsampledAlive; }
  get segmentCount() { return this.ice.segmentCount; }
  get segments() { return this.ice.segments; }
  get segmentsLink() { return this.ice.segmentsLink; }
  get segmentsAlive() { return this.ice.segmentsAlive; }
  get waterCount() { return this.water.n; }
}
