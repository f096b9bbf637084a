"""Glyph outlines through HarfBuzz's draw API (``hb_font_draw_glyph`` via uharfbuzz): compiled glyf, CFF and CFF2
interpreters, with a variable font's axis values applied by HarfBuzz itself.

fontTools interprets CFF charstrings in Python (about 3 ms a glyph: 10 s of a 3,500-glyph CJK atlas); HarfBuzz does
it in C, so only its draw callbacks (one per segment) run in Python. The curves are the ones fontTools' segment pens
see: the font's own points, quadratic for TrueType (implied on-curve points halfway between two off-curve ones),
cubic for CFF, a closing line when a contour does not end where it starts, empty contours dropped. HarfBuzz reports
coordinates as C floats: exact for the integer (and half-integer implied) coordinates of static fonts, while
interpolated coordinates of a variable font may differ from fontTools' doubles in the last float bits
(``tests/techniques/test_glyphs_outline.py`` compares both readers segment by segment).

A glyph HarfBuzz draws nothing for, although its face has outline data for it (a damaged or truncated table, which
HarfBuzz's sanitizer silently empties), is left to the caller (``None``), which reads it with fontTools: that either
raises the damaged-font error or agrees that the glyph is empty.
"""
from __future__ import annotations

import numpy as np

from baker.techniques.glyphs.shape import Shape

OUTLINE_TABLES = ("glyf", "CFF ", "CFF2")


class _Collector:
    """Segments of one glyph as HarfBuzz draws them: rows of 8 floats (4 control points, unused ones 0), degrees, and
    the segment count at the end of each contour."""

    __slots__ = ("rows", "degrees", "ends", "x", "y", "x0", "y0", "first")

    def __init__(self):
        self.rows, self.degrees, self.ends = [], [], []
        self.x = self.y = self.x0 = self.y0 = 0.0
        self.first = 0  # segment index where the open contour began

    def close(self):
        n = len(self.degrees)
        if n > self.first:
            if self.x != self.x0 or self.y != self.y0:  # as a segment pen: the contour returns to its start
                self.rows.append((self.x, self.y, self.x0, self.y0, 0.0, 0.0, 0.0, 0.0))
                self.degrees.append(1)
                n += 1
            self.ends.append(n)
        self.first = n
        self.x, self.y = self.x0, self.y0


def _move_to(x, y, c):
    c.close()
    c.x = c.x0 = x
    c.y = c.y0 = y


def _line_to(x, y, c):
    c.rows.append((c.x, c.y, x, y, 0.0, 0.0, 0.0, 0.0))
    c.degrees.append(1)
    c.x, c.y = x, y


def _quadratic_to(x1, y1, x, y, c):
    c.rows.append((c.x, c.y, x1, y1, x, y, 0.0, 0.0))
    c.degrees.append(2)
    c.x, c.y = x, y


def _cubic_to(x1, y1, x2, y2, x, y, c):
    c.rows.append((c.x, c.y, x1, y1, x2, y2, x, y))
    c.degrees.append(3)
    c.x, c.y = x, y


def _close_path(c):
    c.close()


class HarfBuzzOutlines:
    """Outlines of one face (``path``, ``face_index``) at a variable font's ``location`` ({axis tag: user value})."""

    def __init__(self, path, face_index: int = 0, location: dict | None = None):
        import uharfbuzz as hb

        self.face = hb.Face(hb.Blob.from_file_path(str(path)), face_index)
        self.font = hb.Font(self.face)
        self.font.scale = (self.face.upem, self.face.upem)  # font units (the default; stated, not assumed)
        if location:
            self.font.set_variations({str(k): float(v) for k, v in location.items()})
        self.funcs = hb.DrawFuncs()
        self.funcs.set_move_to_func(_move_to)
        self.funcs.set_line_to_func(_line_to)
        self.funcs.set_quadratic_to_func(_quadratic_to)
        self.funcs.set_cubic_to_func(_cubic_to)
        self.funcs.set_close_path_func(_close_path)

    def shape(self, glyph_id: int, scale: float = 1.0, drop_contours=(), contours: int | None = None) -> Shape | None:
        """The outline of ``glyph_id`` in font units (times ``scale``), without the contours numbered in
        ``drop_contours``; None when HarfBuzz draws nothing, or not ``contours`` contours when that is given."""
        c = _Collector()
        self.font.draw_glyph(glyph_id, self.funcs, c)
        c.close()
        if not c.degrees or (contours is not None and len(c.ends) != contours):
            return None
        rows, degrees, ends = c.rows, c.degrees, c.ends
        if drop_contours:
            keep = [k for k in range(len(ends)) if k not in drop_contours]
            bounds = [(0 if k == 0 else ends[k - 1], ends[k]) for k in keep]
            rows = [r for a, b in bounds for r in rows[a:b]]
            degrees = [d for a, b in bounds for d in degrees[a:b]]
            ends = list(np.cumsum([b - a for a, b in bounds]))
            if not degrees:
                return Shape.empty()
        points = np.array(rows, np.float64).reshape(-1, 4, 2)
        if scale != 1.0:
            points = points * scale  # padding rows stay 0, as fontTools' path scales only the used points
        return Shape(points, np.array(degrees, np.int8), np.array([0] + ends, np.int64))
