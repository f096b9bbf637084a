"""Text layout on a baked atlas: pen positions from advances and kerning, one textured quad per visible glyph.

Units are ems until the caller scales them. The first line's baseline is y = 0, lines go down by the font's line
height (times ``line_spacing``); each line is aligned on x = 0 (left), centred on it, or ends on it (right). Glyphs the
atlas lacks advance by nothing and are reported. No shaping beyond pair kerning (no ligatures or complex scripts).
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


def layout_text(text: str, atlas, align: str = "left", line_spacing: float = 1.0) -> TextQuads:
    if align not in ALIGNMENTS:
        raise ValueError(f"unknown alignment {align!r} (known: {', '.join(ALIGNMENTS)})")
    glyphs = {g.codepoint: g for g in atlas.glyphs}
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
    bounds = (float(pos[..., 0].min()), float(pos[..., 1].min()), float(pos[..., 0].max()),
              float(pos[..., 1].max())) if len(pos) else (0.0, 0.0, 0.0, 0.0)
    return TextQuads(pos, np.array(uvs, np.float64).reshape(-1, 4, 2), np.array(cps, np.int64), bounds, missing)
