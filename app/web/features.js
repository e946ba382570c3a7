// The ice pass's sharp features (app/gl/renderer.py's FeatureLayer): feature triangles
// rasterized once, as they arrive, into a screen-sized ice texture with a depth test so the
// higher surface wins.

import { Program, texture } from "./programs.js";

// The features' height scale until a delta says (each delta carries its own).
export const FEATURE_HEIGHT_SCALE = 16.0;

// The sharp features: queued as they arrive, rasterized once into a persistent
// screen-sized ice texture (normal xy, height, coverage), the higher surface winning.
export class FeatureLayer {
  // maxDepth: px; features higher than this share the nearest depth; defines: each look's
  // #defines of the feature pass (the hello's)
  constructor(gl, sources, size, maxDepth, defines) {
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
    this.defines = defines;
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
