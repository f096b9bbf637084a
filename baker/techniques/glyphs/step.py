"""Wire the glyph kernels to files: a font -> an atlas (PNG + JSON), and text -> a glTF label.

Used by the ``baker glyphs`` and ``baker text`` commands (:mod:`baker.techniques.glyphs.glyphs_command`, :mod:`baker.techniques.glyphs.text_command`).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from baker.techniques.glyphs.atlas import GlyphAtlas, bake_atlas
from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.layout import layout_text
from baker.techniques.glyphs.outline import load_font
from baker.errors import BakerError
from baker.techniques.glyphs import extension as ext
from baker.gltf.atomic import write_files_atomic
from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image


def font_atlas(font_path, options: GlyphOptions, charset=None, warn=True) -> GlyphAtlas:
    """Read the font and bake its atlas; characters without a glyph are reported on stderr (``warn``)."""
    font = load_font(font_path, options.charset if charset is None else charset, font_number=options.font_number,
                     instance=options.instance, kerning=options.kerning)
    if not font.glyphs:  # before the warning: a failed run says one line
        shown = ", ".join(f"U+{c:04X}" for c in font.missing[:5]) + (" ..." if len(font.missing) > 5 else "")
        raise BakerError(font_path, f"none of the {len(font.missing)} requested characters has a glyph in this font "
                                    f"({shown})")
    if font.missing and warn:
        listed = ", ".join(f"U+{c:04X}" for c in font.missing[:20]) + (" ..." if len(font.missing) > 20 else "")
        print(f"baker: warning: {font_path}: {len(font.missing)} character(s) have no glyph: {listed}",
              file=sys.stderr)
    return bake_atlas(font, options)


def write_atlas_files(atlas: GlyphAtlas, basename, fmt: str = "msdf-atlas-gen") -> tuple[Path, Path]:
    """Write ``<basename>.png`` and ``<basename>.json`` (msdf-atlas-gen layout, or BMFont JSON) atomically."""
    base = Path(basename)
    png = base.with_name(base.name + ".png")
    meta = base.with_name(base.name + ".json")
    if fmt == "bmfont":
        layout = atlas.bmfont_json(png.name)
    elif fmt == "msdf-atlas-gen":
        layout = atlas.layout_json()
    else:
        raise BakerError(None, f"unknown metrics format {fmt!r} (use msdf-atlas-gen or bmfont)")
    # one atomic group: a failed or killed run keeps the earlier pair, never a new image beside old metrics
    write_files_atomic([(png, encode_image(atlas.image, ".png")),
                        (meta, (json.dumps(layout, indent=1, ensure_ascii=False) + "\n").encode("utf-8"))])
    return png, meta


def text_document(text: str, atlas: GlyphAtlas, *, em_size: float = 1.0, align: str = "left",
                  color=(1.0, 1.0, 1.0, 1.0), outline_width: float = 0.0, outline_color=(0.0, 0.0, 0.0, 1.0),
                  line_spacing: float = 1.0) -> tuple[GltfDocument, list]:
    """A new glTF document holding the atlas (BAKER_glyph_atlas) and one node drawing ``text`` (BAKER_text + plain
    quads). Returns the document and the characters the atlas lacks."""
    quads = layout_text(text, atlas, align=align, line_spacing=line_spacing)
    doc = GltfDocument()
    font = ext.write_glyph_atlas(doc, atlas)
    node = ext.write_text_node(doc, atlas, quads, text=text, font=font, em_size=em_size, align=align, color=color,
                               outline_width=outline_width, outline_color=outline_color, line_spacing=line_spacing)
    doc.json["scenes"] = [{"nodes": [node]}]
    doc.json["scene"] = 0
    return doc, quads.missing
