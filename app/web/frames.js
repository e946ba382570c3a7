// The frame loop: each frame fits the canvas, turns the light by the phone's tilt, draws
// what changed into the pane's texture and then onto the canvas, and times a tap's first
// drawn frost; a frame that fails is counted and said, and the next one still runs.

// A failed frame's reason is logged once, for this many reasons at most.
const FRAME_REASONS_LOGGED = 16;

export class FrameLoop {
  // page: `window.frost` (its phone); parts: the page's view, stream, pane, taps and status
  // line, and its gl.
  constructor(page, { view, stream, pane, taps, status, gl }) {
    Object.assign(this, { page, view, stream, pane, taps, status, gl });
    this.frames = 0;          // frames drawn onto the canvas
    this.blitDamage = null;   // pane px [x0, y0, x1, y1] drawn but not yet on the canvas
    this.frameError = null;   // the reason the last frame failed, while frames fail
    this.frameErrors = 0;
    this.loggedReasons = new Set();
  }

  start() {
    requestAnimationFrame(() => this.frame());
  }

  // One frame, and the next asked for whatever this one met: a frame that throws (a bad
  // value set on `frost`, a renderer's bug) stopped every frame after it, ticks still coming.
  frame() {
    try {
      this.draw();
      if (this.frameError) this.recovered();
    } catch (err) {
      this.failed(err);
    } finally {
      requestAnimationFrame(() => this.frame());
    }
  }

  // A failed frame: counted, its reason in the status line and the console, logged once for
  // each reason (a frame fails again 60 times a second while its cause stays).
  failed(err) {
    const reason = (err && err.message) || String(err);
    this.frameErrors += 1;
    if (reason === this.frameError) return;
    this.frameError = reason;
    this.status.say(`a frame failed: ${reason}`);
    if (!this.loggedReasons.has(reason) && this.loggedReasons.size < FRAME_REASONS_LOGGED) {
      this.loggedReasons.add(reason);
      console.error(`frost: a frame failed: ${reason}`, err);
    }
  }

  // Frames run again: the status line's word on the failure goes.
  recovered() {
    if (this.status.text === `a frame failed: ${this.frameError}`) this.status.say("");
    this.frameError = null;
  }

  draw() {
    const view = this.view, r = view.renderer, pane = this.pane;
    pane.fitCanvas();
    if (r && view.serverLight) this.page.phone.frame(r, view.serverLight);
    // (a snapshot comes in parts: the pane is drawn once it is whole, not half drawn first,
    // a whole pane's draw spent on a frame the next part replaces)
    if (r && view.warm) {
      const look = view.warm in r.defines.ice ? view.warm : "paper";
      view.warm = null;
      if (this.stream.midSnapshot) r.warm(look);
    }
    if (r && !this.stream.midSnapshot) this.drawPane();
    if (r && (pane.dirty || this.blitDamage)) {
      view.blitter.draw(r.frame, pane.rect(), pane.dirty ? null : this.blitDamage);
      pane.dirty = false;
      this.blitDamage = null;
      this.frames += 1;
      if (this.taps.due()) this.tapDrawn();
    }
  }

  // The tap's first frost or growth is on the canvas: its time, once the GPU drew it.
  tapDrawn() {
    const gl = this.gl;
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    if (this.taps.drawn(performance.now() - this.taps.watch.t0)) {
      this.page.phone.tapped();  // a short buzz: the tap took
    }
  }

  // Draw what changed into the pane's texture, where the screen shows it (`whole`: all of
  // it); the canvas is told of it at the next frame.
  drawPane(all = false, whole = false) {
    // (a px more each way: a scaled blit's filter reaches past the last px shown)
    const [x0, y0, x1, y1] = this.pane.visible();
    const d = this.view.renderer.render(all, whole ? null : [x0 - 2, y0 - 2, x1 + 2, y1 + 2]);
    const b = this.blitDamage;
    if (d) this.blitDamage = b ? [Math.min(b[0], d[0]), Math.min(b[1], d[1]), Math.max(b[2], d[2]), Math.max(b[3], d[3])] : d;
  }

  // The pane's pixels now (RGBA, top row first) as base64: for the tests and the bench.
  pixels() {
    this.drawPane(false, true);
    const px = this.view.renderer.readFrame();
    let s = "";
    for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode(...px.subarray(i, i + 0x8000));
    return btoa(s);
  }

  // Frame times (ms) of `n` full frames of the pane, each waited for (a 1-pixel read).
  times(n) {
    const gl = this.gl, r = this.view.renderer, one = new Uint8Array(4), times = [];
    for (let i = 0; i < n; i++) {
      const t0 = performance.now();
      r.render(true);
      gl.bindFramebuffer(gl.FRAMEBUFFER, r.frameFbo);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
      times.push(performance.now() - t0);
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return times;
  }
}
