// Fingers (Pointer Events) to the server's touch and melt messages: a tap plants a seed, a
// drag a trail; a finger that lands while another grows, the mouse's right button, or any
// finger while the warm-finger toggle is on melts. Every finger is its own id (0..31), so
// several draw at once. Moves are sent at most once a frame per finger (the latest point).

export const FINGERS = 32;

export class Pointers {
  // canvas: the element; paneRect(): where the pane lies on it, canvas px (null before
  // the hello says the pane's size); send(message): to the server; screen(): the pane's
  // [width, height] px, the hello's.
  constructor(canvas, paneRect, send, screen) {
    this.canvas = canvas;
    this.paneRect = paneRect;
    this.send = send;
    this.screen = screen;
    this.warm = false;
    this.fingers = new Map();  // pointerId -> {id, kind, moved: [x, y] | null}
    this.flushing = false;
    this.onDown = null;  // (kind, [x, y], time) of each finger down, if set
  }

  attach() {
    const c = this.canvas;
    c.addEventListener("pointerdown", (e) => this.down(e));
    c.addEventListener("pointermove", (e) => this.move(e));
    for (const type of ["pointerup", "pointercancel", "lostpointercapture"]) {
      c.addEventListener(type, (e) => this.up(e));
    }
    c.addEventListener("contextmenu", (e) => e.preventDefault());
  }

  // Screen px (y down) of an event, or null off the pane.
  point(event, clamp = false) {
    const box = this.canvas.getBoundingClientRect();
    // (canvas px per CSS px each way: a canvas's rounded size stretches it a hair)
    const kx = this.canvas.width / (box.width || 1), ky = this.canvas.height / (box.height || 1);
    const r = this.paneRect();
    if (!r) return null;  // (no pane yet)
    let x = ((event.clientX - box.left) * kx - r.x) / r.scale;
    let y = ((event.clientY - box.top) * ky - r.y) / r.scale;
    const [w, h] = this.screen();
    if (clamp) {
      x = Math.min(Math.max(x, 0), w - 0.01);
      y = Math.min(Math.max(y, 0), h - 0.01);
    }
    return x >= 0 && y >= 0 && x < w && y < h ? [x, y] : null;
  }

  down(event) {
    const p = this.point(event);
    if (!p || this.fingers.size >= FINGERS) return;
    event.preventDefault();
    const used = new Set([...this.fingers.values()].map((f) => f.id));
    let id = 0;
    while (used.has(id)) id++;
    const growing = [...this.fingers.values()].some((f) => f.kind === "touch");
    const kind = this.warm || event.button === 2 || growing ? "melt" : "touch";
    this.fingers.set(event.pointerId, { id, kind, moved: null });
    try { this.canvas.setPointerCapture(event.pointerId); } catch { /* synthetic events */ }
    this.send({ type: kind, phase: "down", id, x: p[0], y: p[1] });
    if (this.onDown) this.onDown(kind, p, event.timeStamp);
  }

  move(event) {
    const f = this.fingers.get(event.pointerId);
    if (!f) return;
    f.moved = this.point(event, true);
    if (!this.flushing) {
      this.flushing = true;
      requestAnimationFrame(() => this.flush());
    }
  }

  flush() {
    this.flushing = false;
    for (const f of this.fingers.values()) this.sendMove(f);
  }

  sendMove(f) {
    if (!f.moved) return;
    this.send({ type: f.kind, phase: "move", id: f.id, x: f.moved[0], y: f.moved[1] });
    f.moved = null;
  }

  up(event) {
    const f = this.fingers.get(event.pointerId);
    if (!f) return;
    this.sendMove(f);
    this.fingers.delete(event.pointerId);
    this.send({ type: f.kind, phase: "up", id: f.id });
  }
}
