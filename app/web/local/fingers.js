// The page's fingers (its touch and melt messages, as it sends them to frost serve) as the
// touches and melts the worker applies: a drag leaves one every few px (the window's
// spacing, sim/io/gestures.py), a point off the pane or not a number is dropped, and at
// most PENDING_MOST wait (more are dropped and counted), so a storm of taps holds no more
// memory and no more work than that.

import { PENDING_MOST } from "./shared.js";
export { PENDING_MOST };  // frost serve's bound on a page's waiting commands
const FINGERS = 32;                // finger ids 0..31, as the protocol's

export class Fingers {
  // screen: [width, height]; spacing(kind): px between a drag's points.
  constructor(screen, spacing) {
    this.screen = screen;
    this.spacing = spacing;
    this.last = new Map();  // "kind id" -> [x, y] the finger's path goes on from
    this.pending = [];      // [kind, x, y] in order
    this.dropped = 0;       // touches and melts dropped: the queue was full
  }

  // Whether (x, y) lands on the pane (sim/screen.py's touch_problem).
  onPane(x, y) {
    return Number.isFinite(x) && Number.isFinite(y) && x >= 0 && y >= 0
      && x < this.screen[0] && y < this.screen[1];
  }

  // One of the page's touch or melt messages.
  take(m) {
    const id = Number.isInteger(m.id) && m.id >= 0 && m.id < FINGERS ? m.id : 0;
    const key = `${m.type} ${id}`;
    if (m.phase === "up") {
      this.last.delete(key);
      return;
    }
    const x = m.x, y = m.y;
    if (typeof x !== "number" || typeof y !== "number" || !this.onPane(x, y)) return;
    const from = this.last.get(key);
    if (m.phase !== "move" || !from) {
      this.last.set(key, [x, y]);
      this.push(m.type, x, y);
      return;
    }
    // The points every `spacing` px from where the finger was, towards (x, y).
    const dx = x - from[0], dy = y - from[1], length = Math.hypot(dx, dy);
    const spacing = this.spacing(m.type);
    const n = Math.floor(length / spacing);
    for (let k = 1; k <= n; k++) {
      const px = from[0] + dx * k * spacing / length, py = from[1] + dy * k * spacing / length;
      this.push(m.type, px, py);
      if (k === n) this.last.set(key, [px, py]);
    }
  }

  push(kind, x, y) {
    if (this.pending.length >= PENDING_MOST) {
      this.dropped += 1;
      return;
    }
    this.pending.push([kind, x, y]);
  }

  // Up to `most` of the waiting touches and melts, oldest first.
  next(most) {
    return this.pending.splice(0, most);
  }

  clear() {
    this.pending.length = 0;
  }
}
