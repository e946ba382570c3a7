"""Heads-up display: text drawn with Pillow's bundled font into RGBA textures.

A panel re-renders its texture only when its text changes; drawing is one blended quad.
Sizes are for a screen of content scale 1; the HUD draws them times its `scale` (the
window's content scale: 2 on a Retina Mac, 1.5 on a Windows screen at 150 %), so its text
stays legible at any.
"""

from __future__ import annotations

from typing import cast

import moderngl
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from app.gl.shaders import load_program

FONT_SIZE = 14
LINE_GAP = 3
PADDING = 6
COLUMN_GAP = 12
TEXT_RGBA = (235, 245, 255, 255)
BOX_RGBA = (0, 0, 0, 150)


def text_image(lines: list[str], font, scale: float = 1.0) -> Image.Image:
    """The lines in white on a translucent box, as a top-down RGBA image (`font` at
    FONT_SIZE x `scale`, gaps times `scale`). Tabs split a line into columns, aligned
    across lines (the font is proportional)."""
    pad = round(PADDING * scale)
    ascent, descent = font.getmetrics()
    line_h = ascent + descent + round(LINE_GAP * scale)
    rows = [line.split("\t") for line in lines]
    starts = _column_starts(rows, font, round(COLUMN_GAP * scale))
    width = max((starts[len(r) - 1] + int(font.getlength(r[-1])) for r in rows), default=0)
    size = (width + 2 * pad, line_h * len(lines) + 2 * pad)
    image = Image.new("RGBA", size, BOX_RGBA)
    draw = ImageDraw.Draw(image)
    for i, row in enumerate(rows):
        for start, cell in zip(starts, row, strict=False):
            draw.text((pad + start, pad + i * line_h), cell, font=font, fill=TEXT_RGBA)
    return image


def _column_starts(rows: list[list[str]], font, gap: int) -> list[int]:
    """x of each column: after the widest cell of the column before, plus `gap`."""
    columns = max((len(r) for r in rows), default=1)
    starts = [0]
    for c in range(columns - 1):
        widest = max((int(font.getlength(r[c])) for r in rows if len(r) > c + 1), default=0)
        starts.append(starts[-1] + widest + gap)
    return starts


class Panel:
    """One block of text at a fixed spot of the window, kept in its own texture."""

    def __init__(self, ctx: moderngl.Context, program: moderngl.Program, scale: float = 1.0):
        self.ctx, self.program = ctx, program
        self.vao = ctx.vertex_array(program, [])
        self.rect = cast(moderngl.Uniform, program["u_rect"])  # where on the screen, in NDC
        self.texture: moderngl.Texture | None = None
        self.lines: list[str] | None = None
        self.renders = 0  # texture re-renders, for tests and the log
        self.set_scale(scale)

    def set_scale(self, scale: float) -> None:
        """Text and gaps `scale` times their size (the text drawn again at the next set)."""
        self.scale = scale
        self.font = ImageFont.load_default(size=max(1, round(FONT_SIZE * scale)))
        self.lines = None

    def set(self, lines: list[str]) -> None:
        if lines == self.lines:
            return
        self.lines = list(lines)
        image = text_image(self.lines, self.font, self.scale).transpose(
            Image.Transpose.FLIP_TOP_BOTTOM)
        if self.texture is None or self.texture.size != image.size:
            if self.texture is not None:
                self.texture.release()
            self.texture = self.ctx.texture(image.size, 4)
            self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)  # when shrunk
        self.texture.write(np.asarray(image).tobytes())
        self.renders += 1

    def draw(self, x: int, y: int, framebuffer_size: tuple[int, int]) -> int:
        """Draw with its top-left corner at framebuffer pixel (x, y), y from the top,
        shrunk where the window is too small for it; returns the drawn height."""
        if self.texture is None:
            return 0
        frame_w, frame_h = framebuffer_size
        texture_w, texture_h = self.texture.size
        pad = PADDING * self.scale
        shrink = min(1.0, (frame_w - x - pad) / texture_w, (frame_h - y - pad) / texture_h)
        if shrink <= 0:
            return 0
        width, height = texture_w * shrink, texture_h * shrink
        x0, x1 = 2 * x / frame_w - 1, 2 * (x + width) / frame_w - 1
        y0, y1 = 1 - 2 * (y + height) / frame_h, 1 - 2 * y / frame_h
        self.rect.value = (x0, y0, x1, y1)
        self.texture.use(0)
        self.vao.render(moderngl.TRIANGLE_STRIP, vertices=4)
        return round(height)


class Hud:
    """The stats panel (top left) and the help overlay (below it)."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        program = load_program(ctx, "blit.vert", "blit.frag")
        program["u_texture"].value = 0
        self.stats = Panel(ctx, program)
        self.help = Panel(ctx, program)
        self.visible, self.show_help = True, False
        self.scale = 1.0

    def set_scale(self, scale: float) -> None:
        """The window's content scale (GLFW's): text and gaps drawn that many times their
        size, in framebuffer px."""
        if scale > 0 and scale != self.scale:
            self.scale = scale
            self.stats.set_scale(scale)
            self.help.set_scale(scale)

    def draw(self, framebuffer_size: tuple[int, int], stats: list[str], help_lines: list[str]) -> None:
        if not self.visible:
            return
        self.stats.set(stats)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        pad = round(PADDING * self.scale)
        height = self.stats.draw(pad, pad, framebuffer_size)
        if self.show_help:
            self.help.set(help_lines)
            self.help.draw(pad, pad * 2 + height, framebuffer_size)
        self.ctx.disable(moderngl.BLEND)
