// The page as a phone app: the menu's switches for how the pane fills the screen, tilt
// and vibration (each remembered), the tilted light drawn each frame, the screen kept on,
// and a short buzz when a tap's first frost is drawn.

import { FITS, prefs } from "./fit.js";
import { Tilt, tiltProblem } from "./tilt.js";
import { Awake } from "./awake.js";

export const BUZZ_MS = 12;

export class PhoneApp {
  // state: `window.frost` (state.fit is the pane's, pane.js); root: the menu's element.
  constructor(state, root, win = globalThis) {
    this.state = state;
    this.win = win;
    this.tilt = new Tilt(win);
    this.awake = new Awake(win.navigator, win.document);
    this.applied = null;  // the light this module last gave the renderer
    this.trace = null;    // [[ms, right, up], ...] of each frame's drawn tilt, when an array
    const $ = (id) => root.querySelector(`#${id}`);
    this.$ = $;

    state.fit = prefs.get("fit", "fill", FITS);
    const whole = $("whole");
    whole.checked = state.fit === "pane";
    whole.addEventListener("change", () => {
      state.fit = whole.checked ? "pane" : "fill";
      prefs.set("fit", state.fit);
      state.dirty = true;
    });

    this.canBuzz = typeof win.navigator.vibrate === "function";
    this.buzzing = this.canBuzz && prefs.get("buzz", "on", ["on", "off"]) === "on";
    const buzz = $("buzz");
    buzz.closest("label").hidden = !this.canBuzz;  // iOS has no Vibration API
    buzz.checked = this.buzzing;
    buzz.addEventListener("change", () => {
      this.buzzing = buzz.checked;
      prefs.set("buzz", buzz.checked ? "on" : "off");
    });

    // Tilt: on unless switched off. Where the browser asks a permission it is tried at
    // once (granted before, or a browser that grants it); iOS grants it only from a tap,
    // so there the switch stays off until the user turns it on.
    const tilt = $("tilt");
    const problem = tiltProblem(win);
    this.why(problem);
    tilt.disabled = !!problem;
    tilt.checked = false;
    if (!problem && prefs.get("tilt", "on", ["on", "off"]) === "on") {
      this.tilt.enable(true).then(() => { tilt.checked = this.tilt.on; });
    }
    tilt.addEventListener("change", async () => {
      prefs.set("tilt", tilt.checked ? "on" : "off");
      const why = await this.tilt.enable(tilt.checked);
      tilt.checked = this.tilt.on;
      this.why(why);
    });
    win.document.addEventListener("visibilitychange", () => {
      if (win.document.visibilityState === "visible") this.tilt.recentre();
    });
  }

  why(text) {
    const el = this.$("tilt-why");
    el.textContent = text || "";
    el.hidden = !text;
  }

  // Once a frame: the renderer's light is the server's (`base`, what applyView set last)
  // turned by the tilt; the frame is drawn again when it moved (or the server's light or
  // the renderer is new).
  frame(renderer, base) {
    const { light, changed } = this.tilt.light(base);
    if (this.trace) this.trace.push([performance.now(), ...this.tilt.drawn]);  // the bench's
    if (changed || renderer.light !== this.applied) {
      renderer.light = this.applied = light;
      renderer.damageIce();  // the iced tiles alone: a tilt costs what the ice covers
    }
  }

  connected(on) {
    this.awake.setConnected(on);
  }

  // A tap's first frost is on the screen.
  tapped() {
    if (this.buzzing) {
      try { this.win.navigator.vibrate(BUZZ_MS); } catch { /* refused */ }
    }
  }
}
