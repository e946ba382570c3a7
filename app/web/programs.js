// The page's shader programs: the project's own shader files, fetched over HTTP, given the
// same header and #defines as app/gl/shaders.py, linked; and the textures they read.

export const HEADER = "#version 300 es\nprecision highp float;\n";
export const SHADERS = ["fullscreen.vert", "background.frag", "tile.vert", "ice.frag",
  "feature.vert", "feature.frag", "blit.vert", "blit.frag"];
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

export function texture(gl, w, h, format, filter) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texStorage2D(gl.TEXTURE_2D, 1, format, w, h);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  return tex;
}

export function bindTexture(gl, unit, tex) {
  gl.activeTexture(gl.TEXTURE0 + unit);
  gl.bindTexture(gl.TEXTURE_2D, tex);
}
