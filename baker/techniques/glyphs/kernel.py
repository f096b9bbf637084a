"""Glyph atlases: exact SDF, pseudo-SDF, MSDF and MTSDF from font outlines (RTR4 15.5; Green 2007; Chlumsky 2015).

One small module per step, in pipeline order:

- :mod:`.outline`     font file -> glyph outlines (lines, quadratic and cubic Beziers), metrics, kerning, charsets
- :mod:`.shape`       outline arrays: normalization, nonzero-rule orientation, y-monotone pieces, winding numbers
- :mod:`.segments`    exact distance from a point to a line or Bezier; pseudo-distance; splitting
- :mod:`.coloring`    MSDF edge coloring (notch, ink-trap, simple and by-distance strategies)
- :mod:`.sdf`         the distance kernel: true signed distance and per-channel pseudo-distances per texel
- :mod:`.msdf`        field types (sdf, psdf, msdf, mtsdf), sign correction
- :mod:`.correction`  MSDF error correction
- :mod:`.atlas`       boxes, packing, the baked atlas, msdf-atlas-gen and BMFont metrics
- :mod:`.quality`     the quality metric: magnified median render vs an exact nonzero rasterization
- :mod:`.layout`      text layout with advances and kerning (quads for ``baker text``)
"""
from __future__ import annotations

from baker.techniques.glyphs.atlas import GlyphAtlas, GlyphEntry, bake_atlas
from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.outline import Font, load_font, parse_charset

__all__ = ["GlyphAtlas", "GlyphEntry", "GlyphOptions", "bake_atlas", "Font", "load_font", "parse_charset"]
