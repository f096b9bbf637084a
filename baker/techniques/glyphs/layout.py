"""Text layout on a baked atlas: one textured quad per visible glyph.

Units are ems until the caller scales them. The first line's baseline is y = 0, lines go down by the font's line
height (times ``line_spacing``); each line is aligned on x = 0 (left), centred on it, or ends on it (right).

- :func:`quads_of_shaped`: glyphs placed by HarfBuzz (:mod:`.shaping`: ligatures, complex scripts, bidi, fallback
  fonts, line breaking), looked up in the atlas by (font, glyph id);
- :func:`layout_text`: by code point with advances and pair kerning only (the layout a runtime without a shaper
  does, and what ``BAKER_text`` without ``glyphs`` means). Glyphs the atlas lacks advance by nothing and are reported.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ALIGNMENTS = ("left", "center", "right")


@dataclass
class TextQuads:
    positions: np.ndarray  # (n, 4, 2) em, corners left-bottom, right-bottom, right-top, left-top
    uvs: np.ndarray  # (n, 4, 2) glTF texture coordinates (origin top-left)
    codepoints: np.ndarray  # (n,) the glyph of each quad
    bounds: tuple  # (left, bottom, right, top) em of all quads (0s when empty)
    missing: list  # characters of the text the atlas has no glyph for
    table: np.ndarray | None = None  # (m,) shaped text: atlas glyph-table index of every placed glyph (spaces too)
    origins: np.ndarray | None = None  # (m, 2) em: where each of those glyphs' origin is


def quads_of_shaped(shaped, atlas) -> TextQuads:
    """Quads for a :class:`~baker.techniques.glyphs.shaping.ShapedText` whose glyphs the atlas holds (.notdef is
    not drawn: its characters are in ``shaped.missing``)."""
    where = {(g.face, g.index): k for k, g in enumerate(atlas.glyphs)}
    W, H = float(atlas.width), float(atlas.height)
    positions, uvs, cps, table, origins = [], [], [], [], []
    for s in shaped.glyphs:
        k = where.get((s.face, s.glyph_id))
        if k is None or s.glyph_id == 0:
            continue
        g = atlas.glyphs[k]
        table.append(k)
        origins.append((s.x, s.y))
        if g.plane is None:
            continue
        l, b, r, t = g.plane
        x, y = s.x, s.y
        positions.append([[x + l, y + b], [x + r, y + b], [x + r, y + t], [x + l, y + t]])
        al, ab, ar, at = g.atlas
        uvs.append([[al / W, 1 - ab / H], [ar / W, 1 - ab / H], [ar / W, 1 - at / H], [al / W, 1 - at / H]])
        cps.append(g.codepoint)
    pos = np.array(positions, np.float64).reshape(-1, 4, 2)
    return TextQuads(pos, np.array(uvs, np.float64).reshape(-1, 4, 2), np.array(cps, np.int64), _bounds(pos),
                     list(shaped.missing), np.array(table, np.int64), np.array(origins, np.float64).reshape(-1, 2))


def _bounds(pos) -> tuple:
    return (float(pos[..., 0].min()), float(pos[..., 1].min()), float(pos[..., 0].max()),
            float(pos[..., 1].max())) if len(pos) else (0.0, 0.0, 0.0, 0.0)


def layout_text(text: str, atlas, align: str = "left", line_spacing: float = 1.0) -> TextQuads:
    if align not in ALIGNMENTS:
        raise ValueError(f"unknown alignment {align!r} (known: {', '.join(ALIGNMENTS)})")
    glyphs = {g.codepoint: g for g in atlas.glyphs if g.codepoint >= 0}
    kerning = {(a, b): v for a, b, v in atlas.kerning}
    line_height = atlas.metrics_em()["lineHeight"] * line_spacing
    W, H = float(atlas.width), float(atlas.height)
    positions, uvs, cps, missing = [], [], [], []
    for row, line in enumerate(text.split("\n")):
        pen, prev, start = 0.0, None, len(positions)
        y = -row * line_height
        for ch in line:
            cp = ord(ch)
            g = glyphs.get(cp)
            if g is None:
                if ch not in missing:
                    missing.append(ch)
                prev = None
                continue
            if prev is not None:
                pen += kerning.get((prev, cp), 0.0)
            if g.plane is not None:
                l, b, r, t = g.plane
                positions.append([[pen + l, y + b], [pen + r, y + b], [pen + r, y + t], [pen + l, y + t]])
                al, ab, ar, at = g.atlas
                uvs.append([[al / W, 1 - ab / H], [ar / W, 1 - ab / H], [ar / W, 1 - at / H], [al / W, 1 - at / H]])
                cps.append(cp)
            pen += g.advance
            prev = cp
        shift = {"left": 0.0, "center": -pen / 2.0, "right": -pen}[align]
        for q in positions[start:]:
            for corner in q:
                corner[0] += shift
    pos = np.array(positions, np.float64).reshape(-1, 4, 2)
    return TextQuads(pos, np.array(uvs, np.float64).reshape(-1, 4, 2), np.array(cps, np.int64), _bounds(pos), missing)
