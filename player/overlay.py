"""On-screen text for the realtime window: the bitmap font of ``tvmedit.player.font`` as textured quads.

The glyphs go once into a one-channel atlas texture; each label becomes quads in pixel
coordinates with a translucent backing box, so the text stays readable over the mesh and the
floor. The vertex buffer is rewritten only when the text changes, not on every redraw.
"""

import moderngl
import numpy as np

from .font import CHARSET, GLYPH_H, GLYPH_W, bitmap
from .programs import load_program

_CELL = GLYPH_W + 1          # one empty texel column between cells keeps glyphs apart
#: Colour of dimmed lines (motions out of reach), sRGB.
DIMMED = (0.42, 0.42, 0.46)

_VERTEX = np.dtype([("pixel", np.float32, 2), ("uv", np.float32, 2), ("colour", np.float32, 4)])


class Label:
    """Lines of text at a corner of the window.

    Parameters
    ----------
    lines : list of str
    corner : "top-left", "top-right", "bottom-left" or "bottom-right"
    colour : sRGB (r, g, b) in 0..1
    dimmed : indices of lines drawn in :data:`DIMMED` instead (e.g. motions out of reach)
    """

    def __init__(self, lines, corner="top-left", colour=(1.0, 1.0, 1.0), dimmed=()):
        self.lines = [str(line) for line in lines]
        self.corner = corner
        self.colour = tuple(colour)
        self.dimmed = frozenset(dimmed)

    def _key(self):
        return (tuple(self.lines), self.corner, self.colour, tuple(sorted(self.dimmed)))


class TextOverlay:
    """Draws ``Label``s over whatever the framebuffer holds.

    Parameters
    ----------
    ctx : moderngl.Context
    scale : screen pixels per font pixel (the font is 3 x 5)
    """

    def __init__(self, ctx, scale=2, margin=8, backing=(0.0, 0.0, 0.0, 0.55)):
        self.ctx = ctx
        self.scale = int(scale)
        self.margin = margin
        self.backing = tuple(backing)
        self._index = {char: i for i, char in enumerate(CHARSET)}
        atlas = np.zeros((GLYPH_H, _CELL * (len(CHARSET) + 1)), np.uint8)
        for i, char in enumerate(CHARSET):
            atlas[:, i * _CELL:i * _CELL + GLYPH_W] = bitmap(char) * 255
        atlas[:, -_CELL:] = 255  # the solid cell that backing boxes sample
        self._atlas_width = atlas.shape[1]
        self.texture = ctx.texture((atlas.shape[1], atlas.shape[0]), 1, np.ascontiguousarray(atlas).tobytes())
        self.texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.program = load_program(ctx, "overlay")
        self._buffer = ctx.buffer(reserve=_VERTEX.itemsize * 6 * 256, dynamic=True)
        self._vao = self._vertex_array()
        self._count = 0
        self._shown = None

    def draw(self, labels, framebuffer):
        """Draw ``labels`` (list of ``Label``) over ``framebuffer`` (e.g. ``ctx.screen``)."""
        width, height = framebuffer.viewport[2:]
        key = ((width, height), tuple(label._key() for label in labels))
        if key != self._shown:
            self._upload(self._quads(labels, width, height))
            self._shown = key
        if not self._count:
            return
        framebuffer.use()
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.texture.use(0)
        self.program["atlas"].value = 0
        self.program["screen"].value = (float(width), float(height))
        self._vao.render(moderngl.TRIANGLES, vertices=self._count)
        self.ctx.disable(moderngl.BLEND)

    def text_size(self, lines):
        """(width, height) in pixels of a block of ``lines`` without its backing."""
        s = self.scale
        width = max((len(line) * _CELL - 1) * s for line in lines) if lines else 0
        return max(width, 0), (len(lines) * (GLYPH_H + 2) - 2) * s if lines else 0

    def columns(self, width):
        """How many characters fit in ``width`` pixels."""
        return int((width - 2 * self.margin - 4 * self.scale) // (_CELL * self.scale))

    def release(self):
        self._vao.release()
        self._buffer.release()
        self.program.release()
        self.texture.release()

    def _vertex_array(self):
        return self.ctx.vertex_array(self.program, [(self._buffer, "2f 2f 4f", "in_pixel", "in_uv", "in_colour")])

    def _upload(self, quads):
        data = np.ascontiguousarray(quads).view(np.uint8)
        if data.nbytes > self._buffer.size:
            self._vao.release()
            self._buffer.release()
            self._buffer = self.ctx.buffer(reserve=int(data.nbytes * 1.5), dynamic=True)
            self._vao = self._vertex_array()
        if data.nbytes:
            self._buffer.write(data)
        self._count = len(quads)

    def _quads(self, labels, width, height):
        s, pad = self.scale, self.scale * 2
        quads = []
        for label in labels:
            if not label.lines:
                continue
            w, h = self.text_size(label.lines)
            x = self.margin + pad if "left" in label.corner else width - self.margin - pad - w
            y = self.margin + pad if "top" in label.corner else height - self.margin - pad - h
            quads.append(self._solid(x - pad, y - pad, w + 2 * pad, h + 2 * pad, self.backing))
            for row, line in enumerate(label.lines):
                colour = (*(DIMMED if row in label.dimmed else label.colour), 1.0)
                top = y + row * (GLYPH_H + 2) * s
                for col, char in enumerate(line.upper()):
                    if char == " ":
                        continue
                    cell = self._index.get(char, self._index["?"])
                    quads.append(self._glyph_quad(x + col * _CELL * s, top, cell, colour))
        return np.concatenate(quads) if quads else np.zeros(0, _VERTEX)

    def _glyph_quad(self, x, y, cell, colour):
        u0 = cell * _CELL / self._atlas_width
        u1 = (cell * _CELL + GLYPH_W) / self._atlas_width
        return _quad(x, y, GLYPH_W * self.scale, GLYPH_H * self.scale, (u0, 0.0, u1, 1.0), colour)

    def _solid(self, x, y, w, h, colour):
        u = (self._atlas_width - _CELL / 2) / self._atlas_width
        return _quad(x, y, w, h, (u, 0.5, u, 0.5), colour)


def _quad(x, y, w, h, uv, colour):
    """Two triangles covering the pixel rectangle (x, y, w, h), y down."""
    u0, v0, u1, v1 = uv
    corners = [(x, y, u0, v0), (x + w, y, u1, v0), (x, y + h, u0, v1),
               (x + w, y, u1, v0), (x + w, y + h, u1, v1), (x, y + h, u0, v1)]
    quad = np.zeros(6, _VERTEX)
    quad["pixel"] = [c[:2] for c in corners]
    quad["uv"] = [c[2:] for c in corners]
    quad["colour"] = colour
    return quad
