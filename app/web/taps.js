// Touch to first drawn growth (the bench reads frost.latencies, ms): whether a delta
// brings features (a link's ridge) within GREW_NEAR px of the last finger down: the
// desktop log's "growth", a first crystal frozen onto the seed (a link from the seed
// itself, so its ridge has vertices there whatever hc is). With `anyIce`, ice of any
// thickness on a grid vertex there counts too: the first frost (frost.frostLatencies: the
// seed's own ice, drawn with the first step after the touch, as the desktop log's "frost").

const GREW_NEAR = 12;

export class TapWatch {
  constructor() {
    this.watch = null;  // the last finger down: {x, y, t0, seen, frost, frostDrawn}, until its growth is drawn
    this.latencies = [];
    this.frostLatencies = [];
  }

  // A finger down (input.js's onDown): a touch is watched, a melt is not.
  down(kind, p, t0) {
    if (kind === "touch") this.watch = { x: p[0], y: p[1], t0, seen: false, frost: false, frostDrawn: false };
  }

  // A delta applied, its grid vertices `spacing` px apart: did the tap's frost or growth come?
  delta(delta, spacing) {
    const w = this.watch;
    if (w && !w.frost) w.frost = grewNear(delta, w, true, spacing);
    if (w && !w.seen) w.seen = grewNear(delta, w, false, spacing);
  }

  // Whether the frame about to show holds what the tap waits for.
  due() {
    const w = this.watch;
    return !!w && (w.seen || (w.frost && !w.frostDrawn));
  }

  // The frame that shows it was drawn (`ms` after the tap): true at its first frost.
  drawn(ms) {
    const w = this.watch, first = !w.frostDrawn;
    if (first) this.frostLatencies.push(ms);
    w.frostDrawn = true;
    if (w.seen) {
      this.latencies.push(ms);
      this.watch = null;
    }
    return first;
  }
}

function grewNear(delta, { x, y }, anyIce, spacing) {
  const f = delta.features;
  for (let i = 0; i < f.length; i += 6) {
    if (Math.hypot(f[i] - x, f[i + 1] - y) < GREW_NEAR) return true;
  }
  if (!anyIce) return false;
  const cols = delta.grid[0], s = spacing;
  let k = 0;
  for (const [start, count] of delta.runs) {
    for (let i = start; i < start + count; i++, k++) {
      const px = (i % cols) * s, py = Math.floor(i / cols) * s;
      if (delta.heights[k] > 0 && Math.hypot(px - x, py - y) < GREW_NEAR) return true;
    }
  }
  return false;
}
