// The frost renderer of app/gl/renderer.py in WebGL2, drawing with the project's own shader
// files (programs.js). As there: a background pass (backdrop.js), then, blended over it
// (premultiplied "over"), the ice pass on the screen tiles that hold ice (tiles.js), from the
// height grid (heights.js) and the feature triangles (features.js). Every setting the
// desktop has (the tile, the features' depth, each look's #defines, the material and the
// light) is the server's hello's: the page keeps no copy of them.

import { Backdrop } from "./backdrop.js";
import { FEATURE_HEIGHT_SCALE, FeatureLayer } from "./features.js";
import { HeightGrid } from "./heights.js";
import { Program, bindTexture, texture } from "./programs.js";
import { TileDamage, TileSet } from "./tiles.js";

export { Program, fetchShaders } from "./programs.js";

export class Renderer {
  // gl: a WebGL2 context; sources: the shader files' text (fetchShaders); grid: [cols, rows]
  // of the height grid, spacing px apart; tile: the side of a screen tile of the ice pass
  // (px), maxDepth: the height (px) above which features share the nearest depth; defines:
  // each look's #defines ({look: {ice, feature}}). All but the screen's size are the
  // hello's (grid, spacing, tile, max_depth, defines): the desktop's own. The material and
  // the light are the hello's too (main.js sets them, as each hello and state message says).
  constructor(gl, sources, { width = 760, height = 1280, grid, spacing, tile, maxDepth, defines }) {
    if (!(tile > 0) || !(maxDepth > 0)) throw new Error(`a tile of ${tile} px, a depth of ${maxDepth} px: the hello's are needed`);
    if (!defines) throw new Error("no looks' #defines: the hello's are needed");
    this.gl = gl;
    this.tile = tile;
    this.maxDepth = maxDepth;
    this.sources = sources;
    this.size = [width, height];
    this.spacing = spacing;
    this.gridSize = grid;
    this.light = null;  // [x, y, z] and the material's uniforms (names without u_): the hello's
    this.material = {};
    this.showFeatures = true;
    this.showBumps = true;
    this.look = "paper";
    this.heightScale = FEATURE_HEIGHT_SCALE;
    this.defines = byPass(defines);
    this.iceProgs = {};  // per look
    this.backdrop = new Backdrop(gl, sources, this.size, tile);
    this.heights = new HeightGrid(gl, grid, spacing);
    this.features = new FeatureLayer(gl, sources, this.size, maxDepth, this.defines.feature);
    this.tiles = new TileSet(gl, this.size, spacing, tile);
    // The frame: RGBA8 of the screen's size, as the desktop's offscreen framebuffer.
    this.frame = texture(gl, width, height, gl.RGBA8, gl.LINEAR);
    // The tiles of the frame to draw again: only what changed is drawn (the frame texture
    // keeps the rest), the same pixels a whole frame gives.
    this.damage = new TileDamage(this.size, tile);
    this.frameFbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.frame, 0);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.reset();
  }

  // Draw everything again next frame (a new backdrop, look, light or material).
  damageAll() {
    this.damage.all = true;
  }

  // Draw again next frame the tiles that hold ice alone (a page's own new light: clear
  // glass is the backdrop's whatever the light).
  damageIce() {
    this.damage.markTiles(this.tiles.mask);
  }

  // Draw again next frame the tiles under a px box (y down; clipped to the frame here).
  addDamage(x0, y0, x1, y1) {
    this.damage.markBox(x0, y0, x1, y1);
  }

  // The view behind the glass from an image (ImageBitmap, top row first) of the screen's size.
  setBackgroundImage(image) {
    this.backdrop.put(0, 0, image);
    this.damageAll();
  }

  // A rectangle of the view behind the glass (the lock screen's clock box): `image` at
  // (x, y) px, y down. Everything is drawn again (the glass bends the view from afar).
  setBackgroundRect(x, y, image) {
    this.backdrop.put(x, y, image);
    this.damageAll();
  }

  // Upload a tick's changes (a decoded message): its dirty height rows and new features.
  apply(delta) {
    if (delta.reset) this.reset();
    if (delta.look !== this.look || delta.heightScale !== this.heightScale) this.damageAll();
    this.look = delta.look;
    this.heightScale = delta.heightScale;
    this.features.heightScale = delta.heightScale;
    this.features.look = delta.look;
    if (delta.clearBox) {
      const b = delta.clearBox;
      this.features.wipe(b);
      this.addDamage(b[0] - 2, b[1] - 2, b[2] + 2, b[3] + 2);  // as wiped, and a px more
    }
    if (delta.runs.length) {
      this.heights.apply(delta, (c, r) => this.tiles.markHeights(c, r),
        (x0, y0, x1, y1) => this.addDamage(x0, y0, x1, y1));
    }
    // (each triangle's box is damaged, unless everything is already: a snapshot's)
    this.tiles.markTriangles(delta.features, this.damage.all ? null
      : (x0, y0, x1, y1) => this.addDamage(x0 - 1, y0 - 1, x1 + 1, y1 + 1));
    this.features.append(delta.features);
  }

  // Clear glass: no heights, no features.
  reset() {
    this.heights.clear();
    this.features.clear();
    this.tiles.clear();
    this.damageAll();
  }

  // Draw what changed since the last frame into the frame texture (`all`: everything);
  // the box drawn ([x0, y0, x1, y1] px, y down), or null if nothing changed. With `view`
  // (a px box, y down: what the screen shows of the pane), what changed outside it waits
  // until the screen shows it (a phone's covering pane crops a fifth of it, in landscape
  // three quarters). Only the changed tiles are drawn (each pass one instanced draw: SwiftShader pays for every draw
  // call and every quad, so neither a scissored pass per place nor the pane's every tile).
  render(all = false, view = null) {
    const gl = this.gl;
    if (all) this.damageAll();
    this.features.drawQueued();
    const d = this.damage.take(view);
    if (!d) return null;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo);
    gl.viewport(0, 0, ...this.size);
    if (d.tiles) this.drawPasses(d.tiles);
    else this.drawPasses();
    return d.box;
  }

  // The background pass, then the ice pass blended over it, as the desktop draws a frame;
  // on `tiles` alone (a mask of the TileSet's tiles) if given.
  drawPasses(tiles = null) {
    const gl = this.gl;
    gl.disable(gl.DEPTH_TEST);
    gl.disable(gl.BLEND);
    this.backdrop.draw(this.tiles, tiles);
    if (!(this.showBumps || this.showFeatures)) return;
    const prog = this.useIce(this.look);
    if (tiles) this.tiles.renderSome(prog, tiles, true);
    else this.tiles.render(prog);
    gl.disable(gl.BLEND);
  }

  // The ice pass's program for `look`, used, its textures bound and the blending set:
  // premultiplied "over" (frame = ice + (1 - alpha) * background).
  useIce(look) {
    const gl = this.gl;
    bindTexture(gl, 1, this.heights.texture);
    bindTexture(gl, 2, this.features.texture);
    const prog = this.iceProgram(look);
    prog.use(this.iceUniforms());
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    return prog;
  }

  // Each pass's program for `look` run once, on a px: a GPU that builds a program's code at
  // its first draw (SwiftShader does: tens of ms for each, the ice's the most) builds it
  // now, while the snapshot is on its way, not in the frame that shows it. The feature
  // drawn is wiped; the frame's px is drawn again with the rest (a new renderer's reset
  // damaged everything, and nothing is drawn until the snapshot is in).
  warm(look) {
    const gl = this.gl;
    this.features.warm(look);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo);
    gl.viewport(0, 0, ...this.size);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(0, 0, 1, 1);
    gl.disable(gl.BLEND);
    this.backdrop.draw(this.tiles);
    const one = new Uint8Array(this.tiles.mask.length);
    one[0] = 1;
    this.backdrop.draw(this.tiles, one);
    this.tiles.renderSome(this.useIce(look), one, false);
    gl.disable(gl.BLEND);
    gl.disable(gl.SCISSOR_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  iceProgram(look) {
    if (!(look in this.iceProgs)) {
      this.iceProgs[look] = new Program(this.gl, this.sources, "tile.vert", "ice.frag", this.defines.ice[look]);
    }
    return this.iceProgs[look];
  }

  iceUniforms() {
    const m = this.material;
    const n = Math.hypot(...this.light);
    return {
      u_heights: 1, u_ice: 2, u_tile: this.tile, u_screen: this.size, u_grid_size: this.gridSize,
      u_spacing: this.spacing, u_height_scale: this.heightScale, u_background: 0,
      u_refraction: m.refraction, u_show_bumps: this.showBumps ? 1 : 0,
      u_show_features: this.showFeatures ? 1 : 0, u_light: this.light.map((c) => c / n),
      u_ice_color: m.ice_color, u_ambient: m.ambient, u_diffuse: m.diffuse,
      u_specular: m.specular, u_shininess: m.shininess, u_opacity: m.opacity,
      u_density: m.density, u_relief: m.relief,
    };
  }

  // The frame's pixels, W*H*4 RGBA, top row first.
  readFrame() {
    return readTopFirst(this.gl, this.frameFbo, this.size);
  }
}

// Each look's #defines by pass ({ice: {look: [...]}, feature: {look: [...]}}) from the
// hello's by look ({look: {ice, feature}}).
function byPass(defines) {
  const ice = {}, feature = {};
  for (const [look, d] of Object.entries(defines)) {
    ice[look] = d.ice;
    feature[look] = d.feature;
  }
  return { ice, feature };
}

// The pixels of framebuffer `fbo` ([w, h]: RGBA8), W*H*4 RGBA, top row first (GL's rows
// count up).
function readTopFirst(gl, fbo, [w, h]) {
  const raw = new Uint8Array(w * h * 4);
  gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
  gl.pixelStorei(gl.PACK_ALIGNMENT, 1);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, raw);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  const out = new Uint8Array(raw.length);
  for (let y = 0; y < h; y++) out.set(raw.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
  return out;
}
