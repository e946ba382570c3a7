// The phone's own session, as sim/io/session.py reads it: the seed, the first parameters,
// every touch, melt, parameter change, clear and backdrop with the tick of its timeline
// (a rebuild, params or clear, starts a new timeline at tick 0), and "source": "phone"
// (`frost replay` grows it again with the Python simulation, not bit for bit). A rebuild
// schedules the touches so far again as sim/io/timeline.py does (`regrow`).

import { REGROW_GAP } from "./shared.js";
export { REGROW_GAP };  // sim/core/versions.py: the longest pause a rebuild keeps
export const MOST_EVENTS = 200000;  // beyond, the file keeps what it has (and says so)

export class SessionRecord {
  // session: params.json's {format, version}; screen: [width, height].
  constructor(session, seed, params, screen) {
    this.head = { format: session.format, version: session.version, source: "phone", seed,
      width: screen[0], height: screen[1], params: { ...params } };
    this.events = [];
    this.full = false;  // MOST_EVENTS reached: later events are not kept
    this.touches = [];  // the touches since the last clear, with their timeline's ticks
    this.melts = [];
  }

  add(event) {
    if (this.events.length >= MOST_EVENTS) {
      this.full = true;
      return;
    }
    this.events.push(event);
    if (event.kind === "touch") this.touches.push(event);
    else if (event.kind === "melt") this.melts.push(event);
  }

  // A rebuild at `tick` (a "params" event with `params`, or a "clear"): the touches and
  // melts the new timeline plants again, [[tick, kind, x, y, r], ...] in tick order (none
  // after a clear).
  rebuild(tick, params = null) {
    this.add(params ? { kind: "params", tick, params: { ...params } } : { kind: "clear", tick });
    if (!params) {
      this.touches = [];
      this.melts = [];
      return [];
    }
    const again = [];
    let at = 0, prev = null;
    for (const t of this.touches) {
      if (prev !== null) at += Math.min(t.tick - prev, REGROW_GAP);
      prev = t.tick;
      again.push([at, "touch", t.x, t.y, 0]);
    }
    for (const m of this.melts) again.push([m.tick, "melt", m.x, m.y, m.r]);
    again.sort((a, b) => a[0] - b[0]);
    this.touches = again.filter((e) => e[1] === "touch").map(([tick, , x, y]) => ({ kind: "touch", tick, x, y }));
    this.melts = this.melts.map((m) => ({ ...m }));
    return again;
  }

  // The session file's JSON after `steps` ticks in all, shown with `view`.
  json(steps, view) {
    return { ...this.head, steps, events: this.events, view };
  }
}
