"""Glyph atlases: boxes per glyph, deterministic packing, the field kernels, and msdf-atlas-gen / BMFont metrics.

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

from baker.techniques.glyphs.coloring import corner_points, edge_colors
from baker.techniques.glyphs.msdf import CHANNELS, glyph_fields
from baker.techniques.glyphs.outline import Font
from baker.techniques.glyphs.sdf import GlyphBatch
from baker.techniques.glyphs.shape import monotone_pieces, prepare
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
def bake_atlas(font: Font, options: GlyphOptions = GlyphOptions()) -> GlyphAtlas:
    """Bake the distance-field atlas of every glyph of ``font`` (see the module docstring)."""
    scale = options.size / font.metrics.units_per_em
    entries, shapes, boxes = [], [], []
    for g, shape in zip(font.glyphs, _prepared([g.shape for g in font.glyphs])):
        advance = g.advance / font.metrics.units_per_em
        if shape.segment_count == 0:
            entries.append(GlyphEntry(g.codepoint, g.index, advance, None, None, None, g.face))
            continue
        bounds = shape.bounds()
        left, bottom, w, h = glyph_box(bounds, scale, options.range)
        entries.append(GlyphEntry(g.codepoint, g.index, advance, None, None, bounds, g.face))
        shapes.append((len(entries) - 1, shape.transformed(scale, -left, -bottom), (left, bottom, w, h)))
        boxes.append((w, h))

    def key(k):
        e = entries[shapes[k][0]]
        return -boxes[k][1], -boxes[k][0], e.codepoint, e.face, e.index

    order = sorted(range(len(boxes)), key=key)
    placed, width, height = pack([boxes[k] for k in order], options.padding, options.pot, options.square)
    position = {k: placed[n] for n, k in enumerate(order)}

    channels = CHANNELS[options.type]
    image = np.zeros((height, width, channels), np.uint8)
    # the kernels run on groups of about CHUNK_TEXELS texels: every texel's value depends on its own glyph alone,
    # so the bytes are those of one batch, while the float fields and the kernels' work arrays stay bounded (a
    # 3,500-glyph CJK atlas held ~0.5 GB of them at once); each group is quantized straight into the byte image
    for group in _texel_groups([w * h for _, _, (_, _, w, h) in shapes], CHUNK_TEXELS):
        batch, corners = _batch([shapes[k] for k in group], options)
        values = glyph_fields(batch, corners, options.type, options.range, options.error_correction)
        for n, k in enumerate(group):
            e, _, (left, bottom, w, h) = shapes[k]
            x, y = position[k]
            block = values[batch.texel_start[n]: batch.texel_start[n + 1]].reshape(h, w, channels)
            image[y: y + h, x: x + w] = quantize(block[::-1])  # glyph rows are bottom-up, image rows top-down
            entry = entries[e]
            entry.plane = (left / options.size, bottom / options.size, (left + w) / options.size,
                           (bottom + h) / options.size)
            entry.atlas = (float(x), float(height - y - h), float(x + w), float(height - y))
        del batch, corners, values
    u = float(font.metrics.units_per_em)
    kerning = sorted((a, b, v / u) for (a, b), v in font.kerning.items() if v)
    return GlyphAtlas(image, entries, kerning, font, options)


def _prepared(outlines: list) -> list:
    """:func:`~baker.techniques.glyphs.shape.prepare` of every outline, on the numba thread count's threads (its
    kernels release the GIL; each glyph's result depends on that glyph alone, so the order of work changes nothing)."""
    import numba

    threads = min(numba.get_num_threads(), max(1, len(outlines) // 64))
    if threads <= 1:
        return [prepare(s) for s in outlines]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(threads) as pool:
        return list(pool.map(prepare, outlines))


CHUNK_TEXELS = 1 << 20  # texels per kernel call in bake_atlas (~24 MB of float64 MSDF values)


def _texel_groups(texels: list, limit: int) -> list:
    """Consecutive index groups whose texel counts add up to at most ``limit`` (a bigger glyph: a group alone)."""
    groups, current, total = [], [], 0
    for k, n in enumerate(texels):
        if current and total + n > limit:
            groups.append(current)
            current, total = [], 0
        current.append(k)
        total += n
    if current:
        groups.append(current)
    return groups


def quantize(values: np.ndarray) -> np.ndarray:
    """Field values in [0, 1] -> bytes as msdfgen writes them (``pixelFloatToByte``: 256 v truncated, clamped to
    255). Near the edge (v = 0.5) the decoded b / 255 is unbiased and keeps the sign exactly, like rounding 255 v; the
    difference is which texels a sub-step distance sends up or down. Choosing msdfgen's makes an atlas byte-equal to
    msdfgen's wherever the fields agree, so comparisons with it measure the fields rather than the rounding (on
    DejaVu Serif, rounding alone moved the mean coverage error by 13%, all of it on texels within one 8-bit step)."""
    return np.clip(np.floor(values * 256.0), 0.0, 255.0).astype(np.uint8)


def _batch(shapes: list, options: GlyphOptions) -> tuple[GlyphBatch, list]:
    """Concatenate the glyphs' prepared shapes (already in box pixel space) for the kernels, with edge colors."""
    pts, deg, cols, seg_counts, pieces, piece_deg, piece_counts, corners = [], [], [], [], [], [], [], []
    widths, heights = [], []
    need_colors = options.type in ("msdf", "mtsdf")
    for _, shape, (_, _, w, h) in shapes:
        if need_colors:
            colors = edge_colors(shape.points, shape.degree, shape.contour_start, options.angle_threshold,
                                 options.coloring, cutoff=options.range / 2, texel=1.0)  # box pixel space
            buf = np.empty((shape.segment_count, 2))
            n = corner_points(shape.points, shape.degree, shape.contour_start, colors, buf)
            corners.append(buf[:n].copy())
        else:
            colors = np.full(shape.segment_count, 7, np.uint8)
            corners.append(np.zeros((0, 2)))
        colors = np.where(shape.interior, 0, colors).astype(np.uint8) if shape.interior is not None else colors
        if shape.fill_pieces is not None:
            p, pd = shape.fill_pieces, shape.fill_piece_degree
        else:
            p, pd = monotone_pieces(shape.points, shape.degree)
        pts.append(shape.points)
        deg.append(shape.degree)
        cols.append(colors)
        seg_counts.append(shape.segment_count)
        pieces.append(p)
        piece_deg.append(pd)
        piece_counts.append(len(pd))
        widths.append(w)
        heights.append(h)

    def starts(counts):
        return np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)

    if not shapes:
        empty = np.zeros((0, 4, 2))
        return GlyphBatch(empty, np.zeros(0, np.int8), np.zeros(0, np.uint8), np.zeros(1, np.int64), empty,
                          np.zeros(0, np.int8), np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
                          np.zeros(1, np.int64)), corners
    widths, heights = np.array(widths, np.int64), np.array(heights, np.int64)
    batch = GlyphBatch(np.ascontiguousarray(np.concatenate(pts)), np.concatenate(deg), np.concatenate(cols),
                       starts(seg_counts), np.ascontiguousarray(np.concatenate(pieces)), np.concatenate(piece_deg),
                       starts(piece_counts), widths, heights, starts(widths * heights))
    return batch, corners
