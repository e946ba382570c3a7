// The canvas and where the pane (the server's screen, the hello's size) lies on it: its
// size fitted to the screen each frame, and the pane's rect in canvas and CSS px (fit.js).

import { FITS, canvasScale, paneRect, prefs, visiblePane } from "./fit.js";

export class Pane {
  constructor(canvas) {
    this.canvas = canvas;
    this.screen = null;  // the pane's [width, height] px: the hello's `screen`
    this.fit = prefs.get("fit", "fill", FITS);  // "fill" (covering, cropped) or "pane" (whole)
    this.dirty = true;  // the whole canvas is to be drawn again (its size or the fit changed)
  }

  // Where the pane lies on the canvas, canvas px {x, y, w, h, scale} (fitCanvas): covering
  // it, centred, cropped ("fill"), or whole and letterboxed ("pane"); null before a hello.
  rect() {
    return this.screen && paneRect(this.canvas.width, this.canvas.height, this.fit, this.screen);
  }

  // The part of the pane the canvas shows, in whole pane px: [x0, y0, x1, y1].
  visible() {
    return visiblePane(this.rect(), this.canvas.width, this.canvas.height, this.screen);
  }

  // The canvas's px for its CSS size, no more than the pane has to show there.
  fitCanvas() {
    if (!this.screen) return;
    const canvas = this.canvas;
    const cw = canvas.clientWidth, ch = canvas.clientHeight, dpr = window.devicePixelRatio || 1;
    const k = canvasScale(cw, ch, dpr, this.fit, this.screen);
    // At a canvas px a pane px, even sizes (as the pane's) leave the pane's crop or bars the
    // same each side: centred to the px.
    const even = k < dpr ? 2 : 1;
    const w = Math.max(even * Math.round(cw * k / even), 1), h = Math.max(even * Math.round(ch * k / even), 1);
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
      this.dirty = true;
    }
  }

  size() {
    return [this.canvas.width, this.canvas.height];
  }

  // Where the pane lies in CSS px (the page's client coordinates): {x, y, w, h, sx, sy}, sx
  // and sy CSS px per pane px (a rounded canvas may be stretched a hair more one way).
  css() {
    const canvas = this.canvas, r = this.rect(), box = canvas.getBoundingClientRect();
    const kx = box.width / canvas.width, ky = box.height / canvas.height;
    return { x: box.left + r.x * kx, y: box.top + r.y * ky, w: r.w * kx, h: r.h * ky,
      sx: r.scale * kx, sy: r.scale * ky };
  }
}
