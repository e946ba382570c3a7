// The page's screenshot: what the screen shows of the pane as a PNG with the desktop's
// metadata keys, downloaded (the menu's button, S or F12).

import { withText } from "./png.js";

const REVOKE_MS = 10000;  // the download's URL kept this long for the browser to read it

// `blob` downloaded as `prefix`-<date>-<time>.`ext`.
export function save(blob, prefix, ext) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  const stamp = new Date().toISOString().replace(/[-:]/g, "").replace("T", "-").slice(0, 15);
  a.download = `${prefix}-${stamp}.${ext}`;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), REVOKE_MS);
}

export class Screenshots {
  // query: "?token=..." or ""; view, pane, frames, stream: the page's parts it reads.
  constructor(query, { view, pane, frames, stream }) {
    Object.assign(this, { query, view, pane, frames, stream });
    this.localMeta = null;  // () => the phone's own frost's keys, while it grows (alone.js)
  }

  // What the screen shows of the pane, in pane px (all of it in "whole pane", the part the
  // screen crops it to in "fill"), as PNG bytes with the desktop's metadata keys.
  async png() {
    const r = this.view.renderer, screen = this.pane.screen;
    this.frames.drawPane();
    const pixels = r.readFrame();
    for (let i = 3; i < pixels.length; i += 4) pixels[i] = 255;
    const [x0, y0, x1, y1] = this.pane.visible();
    const c = document.createElement("canvas");
    [c.width, c.height] = [x1 - x0, y1 - y0];
    c.getContext("2d").putImageData(new ImageData(new Uint8ClampedArray(pixels.buffer), ...screen), -x0, -y0);
    const blob = await new Promise((resolve) => c.toBlob(resolve, "image/png"));
    const png = new Uint8Array(await blob.arrayBuffer());
    // frost_meta's keys in its order; parameters, seed and touches as the server gives them
    // (GET /meta).
    const known = (this.localMeta && await this.localMeta()) || await this.serverMeta();
    const local = new Date(Date.now() - new Date().getTimezoneOffset() * 60000);
    const meta = {
      parameters: known.parameters ?? null, seed: known.seed ?? null, tick: this.stream.tick,
      touches: known.touches ?? [], Software: "frost (page)",
      "Creation Time": local.toISOString().slice(0, 19),
      view: { light: r.light, features: r.showFeatures, bumps: r.showBumps, background: this.view.backdrop },
    };
    // A crop: where its px lie on the pane (the touches' px are the pane's).
    if (c.width !== screen[0] || c.height !== screen[1]) meta.view.crop = [x0, y0, c.width, c.height];
    if (known.source) meta.source = known.source;  // "phone": grown by the page, not frost serve
    return withText(png, meta);
  }

  async serverMeta() {
    try {
      const r = await fetch(`meta${this.query}`);
      if (r.ok) return await r.json();
    } catch { /* the server is gone: the page's own keys only */ }
    return {};
  }

  // The screenshot downloaded as frost-<date>-<time>.png (nothing before the first hello).
  async take() {
    if (!this.view.renderer) return;
    save(new Blob([await this.png()], { type: "image/png" }), "frost", "png");
  }
}
