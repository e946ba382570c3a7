"""Heads-up display: text drawn with Pillow's bundled font into RGBA textures.

A panel re-renders its texture only when its text changes; drawing is one blended quad.
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


def text_image(lines: list[str], font) -> Image.Image:
    """The lines in white on a translucent box, as a top-down RGBA image. Tabs split a
    line into columns, aligned across lines (the font is proportional)."""
    ascent, descent = font.getmetrics()
    line_h = ascent + descent + LINE_GAP
    rows = [line.split("\t") for line in lines]
    starts = _column_starts(rows, font)
    width = max((starts[len(r) - 1] + int(font.getlength(r[-1])) for r in rows), default=0)
    size = (width + 2 * PADDING, line_h * len(lines) + 2 * PADDING)
    image = Image.new("RGBA", size, BOX_RGBA)
    draw = ImageDraw.Draw(image)
    for i, row in enumerate(rows):
        for start, cell in zip(starts, row, strict=False):
            draw.text((PADDING + start, PADDING + i * line_h), cell, font=font, fill=TEXT_RGBA)
    return image


def _column_starts(rows: list[list[str]], font) -> list[int]:
    """x of each column: after the widest cell of the column before, plus a gap."""
    columns = max((len(r) for r in rows), default=1)
    starts = [0]
    for c in range(columns - 1):
        widest = max((int(font.getlength(r[c])) for r in rows if len(r) > c + 1), default=0)
        starts.append(starts[-1] + widest + COLUMN_GAP)
    return starts


class Panel:
    """One block of text at a fixed spot of the window, kept in its own texture."""

    def __init__(self, ctx: moderngl.Context, program: moderngl.Program, font):
        self.ctx, self.program, self.font = ctx, program, font
        self.vao = ctx.vertex_array(program, [])
        self.rect = cast(moderngl.Uniform, program["u_rect"])  # where on the screen, in NDC
        self.texture: moderngl.Texture | None = None
        self.lines: list[str] | None = None
        self.renders = 0  # texture re-renders, for tests and the log

    def set(self, lines: list[str]) -> None:
        if lines == self.lines:
            return
        self.lines = list(lines)
        image = text_image(self.lines, self.font).transpose(Image.Transpose.FLIP_TOP_BOTTOM)
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
        shrink = min(1.0, (frame_w - x - PADDING) / texture_w, (frame_h - y - PADDING) / texture_h)
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
        font = ImageFont.load_default(size=FONT_SIZE)
        self.stats = Panel(ctx, program, font)
        self.help = Panel(ctx, program, font)
        self.visible, self.show_help = True, False

    def draw(self, framebuffer_size: tuple[int, int], stats: list[str], help_lines: list[str]) -> None:
        if not self.visible:
            return
        self.stats.set(stats)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        height = self.stats.draw(PADDING, PADDING, framebuffer_size)
        if self.show_help:
            self.help.set(help_lines)
            self.help.draw(PADDING, PADDING * 2 + height, framebuffer_size)
        self.ctx.disable(moderngl.BLEND)
