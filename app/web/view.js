// What the page draws with and what the server says it looks like: the renderer, made for
// the hello's grid, screen and looks; its light, material and toggles (each hello and state
// message); the backdrop behind the glass; and the GL context a phone may take away.

import { Renderer } from "./renderer.js";
import { Blitter } from "./blit.js";
import { rememberBackdrop } from "./offline.js";
import { backdropUrl } from "./photo.js";

export class View {
  // gl: the canvas's WebGL2 context; query: "?token=..." or ""; say(text): the status line.
  constructor(gl, query, say) {
    this.gl = gl;
    this.query = query;
    this.say = say;
    this.sources = null;   // the shader files' text (fetchShaders)
    this.renderer = null;  // made at a hello (none while the context is lost)
    this.blitter = null;
    this.backdrop = null;       // the backdrop asked for last
    this.shownBackdrop = null;  // the backdrop drawn
    this.serverLight = null;    // the light the server gives (the page's tilt turns it)
    this.warm = null;  // a look whose programs are made at the next frame
    this.lost = 0;     // times the GL context was lost
  }

  // The shaders are in: the blit's program made (again, when a lost context comes back).
  ready(sources) {
    this.sources = sources;
    this.blitter = new Blitter(this.gl, sources);
  }

  // A hello: a renderer for its grid and looks, or the one there emptied for the snapshot
  // that follows (the same grid: it holds the whole frost).
  hello(msg) {
    const r = this.renderer;
    if (!r || r.gridSize[0] !== msg.grid[0] || r.gridSize[1] !== msg.grid[1] || r.spacing !== msg.spacing
        || r.tile !== msg.tile || r.maxDepth !== msg.max_depth) {
      this.renderer = new Renderer(this.gl, this.sources, { width: msg.screen[0], height: msg.screen[1],
        grid: msg.grid, spacing: msg.spacing, tile: msg.tile, maxDepth: msg.max_depth, defines: msg.defines });
      this.warm = msg.look;  // (at the next frame: the snapshot is on its way)
    } else {
      r.reset();
    }
    this.backdrop = null;
  }

  // The light, the material and the toggles the server sends (names as the shader's uniforms
  // without u_, or as sim.look.material.Material's fields).
  apply(hello) {
    const r = this.renderer;
    for (const [key, value] of Object.entries(hello.uniforms || {})) {
      const name = key.replace(/^u_/, "");
      if (name === "light") r.light = value;
      else r.material[name] = value;
    }
    const view = hello.view || {};
    if ("light" in view) r.light = view.light;
    if ("features" in view) r.showFeatures = !!view.features;
    if ("bumps" in view) r.showBumps = !!view.bumps;
    this.serverLight = r.light;  // the page's tilt turns it (phone.js), for this page alone
    r.damageAll();
  }

  // The backdrop `name` fetched and drawn behind the glass; `clock` draws the lock screen's
  // minute over it (its PNG holds no clock).
  async loadBackdrop(name, clock, page) {
    this.backdrop = name;
    const r = await fetch(backdropUrl(name, this.query));
    if (!r.ok) return this.say(`backdrop ${name}: HTTP ${r.status}`);
    const image = await createImageBitmap(await r.blob(), { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    if (this.backdrop !== name) return;  // another came meanwhile
    this.renderer.setBackgroundImage(image);
    this.shownBackdrop = name;
    rememberBackdrop(name);
    clock.showOn(page);
  }

  // A phone may take the GPU away (in the background): start again when it gives it back
  // (`restored`), the server's snapshot refilling what the context held.
  watchContext(canvas, restored) {
    canvas.addEventListener("webglcontextlost", (event) => {
      event.preventDefault();
      this.renderer = null;
      this.lost += 1;
    });
    canvas.addEventListener("webglcontextrestored", () => {
      this.ready(this.sources);
      this.backdrop = this.shownBackdrop = null;
      restored();
    });
  }
}
