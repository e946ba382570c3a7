// The frost renderer of app/gl/renderer.py in WebGL2, drawing with the project's own shader
// files (fetched over HTTP, given the same header and #defines as app/gl/shaders.py).
// As there: a background pass, then, blended over it (premultiplied "over"), the ice pass
// on the screen tiles that hold ice; the height grid lives in a half-float RGB texture
// (height, slope x, slope y by central differences for the dirty rows only), the feature
// triangles are rasterized once, as they arrive, into a screen-sized ice texture with a
// depth test so the higher surface wins.

import { floatToHalf } from "./protocol.js";

export const HEADER = "#version 300 es\nprecision highp float;\n";
// Each look's compile-time variants (sim/look/material.py LOOK_DEFINES, FEATURE_DEFINES),
// until the server's hello says ({look: {ice: [...], feature: [...]}}: setDefines).
export const LOOK_DEFINES = { paper: [], glass: ["FILM", "SCATTER", "SPARKLE", "REFRACT"] };
export const FEATURE_DEFINES = { paper: [], glass: ["EDGE_AA"] };
export const SHADERS = ["fullscreen.vert", "background.frag", "tile.vert", "ice.frag",
  "feature.vert", "feature.frag", "blit.vert", "blit.frag"];
export const FEATURE_HEIGHT_SCALE = 16.0;
// The ice's material (sim.look.material.Material) and the light, until the server says.
export const MATERIAL = {
  ice_color: [0.93, 0.96, 1.0], ambient: 0.72, diffuse: 0.38, specular: 1.3, shininess: 12.0,
  opacity: 0.88, density: 0.45, relief: 1.6, refraction: 12.0,
};

// The shader files' text by name, fetched from `base` (e.g. "/shaders/") with `query`.
export async function fetchShaders(base = "shaders/", query = "") {
  const texts = await Promise.all(SHADERS.map(async (name) => {
    const r = await fetch(base + name + query);
    if (!r.ok) throw new Error(`shader ${name}: HTTP ${r.status}`);
    return r.text();
  }));
  return Object.fromEntries(SHADERS.map((name, i) => [name, texts[i]]));
}

export function shaderSource(sources, name, defines = []) {
  if (!(name in sources)) throw new Error(`shader ${name} not loaded`);
  return HEADER + defines.map((d) => `#define ${d}\n`).join("") + sources[name];
}

// A linked program with a setter that skips uniforms the program lacks (as moderngl's
// `name in prog`), typed by what the program declares.
export class Program {
  constructor(gl, sources, vert, frag, defines = []) {
    this.gl = gl;
    const p = gl.createProgram();
    for (const [type, name] of [[gl.VERTEX_SHADER, vert], [gl.FRAGMENT_SHADER, frag]]) {
      const s = gl.createShader(type);
      gl.shaderSource(s, shaderSource(sources, name, defines));
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) {
        throw new Error(`shader ${name} [${defines}]: ${gl.getShaderInfoLog(s)}`);
      }
      gl.attachShader(p, s);
    }
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
      throw new Error(`program ${vert}+${frag}: ${gl.getProgramInfoLog(p)}`);
    }
    this.program = p;
    this.uniforms = {};
    const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; i++) {
      const info = gl.getActiveUniform(p, i);
      this.uniforms[info.name] = { loc: gl.getUniformLocation(p, info.name), type: info.type };
    }
  }

  attrib(name) { return this.gl.getAttribLocation(this.program, name); }

  use(values) {
    const gl = this.gl;
    gl.useProgram(this.program);
    for (const [name, value] of Object.entries(values)) {
      const u = this.uniforms[name];
      if (!u) continue;
      switch (u.type) {
        case gl.FLOAT: gl.uniform1f(u.loc, value); break;
        case gl.FLOAT_VEC2: gl.uniform2fv(u.loc, value); break;
        case gl.FLOAT_VEC3: gl.uniform3fv(u.loc, value); break;
        case gl.FLOAT_VEC4: gl.uniform4fv(u.loc, value); break;
        case gl.INT: case gl.SAMPLER_2D: gl.uniform1i(u.loc, value); break;
        default: throw new Error(`uniform ${name}: type ${u.type} not handled`);
      }
    }
  }
}

export function defaultLight() {
  const v = [-0.35, -0.45, 0.82];
  const n = Math.hypot(...v);
  return v.map((c) => c / n);
}

export class Renderer {
  // gl: a WebGL2 context; sources: the shader files' text (fetchShaders); grid: [cols, rows]
  // of the height grid, spacing px apart; tile: the side of a screen tile of the ice pass
  // (px), maxDepth: the height (px) above which features share the nearest depth. All but
  // the screen's size are the hello's (grid, spacing, tile, max_depth): the desktop's own.
  constructor(gl, sources, { width = 760, height = 1280, grid, spacing, tile, maxDepth }) {
    if (!(tile > 0) || !(maxDepth > 0)) throw new Error(`a tile of ${tile} px, a depth of ${maxDepth} px: the hello's are needed`);
    this.gl = gl;
    this.tile = tile;
    this.maxDepth = maxDepth;
    this.sources = sources;
    this.size = [width, height];
    this.spacing = spacing;
    this.gridSize = grid;
    this.light = defaultLight();
    this.material = { ...MATERIAL };
    this.showFeatures = true;
    this.showBumps = true;
    this.look = "paper";
    this.heightScale = FEATURE_HEIGHT_SCALE;
    this.background = texture(gl, width, height, gl.RGB8, gl.NEAREST);
    this.grid = new Float32Array(grid[0] * grid[1]);  // mirror of the heights, row-major
    this.texels = new Uint16Array(grid[0] * grid[1] * 3);  // mirror of the height texture
    // The same bytes as half floats, where the browser has them (rounded to nearest even,
    // as floatToHalf: a third of the time for a whole grid)
    this.halves = typeof Float16Array === "function" ? new Float16Array(this.texels.buffer) : null;
    this.heights = texture(gl, grid[0], grid[1], gl.RGB16F, gl.LINEAR);
    this.features = new FeatureLayer(gl, sources, this.size, maxDepth);
    this.backgroundProg = new Program(gl, sources, "fullscreen.vert", "background.frag");
    this.emptyArray = gl.createVertexArray();
    this.iceProgs = {};
    this.defines = { ice: LOOK_DEFINES, feature: FEATURE_DEFINES };
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
    const iced = this.tiles.mask, d = this.damage;
    for (let i = 0; i < iced.length; i++) {
      if (iced[i]) {
        d.mask[i] = 1;
        d.any = true;
      }
    }
  }

  addDamage(x0, y0, x1, y1) {
    const [w, h] = this.size;
    x0 = Math.max(Math.floor(x0), 0);
    y0 = Math.max(Math.floor(y0), 0);
    x1 = Math.min(Math.ceil(x1), w);
    y1 = Math.min(Math.ceil(y1), h);
    if (x1 > x0 && y1 > y0) this.damage.mark(x0, y0, x1, y1);
  }

  // The view behind the glass from an image (ImageBitmap, top row first) of the screen's size.
  setBackgroundImage(image) {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.background);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, gl.RGB, gl.UNSIGNED_BYTE, image);
    this.damageAll();
  }

  // A rectangle of the view behind the glass (the lock screen's clock box): `image` at
  // (x, y) px, y down. Everything is drawn again (the glass bends the view from afar).
  setBackgroundRect(x, y, image) {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.background);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, x, y, gl.RGB, gl.UNSIGNED_BYTE, image);
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
      const [cols, rows] = this.gridSize;
      if (delta.grid[0] !== cols || delta.grid[1] !== rows) {
        throw new Error(`a delta for a ${delta.grid} grid, the page holds ${this.gridSize}`);
      }
      const touched = new Uint8Array(rows);
      let k = 0;
      for (const [start, count] of delta.runs) {
        for (let i = start; i < start + count; i++, k++) {
          const h = delta.heights[k];
          if (h > 0 && this.grid[i] === 0) this.tiles.markHeights(i % cols, Math.floor(i / cols));
          this.grid[i] = h;
        }
        // A vertex's height changes its neighbours' slopes, and bilinear filtering spreads
        // each texel one grid cell further: two cells each way (and a px).
        // A run that wraps onto later rows: its first row's end, the whole rows between
        // and its last row's start.
        const s = this.spacing, r0 = Math.floor(start / cols), r1 = Math.floor((start + count - 1) / cols);
        const c0 = start % cols, c1 = (start + count - 1) % cols;
        const cells = (ca, ra, cb, rb) => this.addDamage((ca - 2) * s - 1, (ra - 2) * s - 1, (cb + 2) * s + 1, (rb + 2) * s + 1);
        if (r1 === r0) cells(c0, r0, c1, r0);
        else {
          cells(c0, r0, cols - 1, r0);
          if (r1 > r0 + 1) cells(0, r0 + 1, cols - 1, r1 - 1);
          cells(0, r1, c1, r1);
        }
        for (let r = Math.floor(start / cols); r <= Math.floor((start + count - 1) / cols); r++) touched[r] = 1;
      }
      // Each block of touched rows, with one more each side (whose slopes they change).
      for (let r = 0; r < rows; r++) {
        if (!touched[r]) continue;
        let end = r;
        while (end + 1 < rows && touched[end + 1]) end++;
        this.uploadRows(r - 1, end + 2);
        r = end;
      }
    }
    // (each triangle's box is damaged, unless everything is already: a snapshot's)
    this.tiles.markTriangles(delta.features, this.damage.all ? null
      : (x0, y0, x1, y1) => this.addDamage(x0 - 1, y0 - 1, x1 + 1, y1 + 1));
    this.features.append(delta.features);
  }

  // Height and slope (per px; numpy.gradient's central differences, one-sided at the
  // grid's edges) of grid rows lo..hi-1 into the texture.
  uploadRows(lo, hi) {
    const gl = this.gl;
    const [cols, rows] = this.gridSize;
    lo = Math.max(lo, 0);
    hi = Math.min(hi, rows);
    if (hi <= lo) return;
    const g = this.grid, h = this.spacing;
    const at = (r, c) => g[r * cols + c];
    const texels = this.texels, halves = this.halves;
    const fr = Math.fround;
    for (let r = lo; r < hi; r++) {
      const [ra, rb, dy] = r === 0 ? [0, 1, h] : r === rows - 1 ? [r - 1, r, h] : [r - 1, r + 1, 2 * h];
      for (let c = 0; c < cols; c++) {
        const [ca, cb, dx] = c === 0 ? [0, 1, h] : c === cols - 1 ? [c - 1, c, h] : [c - 1, c + 1, 2 * h];
        const o = (r * cols + c) * 3;
        // (each a float32 first, as the desktop's numpy: then one rounding to a half)
        const v = at(r, c), sx = fr(fr(at(r, cb) - at(r, ca)) / dx), sy = fr(fr(at(rb, c) - at(ra, c)) / dy);
        if (halves) {
          halves[o] = v;
          halves[o + 1] = sx;
          halves[o + 2] = sy;
        } else {
          texels[o] = floatToHalf(v);
          texels[o + 1] = floatToHalf(sx);
          texels[o + 2] = floatToHalf(sy);
        }
      }
    }
    gl.bindTexture(gl.TEXTURE_2D, this.heights);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, lo, cols, hi - lo, gl.RGB, gl.HALF_FLOAT,
      texels.subarray(lo * cols * 3, hi * cols * 3));
  }

  // Clear glass: no heights, no features.
  reset() {
    // (a flat grid: every height and slope is 0, no rows to work out)
    this.grid.fill(0);
    this.texels.fill(0);
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.heights);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, ...this.gridSize, gl.RGB, gl.HALF_FLOAT, this.texels);
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
    bindTexture(gl, 0, this.background);
    if (tiles) {
      this.backgroundTiles ||= new Program(gl, this.sources, "tile.vert", "background.frag");
      this.backgroundTiles.use({ u_background: 0, u_screen: this.size, u_tile: this.tile });
      this.tiles.renderSome(this.backgroundTiles, tiles, false);
    } else {
      this.backgroundProg.use({ u_background: 0, u_screen: this.size });
      gl.bindVertexArray(this.emptyArray);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
    if (!(this.showBumps || this.showFeatures)) return;
    bindTexture(gl, 1, this.heights);
    bindTexture(gl, 2, this.features.texture);
    const prog = this.iceProgram(this.look);
    prog.use(this.iceUniforms());
    // Premultiplied "over": frame = ice + (1 - alpha) * background.
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    if (tiles) this.tiles.renderSome(prog, tiles, true);
    else this.tiles.render(prog);
    gl.disable(gl.BLEND);
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
    bindTexture(gl, 0, this.background);
    this.backgroundProg.use({ u_background: 0, u_screen: this.size });
    gl.bindVertexArray(this.emptyArray);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const one = new Uint8Array(this.tiles.mask.length);
    one[0] = 1;
    this.backgroundTiles ||= new Program(gl, this.sources, "tile.vert", "background.frag");
    this.backgroundTiles.use({ u_background: 0, u_screen: this.size, u_tile: this.tile });
    this.tiles.renderSome(this.backgroundTiles, one, false);
    bindTexture(gl, 1, this.heights);
    bindTexture(gl, 2, this.features.texture);
    const ice = this.iceProgram(look);
    ice.use(this.iceUniforms());
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    this.tiles.renderSome(ice, one, false);
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

  // The looks' #defines as the server's hello gives them ({look: {ice, feature}}).
  setDefines(defines) {
    const ice = {}, feature = {};
    for (const [look, d] of Object.entries(defines)) {
      ice[look] = d.ice;
      feature[look] = d.feature;
    }
    this.defines = { ice, feature };
    this.features.defines = feature;
    this.iceProgs = {};
    this.features.progs = {};
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
    const gl = this.gl;
    const [w, h] = this.size;
    const raw = new Uint8Array(w * h * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo);
    gl.pixelStorei(gl.PACK_ALIGNMENT, 1);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, raw);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const out = new Uint8Array(raw.length);
    for (let y = 0; y < h; y++) out.set(raw.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    return out;
  }
}

// The sharp features: queued as they arrive, rasterized once into a persistent
// screen-sized ice texture (normal xy, height, coverage), the higher surface winning.
export class FeatureLayer {
  // maxDepth: px; features higher than this share the nearest depth
  constructor(gl, sources, size, maxDepth) {
    this.gl = gl;
    this.sources = sources;
    this.size = size;
    this.maxDepth = maxDepth;
    this.texture = texture(gl, size[0], size[1], gl.RGBA8, gl.LINEAR);
    const depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, ...size);
    this.fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.texture, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.pending = [];  // Float32Arrays of vertices (x, y, z, nx, ny, nz) not yet drawn
    this.heightScale = FEATURE_HEIGHT_SCALE;
    this.look = "paper";
    this.progs = {};  // per look
    this.defines = FEATURE_DEFINES;
    this.vbo = gl.createBuffer();
  }

  // No features, nothing queued.
  clear() {
    this.clearBox(0, 0, ...this.size);
    this.pending = [];
  }

  clearBox(x, y, w, h) {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fbo);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(x, y, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clearDepth(1.0);
    gl.depthMask(true);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.disable(gl.SCISSOR_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  // Clear the features inside a px box (y down), after drawing what is queued (older than
  // the wipe); the delta then re-sends the survivors.
  wipe(box) {
    this.drawQueued();
    const [W, H] = this.size;
    const x0 = Math.max(Math.floor(box[0]) - 1, 0), y0 = Math.max(Math.floor(box[1]) - 1, 0);
    const x1 = Math.min(Math.ceil(box[2]) + 1, W), y1 = Math.min(Math.ceil(box[3]) + 1, H);
    if (x1 > x0 && y1 > y0) this.clearBox(x0, H - y1, x1 - x0, y1 - y0);  // GL rows count up
  }

  append(verts) {
    if (verts.length) this.pending.push(verts);
  }

  // Rasterize the queued triangles into the texture.
  drawQueued() {
    if (!this.pending.length) return;
    const gl = this.gl;
    const count = this.pending.reduce((n, v) => n + v.length, 0);
    const all = new Float32Array(count);
    let o = 0;
    for (const v of this.pending) { all.set(v, o); o += v.length; }
    this.pending = [];
    const { prog, array } = this.program(this.look);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.vbo);
    gl.bufferData(gl.ARRAY_BUFFER, all, gl.STREAM_DRAW);
    prog.use({ u_screen: this.size, u_max_depth: this.maxDepth, u_height_scale: this.heightScale });
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fbo);
    gl.viewport(0, 0, ...this.size);
    gl.disable(gl.BLEND);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.bindVertexArray(array);
    gl.drawArrays(gl.TRIANGLES, 0, count / 6);
    gl.bindVertexArray(null);
    gl.disable(gl.DEPTH_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  // Its program for `look` run once (Renderer.warm): a triangle drawn, then wiped.
  warm(look) {
    const saved = [this.look, this.pending];
    this.look = look;
    this.pending = [new Float32Array([0, 0, 1, 0, 0, 1, 4, 0, 1, 0, 0, 1, 0, 4, 1, 0, 0, 1])];  // (1 px high: it passes the depth test)
    this.drawQueued();
    [this.look, this.pending] = saved;
    this.clearBox(0, 0, ...this.size);
  }

  program(look) {
    if (!(look in this.progs)) {
      const gl = this.gl;
      const prog = new Program(gl, this.sources, "feature.vert", "feature.frag", this.defines[look]);
      const array = gl.createVertexArray();
      gl.bindVertexArray(array);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.vbo);
      for (const [name, offset] of [["in_position", 0], ["in_normal", 12]]) {
        const loc = prog.attrib(name);
        gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 24, offset);
      }
      gl.bindVertexArray(null);
      this.progs[look] = { prog, array };
    }
    return this.progs[look];
  }
}

// The tiles (`tile` px a side) of the frame that changed since it was drawn: a mask, or `all`.
export class TileDamage {
  constructor(size, tile) {
    this.size = size;
    this.tile = tile;
    this.cols = Math.ceil(size[0] / tile);
    this.rows = Math.ceil(size[1] / tile);
    this.mask = new Uint8Array(this.cols * this.rows);
    this.any = false;
    this.all = false;
  }

  // The tiles under a px box (y down, x1 and y1 excluded; clipped to the frame already).
  mark(x0, y0, x1, y1) {
    const t = this.tile;
    const tx1 = Math.ceil(x1 / t), ty1 = Math.ceil(y1 / t);
    for (let ty = Math.floor(y0 / t); ty < ty1; ty++) {
      this.mask.fill(1, ty * this.cols + Math.floor(x0 / t), ty * this.cols + tx1);
    }
    this.any = true;
  }

  // What to draw: null (nothing), {tiles: null} (everything) or {tiles: the mask}, with
  // the box ([x0, y0, x1, y1] px, y down) they span. With `view` (a px box, y down), only
  // the tiles it touches are taken: the rest stay, for when the screen shows them.
  take(view = null) {
    const [w, h] = this.size, t = this.tile;
    const whole = !view || (view[0] <= 0 && view[1] <= 0 && view[2] >= w && view[3] >= h);
    if (this.all && whole) {
      this.all = this.any = false;
      this.mask.fill(0);
      return { tiles: null, box: [0, 0, w, h] };
    }
    if (this.all) {
      this.mask.fill(1);
      this.all = false;
      this.any = true;
    }
    if (!this.any) return null;
    let tiles = this.mask;
    if (whole) {
      this.mask = new Uint8Array(tiles.length);
      this.any = false;
    } else {
      const tx0 = Math.floor(view[0] / t), ty0 = Math.floor(view[1] / t);
      const tx1 = Math.ceil(view[2] / t), ty1 = Math.ceil(view[3] / t);
      tiles = new Uint8Array(tiles.length);
      this.any = false;
      for (let i = 0; i < tiles.length; i++) {
        if (!this.mask[i]) continue;
        const c = i % this.cols, r = Math.floor(i / this.cols);
        if (c >= tx0 && c < tx1 && r >= ty0 && r < ty1) {
          tiles[i] = 1;
          this.mask[i] = 0;
        } else {
          this.any = true;
        }
      }
    }
    const box = [w, h, 0, 0];
    for (let i = 0; i < tiles.length; i++) {
      if (!tiles[i]) continue;
      const x = (i % this.cols) * t, y = Math.floor(i / this.cols) * t;
      box[0] = Math.min(box[0], x);
      box[1] = Math.min(box[1], y);
      box[2] = Math.max(box[2], Math.min(x + t, w));
      box[3] = Math.max(box[3], Math.min(y + t, h));
    }
    return box[2] > box[0] ? { tiles, box } : null;
  }
}

// The screen tiles (`tile` px a side) that hold ice, drawn as instanced quads; only added
// until a reset.
export class TileSet {
  constructor(gl, size, spacing, tile) {
    this.gl = gl;
    this.spacing = spacing;
    this.tile = tile;
    this.rows = Math.ceil(size[1] / tile);
    this.cols = Math.ceil(size[0] / tile);
    this.mask = new Uint8Array(this.rows * this.cols);
    this.corners = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, this.corners);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([0, 0, 1, 0, 0, 1, 1, 1]), gl.STATIC_DRAW);
    this.instances = gl.createBuffer();
    this.arrays = new Map();  // instance buffer -> program -> vertex array
    this.count = 0;
    this.dirty = false;
  }

  clear() {
    this.mask.fill(0);
    this.count = 0;
    this.dirty = false;
  }

  fill() {
    this.mask.fill(1);
    this.dirty = true;
  }

  // Mark the tiles that see a newly iced grid vertex (column c, row r): bilinear
  // filtering spreads a vertex one grid cell each way.
  markHeights(c, r) {
    const s = this.spacing;
    const x = c * s, y = r * s;
    this.markBox(x - s, y - s, x + s, y + s);
  }

  // Mark the tiles under each triangle's bounding box (vertices of 6 floats, 3 a triangle).
  // (`each(x0, y0, x1, y1)` is told every box too.)
  markTriangles(verts, each = null) {
    for (let t = 0; t + 18 <= verts.length; t += 18) {
      const ax = verts[t], bx = verts[t + 6], cx = verts[t + 12];
      const ay = verts[t + 1], by = verts[t + 7], cy = verts[t + 13];
      const x0 = Math.min(ax, bx, cx), y0 = Math.min(ay, by, cy);
      const x1 = Math.max(ax, bx, cx), y1 = Math.max(ay, by, cy);
      this.markBox(x0, y0, x1, y1);
      if (each) each(x0, y0, x1, y1);
    }
  }

  markBox(x0, y0, x1, y1) {
    const t = this.tile, cols = this.cols, rows = this.rows;
    const tx0 = Math.min(Math.max(Math.floor(x0 / t), 0), cols - 1), tx1 = Math.min(Math.max(Math.floor(x1 / t), 0), cols - 1);
    const ty0 = Math.min(Math.max(Math.floor(y0 / t), 0), rows - 1), ty1 = Math.min(Math.max(Math.floor(y1 / t), 0), rows - 1);
    for (let ty = ty0; ty <= ty1; ty++) {
      for (let tx = tx0; tx <= tx1; tx++) {
        const i = ty * this.cols + tx;
        if (!this.mask[i]) { this.mask[i] = 1; this.dirty = true; }
      }
    }
  }

  render(prog) {
    const gl = this.gl;
    if (this.dirty) this.upload();
    if (!this.count) return;
    gl.bindVertexArray(this.array(prog));
    gl.drawArraysInstanced(gl.TRIANGLE_STRIP, 0, 4, this.count);
    gl.bindVertexArray(null);
  }

  // The tiles of `mask` (a TileDamage's), with `iced`: those of them that hold ice.
  renderSome(prog, mask, iced) {
    const gl = this.gl;
    const tiles = [];
    for (let i = 0; i < mask.length; i++) {
      if (mask[i] && (!iced || this.mask[i])) tiles.push(i % this.cols, Math.floor(i / this.cols));
    }
    if (!tiles.length) return;
    this.some ||= gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, this.some);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(tiles), gl.STREAM_DRAW);
    gl.bindVertexArray(this.array(prog, this.some));
    gl.drawArraysInstanced(gl.TRIANGLE_STRIP, 0, 4, tiles.length / 2);
    gl.bindVertexArray(null);
  }

  // The vertex array of `prog` over the tiles in `instances` (default: this set's).
  array(prog, instances = this.instances) {
    if (!this.arrays.has(instances)) this.arrays.set(instances, new Map());
    const arrays = this.arrays.get(instances);
    if (!arrays.has(prog)) {
      const gl = this.gl;
      const array = gl.createVertexArray();
      gl.bindVertexArray(array);
      const corner = prog.attrib("in_corner"), tile = prog.attrib("in_tile");
      gl.bindBuffer(gl.ARRAY_BUFFER, this.corners);
      gl.enableVertexAttribArray(corner);
      gl.vertexAttribPointer(corner, 2, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, instances);
      gl.enableVertexAttribArray(tile);
      gl.vertexAttribPointer(tile, 2, gl.FLOAT, false, 0, 0);
      gl.vertexAttribDivisor(tile, 1);
      gl.bindVertexArray(null);
      arrays.set(prog, array);
    }
    return arrays.get(prog);
  }

  upload() {
    const gl = this.gl;
    const tiles = [];
    for (let i = 0; i < this.mask.length; i++) {
      if (this.mask[i]) tiles.push(i % this.cols, Math.floor(i / this.cols));
    }
    gl.bindBuffer(gl.ARRAY_BUFFER, this.instances);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(tiles), gl.DYNAMIC_DRAW);
    this.count = tiles.length / 2;
    this.dirty = false;
  }
}

function texture(gl, w, h, format, filter) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texStorage2D(gl.TEXTURE_2D, 1, format, w, h);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  return tex;
}

function bindTexture(gl, unit, tex) {
  gl.activeTexture(gl.TEXTURE0 + unit);
  gl.bindTexture(gl.TEXTURE_2D, tex);
}
