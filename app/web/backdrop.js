// The view behind the glass: its texture (the screen's size), given whole or a rectangle
// at a time, and the background pass that draws it into the frame.

import { Program, bindTexture, texture } from "./programs.js";

export class Backdrop {
  // size: the screen's [width, height] px; tile: the side of a screen tile (px)
  constructor(gl, sources, size, tile) {
    this.gl = gl;
    this.sources = sources;
    this.size = size;
    this.tile = tile;
    this.texture = texture(gl, size[0], size[1], gl.RGB8, gl.NEAREST);
    this.whole = new Program(gl, sources, "fullscreen.vert", "background.frag");
    this.tiled = null;  // its program on some tiles, made when first drawn
    this.emptyArray = gl.createVertexArray();
  }

  // `image` (ImageBitmap or pixels, top row first) at (x, y) px, y down: the whole view
  // (the screen's size, at 0, 0) or a rectangle of it (the lock screen's clock box).
  put(x, y, image) {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, x, y, gl.RGB, gl.UNSIGNED_BYTE, image);
  }

  // The background pass into the framebuffer bound: the whole frame, or with `tiles` (a
  // mask of `tileSet`'s tiles) those tiles alone.
  draw(tileSet, tiles = null) {
    const gl = this.gl;
    bindTexture(gl, 0, this.texture);
    if (tiles) {
      this.tiled ||= new Program(gl, this.sources, "tile.vert", "background.frag");
      this.tiled.use({ u_background: 0, u_screen: this.size, u_tile: this.tile });
      tileSet.renderSome(this.tiled, tiles, false);
    } else {
      this.whole.use({ u_background: 0, u_screen: this.size });
      gl.bindVertexArray(this.emptyArray);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
  }
}
