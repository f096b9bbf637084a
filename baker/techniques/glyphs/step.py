"""Wire the glyph kernels to files: a font -> an atlas (PNG + JSON), and text -> a glTF label.

Used by the ``baker glyphs`` and ``baker text`` commands (:mod:`baker.techniques.glyphs.glyphs_command`, :mod:`baker.techniques.glyphs.text_command`).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from baker.techniques.glyphs.atlas import GlyphAtlas, bake_atlas
from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.layout import layout_text, quads_of_shaped
from baker.techniques.glyphs.outline import face_metrics, load_fonts, variation_location
from baker.techniques.glyphs.shaping import face_source, open_faces, shape_text
from baker.errors import BakerError
from baker.techniques.glyphs import extension as ext
from baker.gltf.atomic import write_files_atomic
from baker.gltf.document import GltfDocument
from baker.gltf.images import encode_image


def font_sources(fonts, options: GlyphOptions) -> list:
    """The fallback list: ``fonts`` (a path or paths, ``PATH#N`` = face N of a collection; ``--font-number`` is the
    face of collections given without one) -> [FaceSource]."""
    fonts = [fonts] if isinstance(fonts, (str, Path)) else list(fonts)
    if not fonts:
        raise BakerError(None, "no font given (use --font FILE, repeated for fallback fonts)")
    return [face_source(str(f), options.font_number) for f in fonts]


def font_atlas(fonts, options: GlyphOptions, charset=None, warn=True, glyph_ids=()) -> GlyphAtlas:
    """Read the fonts (one path, or a fallback list: each code point from the first font that has it) and bake
    their atlas; characters without a glyph in any font are reported on stderr (``warn``). ``glyph_ids``:
    [(font, glyph id)] baked as well (shaped text); ``charset`` None with glyph ids: only those."""
    sources = font_sources(fonts, options)
    charset = (None if glyph_ids else options.charset) if charset is None else charset
    font = load_fonts([(s.path, s.face_index) for s in sources], charset, glyph_ids, instance=options.instance,
                      kerning=options.kerning)
    where = sources[0].path if len(sources) == 1 else ", ".join(s.path for s in sources)
    if not font.glyphs:  # before the warning: a failed run says one line
        shown = ", ".join(f"U+{c:04X}" for c in font.missing[:5]) + (" ..." if len(font.missing) > 5 else "")
        raise BakerError(where, f"none of the {len(font.missing)} requested characters has a glyph in "
                                f"{'this font' if len(sources) == 1 else 'these fonts'} ({shown})")
    if font.missing and warn:
        listed = ", ".join(f"U+{c:04X}" for c in font.missing[:20]) + (" ..." if len(font.missing) > 20 else "")
        print(f"baker: warning: {where}: {len(font.missing)} character(s) have no glyph: {listed}",
              file=sys.stderr)
    return bake_atlas(font, options)


def shape(text: str, fonts, options: GlyphOptions, *, direction=None, script=None, language=None, features=None,
          max_width=None, align="left", line_spacing=1.0):
    """Shape ``text`` with the fallback list (HarfBuzz, :mod:`.shaping`), lines stacked by the first font's line
    height times ``line_spacing``; returns the :class:`~baker.techniques.glyphs.shaping.ShapedText`."""
    sources = font_sources(fonts, options)
    first = sources[0]
    metrics = face_metrics(first.path, first.face_index)
    faces = open_faces(sources, variation_location(first.path, first.face_index, options.instance))
    return shape_text(text, faces, direction=direction, script=script, language=language, features=features,
                      max_width=max_width, align=align,
                      line_height=metrics.line_height / metrics.units_per_em * line_spacing)


def shaped_glyph_ids(shaped) -> list:
    """The (font, glyph id) pairs a shaped text draws (.notdef left out), sorted."""
    return sorted({(g.face, g.glyph_id) for g in shaped.glyphs if g.glyph_id != 0})


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
                  line_spacing: float = 1.0, shaped=None, shaping: dict | None = None) -> tuple[GltfDocument, list]:
    """A new glTF document holding the atlas (BAKER_glyph_atlas) and one node drawing ``text`` (BAKER_text + plain
    quads). ``shaped``: the text shaped by :func:`shape` (its glyphs in the atlas; BAKER_text then carries them),
    else laid out by code point. Returns the document and the characters the fonts lack."""
    if shaped is not None:
        quads = quads_of_shaped(shaped, atlas)
    else:
        quads = layout_text(text, atlas, align=align, line_spacing=line_spacing)
    doc = GltfDocument()
    font = ext.write_glyph_atlas(doc, atlas)
    node = ext.write_text_node(doc, atlas, quads, text=text, font=font, em_size=em_size, align=align, color=color,
                               outline_width=outline_width, outline_color=outline_color, line_spacing=line_spacing,
                               shaping=shaping)
    doc.json["scenes"] = [{"nodes": [node]}]
    doc.json["scene"] = 0
    return doc, quads.missing
