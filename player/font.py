"""A 3x5 pixel bitmap font for labels on rendered images, so labelling needs no font library.

Lower case is drawn as upper case; characters without a glyph are drawn as '?'.
"""

import numpy as np

_GLYPHS = {
    "0": "111 101 101 101 111", "1": "010 110 010 010 111", "2": "111 001 111 100 111",
    "3": "111 001 111 001 111", "4": "101 101 111 001 001", "5": "111 100 111 001 111",
    "6": "111 100 111 101 111", "7": "111 001 001 010 010", "8": "111 101 111 101 111",
    "9": "111 101 111 001 111",
    "A": "010 101 111 101 101", "B": "110 101 110 101 110", "C": "011 100 100 100 011",
    "D": "110 101 101 101 110", "E": "111 100 110 100 111", "F": "111 100 110 100 100",
    "G": "011 100 101 101 011", "H": "101 101 111 101 101", "I": "111 010 010 010 111",
    "J": "001 001 001 101 010", "K": "101 101 110 101 101", "L": "100 100 100 100 111",
    "M": "101 111 111 101 101", "N": "110 101 101 101 101", "O": "010 101 101 101 010",
    "P": "110 101 110 100 100", "Q": "010 101 101 110 011", "R": "110 101 110 101 101",
    "S": "011 100 010 001 110", "T": "111 010 010 010 010", "U": "101 101 101 101 111",
    "V": "101 101 101 101 010", "W": "101 101 111 111 101", "X": "101 101 010 101 101",
    "Y": "101 101 010 010 010", "Z": "111 001 010 100 111",
    " ": "000 000 000 000 000", ":": "000 010 000 010 000", "-": "000 000 111 000 000",
    "_": "000 000 000 000 111", ".": "000 000 000 000 010", ",": "000 000 000 010 100",
    "/": "001 001 010 100 100", "#": "101 111 101 111 101", "(": "010 100 100 100 010",
    ")": "010 001 001 001 010", "=": "000 111 000 111 000", "+": "000 010 111 010 000",
    "?": "111 001 010 000 010",
    "'": "010 010 000 000 000", "<": "001 010 100 010 001", ">": "100 010 001 010 100",
    "!": "010 010 010 000 010", "%": "101 001 010 100 101", "[": "110 100 100 100 110",
    "]": "011 001 001 001 011", "*": "000 101 010 101 000", "|": "010 010 010 010 010",
}
#: Every character with a glyph (lower case letters are drawn as upper case).
CHARSET = "".join(_GLYPHS)
GLYPH_W, GLYPH_H = 3, 5


def bitmap(char):
    """(5, 3) bool glyph of ``char`` ('?' for characters without one).

    >>> bitmap("|").astype(int)[:, 1].tolist()
    [1, 1, 1, 1, 1]
    """
    rows = _GLYPHS.get(char.upper(), _GLYPHS["?"]).split()
    return np.array([[bit == "1" for bit in row] for row in rows])


def text_mask(text, scale=1):
    """(5 * scale, (4 * len(text) - 1) * scale) bool mask of ``text``, one blank column between letters.

    >>> text_mask("1").astype(int).tolist()[0]
    [0, 1, 0]
    """
    if not text:
        return np.zeros((GLYPH_H * scale, 0), bool)
    gap = np.zeros((GLYPH_H, 1), bool)
    parts = []
    for i, char in enumerate(text):
        parts += [gap, bitmap(char)] if i else [bitmap(char)]
    mask = np.hstack(parts)
    return mask.repeat(scale, axis=0).repeat(scale, axis=1)


def draw_text(image, text, position=(2, 2), scale=1, colour=(255, 255, 255), backing=(0, 0, 0)):
    """Write ``text`` into ``image`` (H, W, 3) uint8 in place, top-left corner at ``position`` (x, y).

    A ``backing`` box with a margin of ``scale`` pixels (None for none) keeps the label
    readable on any picture; text that does not fit is clipped at the image edge.
    """
    mask = text_mask(text, scale)
    x, y = position
    if backing is not None:
        mask = np.pad(mask, scale)
        x, y = x - scale, y - scale
    x, y = max(int(x), 0), max(int(y), 0)
    h, w = min(mask.shape[0], image.shape[0] - y), min(mask.shape[1], image.shape[1] - x)
    if h <= 0 or w <= 0:
        return image
    region = image[y:y + h, x:x + w]
    if backing is not None:
        region[:] = backing
    region[mask[:h, :w]] = colour
    return image
