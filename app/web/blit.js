// The pane's texture drawn into the canvas: where the pane lies on it, black around it, or
// only the px that changed.

import { Program } from "./programs.js";

// The pane's texture drawn into the canvas's rect (canvas px, y down), black around it.
export class Blitter {
  constructor(gl, sources) {
    this.gl = gl;
    this.prog = new Program(gl, sources, "blit.vert", "blit.frag");
    this.array = gl.createVertexArray();
  }

  // `damage`: only the pane px [x0, y0, x1, y1] (y down) changed, else all of it (and the
  // black around it) is drawn.
  draw(texture, rect, damage = null) {
    const gl = this.gl;
    const H = gl.drawingBufferHeight;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    if (damage) {
      // Its canvas px, and two more each way (linear filtering reaches a texel further).
      // Within the pane's rect and the canvas (a covering pane reaches past it).
      const x0 = Math.max(Math.floor(rect.x + damage[0] * rect.scale) - 2, rect.x, 0);
      const y0 = Math.max(Math.floor(rect.y + damage[1] * rect.scale) - 2, rect.y, 0);
      const x1 = Math.min(Math.ceil(rect.x + damage[2] * rect.scale) + 2, rect.x + rect.w, gl.drawingBufferWidth);
      const y1 = Math.min(Math.ceil(rect.y + damage[3] * rect.scale) + 2, rect.y + rect.h, H);
      if (x1 <= x0 || y1 <= y0) return;  // changed where the screen does not show
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(x0, H - y1, x1 - x0, y1 - y0);
    } else {
      gl.viewport(0, 0, gl.drawingBufferWidth, H);
      gl.clearColor(0, 0, 0, 1);
      gl.clear(gl.COLOR_BUFFER_BIT);
    }
    gl.viewport(rect.x, H - rect.y - rect.h, rect.w, rect.h);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    // One canvas px per pane px: nearest, so the page shows the frame exactly.
    const filter = rect.scale === 1 ? gl.NEAREST : gl.LINEAR;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
    this.prog.use({ u_texture: 0, u_rect: [-1, -1, 1, 1] });
    gl.bindVertexArray(this.array);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    gl.bindVertexArray(null);
    gl.disable(gl.SCISSOR_TEST);
  }
}
