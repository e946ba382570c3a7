// The screen tiles (`tile` px a side) of the ice pass: those that hold ice (drawn as
// instanced quads) and those of the frame that changed since it was drawn.

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

  // The tiles under a px box (y down), rounded out to whole px and clipped to the frame.
  markBox(x0, y0, x1, y1) {
    const [w, h] = this.size;
    x0 = Math.max(Math.floor(x0), 0);
    y0 = Math.max(Math.floor(y0), 0);
    x1 = Math.min(Math.ceil(x1), w);
    y1 = Math.min(Math.ceil(y1), h);
    if (x1 > x0 && y1 > y0) this.mark(x0, y0, x1, y1);
  }

  // The tiles of `tiles` (a mask of the same tiles: a TileSet's, those that hold ice).
  markTiles(tiles) {
    for (let i = 0; i < tiles.length; i++) {
      if (tiles[i]) {
        this.mask[i] = 1;
        this.any = true;
      }
    }
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
