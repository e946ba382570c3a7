"""Dear ImGui's draw data drawn with moderngl (the panel beside the phone).

imgui-bundle's own OpenGL backends need PyOpenGL and a second GL state tracker; this is the
same few steps through the project's moderngl context and a shader pair in shaders/:
upload the textures ImGui asks for (its font atlas, under ImGui 1.92's
RendererHasTextures protocol), then each draw list's vertices and indices once, and one
scissored indexed draw per command.
"""

from __future__ import annotations

import ctypes

import moderngl
import numpy as np
from imgui_bundle import imgui

from app.gl.shaders import load_program

VERTEX_FORMAT = "2f 2f 4f1"  # ImDrawVert: pos, uv, colour as 4 normalized bytes
# Room for this many bytes in each buffer at first; a bigger frame grows them.
FIRST_BYTES = 1 << 18


class ImGuiRenderer:
    """Draws `imgui.get_draw_data()` into the current framebuffer; owns its GL objects."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.program = load_program(ctx, "imgui.vert", "imgui.frag")
        self.program["u_texture"].value = 0
        self.vbo = ctx.buffer(reserve=FIRST_BYTES, dynamic=True)
        self.ibo = ctx.buffer(reserve=FIRST_BYTES, dynamic=True)
        self.vao = ctx.vertex_array(self.program, [(self.vbo, VERTEX_FORMAT, "in_position", "in_uv",
                                                    "in_color")], index_buffer=self.ibo,
                                    index_element_size=imgui.INDEX_SIZE)
        self.textures: dict[int, moderngl.Texture] = {}
        io = imgui.get_io()
        io.backend_flags |= imgui.BackendFlags_.renderer_has_textures
        limit = ctx.info["GL_MAX_TEXTURE_SIZE"]
        platform = imgui.get_platform_io()
        platform.renderer_texture_max_width = platform.renderer_texture_max_height = limit

    def render(self, data: imgui.ImDrawData, fb_size: tuple[int, int]) -> None:
        """Every draw list of `data`; `fb_size` is the framebuffer's size in pixels."""
        self._update_textures()
        (dw, dh), (fw, fh) = data.display_size, fb_size
        if dw <= 0 or dh <= 0 or fw <= 0 or fh <= 0:
            return
        ctx = self.ctx
        ctx.viewport = (0, 0, fw, fh)
        ctx.enable_only(moderngl.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.program["u_display"].value = (dw, dh)
        try:
            for draw_list in data.cmd_lists:
                self._draw_list(draw_list, (fw / dw, fh / dh), fh)
        finally:
            ctx.scissor = None

    def _draw_list(self, draw_list, scale: tuple[float, float], fh: int) -> None:
        _upload(self.vbo, draw_list.vtx_buffer, imgui.VERTEX_SIZE)
        _upload(self.ibo, draw_list.idx_buffer, imgui.INDEX_SIZE)
        sx, sy = scale
        for cmd in draw_list.cmd_buffer:
            texture = self.textures.get(cmd.tex_ref.get_tex_id())
            x0, y0, x1, y1 = cmd.clip_rect
            if texture is None or x1 <= x0 or y1 <= y0:
                continue
            texture.use(0)
            # The clip rectangle is in window px, y down; the scissor in framebuffer px, y up.
            left, top = int(x0 * sx), int(y0 * sy)
            self.ctx.scissor = (left, fh - int(y1 * sy), int(x1 * sx) - left, int(y1 * sy) - top)
            self.vao.render(moderngl.TRIANGLES, vertices=cmd.elem_count, first=cmd.idx_offset)

    def _update_textures(self) -> None:
        for tex in imgui.get_platform_io().textures:
            status = tex.status
            if status in (imgui.ImTextureStatus.want_create, imgui.ImTextureStatus.want_updates):
                self._upload_texture(tex)
            elif status == imgui.ImTextureStatus.want_destroy:
                old = self.textures.pop(tex.tex_id, None)
                if old is not None:
                    old.release()
                tex.set_tex_id(0)
                tex.status = imgui.ImTextureStatus.destroyed

    def _upload_texture(self, tex) -> None:
        """The whole texture each time it changes: the font atlas is a few hundred KB and
        changes only when new glyphs or sizes are first drawn."""
        pixels = np.ascontiguousarray(tex.get_pixels_array()).reshape(tex.height, tex.width, 4)
        texture = self.textures.get(tex.tex_id)
        if texture is None or texture.size != (tex.width, tex.height):
            if texture is not None:
                texture.release()
            texture = self.ctx.texture((tex.width, tex.height), 4)
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            key = max(self.textures, default=0) + 1  # 0 is ImGui's "no texture"
            self.textures.pop(tex.tex_id, None)
            self.textures[key] = texture
            tex.set_tex_id(key)
        texture.write(pixels.tobytes())
        tex.status = imgui.ImTextureStatus.ok

    def release(self) -> None:
        for texture in self.textures.values():
            texture.release()
        for obj in (self.vao, self.vbo, self.ibo, self.program):
            obj.release()


def _upload(buffer: moderngl.Buffer, vector, item_size: int) -> None:
    """An ImVector's bytes into `buffer`, grown to twice their size when they do not fit."""
    size = vector.size() * item_size
    if size > buffer.size:
        buffer.orphan(2 * size)
    if size:
        buffer.write(ctypes.string_at(vector.data_address(), size))
