"""Glyph atlases: boxes per glyph, deterministic packing, the baked atlas and its msdf-atlas-gen / BMFont metrics
(:func:`baker.techniques.glyphs.kernel.bake_atlas` fills it).

Each glyph with an outline gets a box on the pixel grid of its own origin (pen position on the baseline): its exact
bounds at ``size`` px/em, grown by range/2 on every side (the field must reach 0 and 1 inside the box) and rounded
outwards to whole pixels. Boxes are packed with a skyline bottom-left packer, tallest first (ties by code point),
``padding`` empty texels between boxes and around the border; the atlas width is the square root of the total area
(or a power of two, or square), so the same charset and options always give the same atlas.

The JSON layout is msdf-atlas-gen's (``atlas``, ``metrics``, ``glyphs`` with ``planeBounds`` in em relative to the
origin and ``atlasBounds`` in atlas pixels, ``kerning``; ``yOrigin`` bottom, ``emSize`` 1), so runtimes written
for msdf-atlas-gen load it unchanged. ``bmfont_json`` writes the BMFont JSON that three.js text libraries read.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baker.techniques.glyphs.outline import Font
from baker.techniques.glyphs.options import GlyphOptions




@dataclass
class GlyphEntry:
    codepoint: int  # -1: a glyph no code point maps to (ligature, contextual form)
    index: int  # glyph id in its font
    advance: float  # em
    plane: tuple | None  # (left, bottom, right, top) em, relative to the origin, y up
    atlas: tuple | None  # (left, bottom, right, top) atlas pixels, y up from the atlas bottom (yOrigin bottom)
    font_bounds: tuple | None  # exact outline bounds in font units (l, b, r, t)
    face: int = 0  # font of the fallback list (Font.faces) the glyph comes from


@dataclass
class GlyphAtlas:
    """A baked atlas: the image (row 0 at the top) and everything a runtime needs to lay out text with it."""

    image: np.ndarray  # (height, width, channels) uint8
    glyphs: list  # [GlyphEntry] in charset order
    kerning: list  # [(codepoint1, codepoint2, advance em)] sorted
    font: Font
    options: GlyphOptions

    @property
    def width(self) -> int:
        return int(self.image.shape[1])

    @property
    def height(self) -> int:
        return int(self.image.shape[0])

    def metrics_em(self) -> dict:
        m = self.font.metrics
        u = float(m.units_per_em)
        return {"emSize": 1, "lineHeight": m.line_height / u, "ascender": m.ascender / u,
                "descender": m.descender / u, "underlineY": m.underline_y / u,
                "underlineThickness": m.underline_thickness / u}

    def layout_json(self) -> dict:
        """msdf-atlas-gen's JSON layout."""
        glyphs = []
        several = len(self.font.faces) > 1
        for g in self.glyphs:
            # msdf-atlas-gen writes "unicode" for code points and "index" for glyph ids; both where both are known
            entry = {"unicode": g.codepoint} if g.codepoint >= 0 else {}
            entry["index"] = g.index
            if several:
                entry["font"] = g.face
            entry["advance"] = g.advance
            if g.plane is not None:
                entry["planeBounds"] = dict(zip(("left", "bottom", "right", "top"), g.plane))
                entry["atlasBounds"] = dict(zip(("left", "bottom", "right", "top"), g.atlas))
            glyphs.append(entry)
        layout = {
            "atlas": {"type": self.options.type, "distanceRange": self.options.range, "distanceRangeMiddle": 0,
                      "size": self.options.size, "width": self.width, "height": self.height, "yOrigin": "bottom"},
            "name": self.font.family,
            "metrics": self.metrics_em(),
            "glyphs": glyphs,
            "kerning": [{"unicode1": a, "unicode2": b, "advance": v} for a, b, v in self.kerning],
        }
        if several:  # the fallback list; each glyph's "font" indexes it
            layout["fonts"] = self.faces_json()
        return layout

    def faces_json(self) -> list:
        """The fallback list as written to files: file name (never a path), face index, family, units per em."""
        from pathlib import Path

        return [{"name": f.family, "file": Path(f.path).name, "faceIndex": f.face_index, "unitsPerEm": f.units_per_em}
                for f in self.font.faces]

    def codepoint_glyphs(self) -> list:
        """The glyphs a code point maps to (BMFont has no place for the others: ligatures, contextual forms)."""
        return [g for g in self.glyphs if g.codepoint >= 0]

    def bmfont_json(self, page: str) -> dict:
        """The BMFont JSON (as written by msdf-bmfont-xml) used by three-bmfont-text and similar libraries:
        pixel units, y down from the top of the line (``base`` = ascender in pixels)."""
        size = self.options.size
        base = round(self.font.metrics.ascender / self.font.metrics.units_per_em * size)
        chars = []
        for g in self.codepoint_glyphs():
            ch = {"id": g.codepoint, "index": g.index, "char": chr(g.codepoint), "xadvance": g.advance * size,
                  "chnl": 15, "page": 0}
            if g.plane is None:
                ch.update(width=0, height=0, xoffset=0, yoffset=0, x=0, y=0)
            else:
                l, b, r, t = g.atlas
                ch.update(width=int(r - l), height=int(t - b), x=int(l), y=int(self.height - t),
                          xoffset=round(g.plane[0] * size), yoffset=base - round(g.plane[3] * size))
            chars.append(ch)
        pad = int(math.ceil(self.options.range / 2))
        return {
            "pages": [page],
            "chars": chars,
            "info": {"face": self.font.family, "size": size, "bold": 0, "italic": 0,
                     "charset": [chr(g.codepoint) for g in self.codepoint_glyphs()], "unicode": 1, "stretchH": 100, "smooth": 1,
                     "aa": 1, "padding": [pad, pad, pad, pad], "spacing": [self.options.padding] * 2},
            "common": {"lineHeight": self.metrics_em()["lineHeight"] * size, "base": base, "scaleW": self.width,
                       "scaleH": self.height, "pages": 1, "packed": 0, "alphaChnl": 0, "redChnl": 0,
                       "greenChnl": 0, "blueChnl": 0},
            "distanceField": {"fieldType": self.options.type, "distanceRange": self.options.range},
            "kernings": [{"first": a, "second": b, "amount": v * size} for a, b, v in self.kerning],
        }


# ---------------------------------------------------------------------------------------------------- boxes
def glyph_box(bounds: tuple, scale: float, distance_range: float) -> tuple[int, int, int, int]:
    """(left, bottom, width, height) in pixels relative to the glyph origin: the bounds grown by range/2."""
    l, b, r, t = bounds
    half = distance_range / 2.0
    left = math.floor(l * scale - half)
    bottom = math.floor(b * scale - half)
    right = math.ceil(r * scale + half)
    top = math.ceil(t * scale + half)
    return left, bottom, max(right - left, 1), max(top - bottom, 1)


# ---------------------------------------------------------------------------------------------------- packing
def pack_skyline(sizes: list, width: int, padding: int) -> tuple[list, int]:
    """Bottom-left skyline packing of (w, h) boxes, in the given order, into ``width`` columns.

    Returns ([(x, y)] top-left corners, image rows top-down, used height). ``padding`` empty texels separate boxes
    from each other and from the border. Deterministic: the lowest position wins, then the leftmost.
    """
    skyline = [(padding, padding, width - padding)]  # segments (x, y, w): the lowest free row over columns
    positions = []
    for w, h in sizes:
        cw, ch = w + padding, h + padding
        best = None
        for i in range(len(skyline)):
            x = skyline[i][0]
            if x + cw > width:  # the cell's right padding may touch the border, the box may not
                break
            y, span, k = 0, 0, i
            while span < cw:
                y = max(y, skyline[k][1])
                span += skyline[k][2]
                k += 1
            if best is None or (y, x) < (best[0], best[1]):
                best = (y, x, i)
        if best is None:
            raise ValueError(f"a {w} x {h} box does not fit in width {width}")
        y, x, i = best
        positions.append((x, y))
        # raise the skyline over [x, x + cw)
        new = []
        for sx, sy, sw in skyline:
            end = sx + sw
            if end <= x or sx >= x + cw:
                new.append((sx, sy, sw))
                continue
            if sx < x:
                new.append((sx, sy, x - sx))
            if end > x + cw:
                new.append((x + cw, sy, end - (x + cw)))
        new.append((x, y + ch, cw))
        new.sort()
        merged = []
        for seg in new:
            if merged and merged[-1][1] == seg[1] and merged[-1][0] + merged[-1][2] == seg[0]:
                merged[-1] = (merged[-1][0], seg[1], merged[-1][2] + seg[2])
            else:
                merged.append(seg)
        skyline = merged
    height = max((y + h for (x, y), (w, h) in zip(positions, sizes)), default=0) + padding
    return positions, height


def _next_pot(n: int) -> int:
    return 1 << max(0, int(n - 1).bit_length())


def pack(sizes: list, padding: int, pot: bool = False, square: bool = False) -> tuple[list, int, int]:
    """Choose the atlas size and pack: ([(x, y)], width, height)."""
    if not sizes:
        return [], max(1, 2 * padding), max(1, 2 * padding)
    area = sum((w + padding) * (h + padding) for w, h in sizes)
    widest = max(w for w, _ in sizes) + 2 * padding
    width = max(widest, int(math.ceil(math.sqrt(area * 1.05))) + padding)
    if pot:
        width = _next_pot(width)
    while True:
        positions, height = pack_skyline(sizes, width, padding)
        if square:
            side = _next_pot(max(width, height)) if pot else max(width, height)
            if height <= width or side == width:
                if height <= side and width <= side:
                    return positions, side, side
            width = side if pot else max(width + 1, int(math.ceil((width + height) / 2)))
            continue
        if pot:
            height = _next_pot(height)
        return positions, width, height


# ---------------------------------------------------------------------------------------------------- baking
