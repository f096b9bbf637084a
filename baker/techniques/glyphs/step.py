"""Wire the glyph kernel to files: a font -> an atlas (PNG + JSON), and text -> a glTF label; the work of the
``baker glyphs`` (:func:`run_glyphs`) and ``baker text`` (:func:`run_text`) commands, whose parsers are in
:mod:`baker.techniques.glyphs.command`.
"""
from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

from baker.techniques.glyphs.atlas import GlyphAtlas
from baker.techniques.glyphs.command import PREFIX
from baker.techniques.glyphs.kernel import bake_atlas
from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.layout import layout_text, quads_of_shaped
from baker.techniques.glyphs.outline import face_metrics, load_fonts, variation_location
from baker.techniques.glyphs.shaping import face_source, open_faces, parse_features, shape_text
from baker.errors import BakerError
from baker.readers.sniff import check_input, describe, identify
from baker.options import from_args
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


# ---------------------------------------------------------------------------------------------------- commands
def shaping_options(args) -> dict:
    """The shaping flags of ``baker text`` / ``baker glyphs --text-file`` as :func:`shape` keywords."""
    return {"direction": args.direction, "script": args.script, "language": args.language,
            "features": parse_features(args.features)}


def options_from(args, **overrides) -> GlyphOptions:
    """The glyph options of the parsed flags (``overrides`` replacing some); a bad value is a BakerError."""
    try:
        options = from_args(GlyphOptions, PREFIX, args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    return dataclasses.replace(options, **overrides) if overrides else options


def parse_glyph_ids(spec: str) -> list:
    """``gid:3,17-20`` -> [(0, 3), (0, 17), ..., (0, 20)] (glyph ids of the first font)."""
    if not spec.startswith("gid:"):
        raise BakerError(None, f"bad --glyphs {spec!r} (use gid:LIST, e.g. gid:3,17-20)")
    ids = []
    for item in (x.strip() for x in spec[4:].split(",")):
        if not item:
            continue
        lo, sep, hi = item.partition("-")
        if not lo.isdigit() or (sep and not hi.isdigit()) or (sep and int(hi) < int(lo)):
            raise BakerError(None, f"bad glyph id range {item!r} in --glyphs (use gid:3,17-20)")
        ids.extend((0, g) for g in range(int(lo), int(hi if sep else lo) + 1))
    if not ids:
        raise BakerError(None, "--glyphs names no glyph id")
    return ids


def parse_color(text: str) -> tuple:
    try:
        parts = [float(v) for v in text.split(",")]
    except ValueError:
        raise BakerError(None, f"bad color {text!r} (use r,g,b or r,g,b,a in 0..1)") from None
    if len(parts) == 3:
        parts.append(1.0)
    if len(parts) != 4 or any(not 0.0 <= v <= 1.0 for v in parts):
        raise BakerError(None, f"bad color {text!r} (use r,g,b or r,g,b,a in 0..1)")
    return tuple(parts)


def run_glyphs(args) -> int:
    """``baker glyphs FONT -o OUT``: the atlas of the fonts' charset, glyph ids and shaped text file, as PNG + JSON."""
    options = options_from(args)
    fonts = ([args.font] if args.font else []) + list(args.fallback_fonts)
    glyph_ids = parse_glyph_ids(args.glyph_ids) if args.glyph_ids else []
    if args.text_file:
        head = check_input(args.text_file, None, "a UTF-8 text file")  # a directory, a FIFO, a PNG: one line
        if identify(head) not in ("text", "json"):
            raise BakerError(args.text_file, f"{describe(identify(head))}, not a UTF-8 text file")
        try:
            text = Path(args.text_file).read_text("utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise BakerError(args.text_file, f"cannot read the text file: {exc}") from None
        shaped = shape(text, fonts, options, **shaping_options(args))
        if shaped.missing and not args.quiet:
            print(f"baker: warning: {args.text_file}: {len(shaped.missing)} character(s) in no font: "
                  f"{''.join(shaped.missing[:20])!r}", file=sys.stderr)
        glyph_ids += shaped_glyph_ids(shaped)
    # a charset flag given with glyph ids adds those characters; the default charset only applies without them
    charset = options.charset if (not glyph_ids or args.glyphs__charset is not None) else None
    atlas = font_atlas(fonts, options, charset=charset, glyph_ids=glyph_ids)
    if args.format == "bmfont" and len(atlas.codepoint_glyphs()) < len(atlas.glyphs) and not args.quiet:
        print(f"baker: warning: BMFont has no place for {len(atlas.glyphs) - len(atlas.codepoint_glyphs())} glyph(s) "
              "without a code point (ligatures, contextual forms): left out of the JSON", file=sys.stderr)
    png, meta = write_atlas_files(atlas, args.output, args.format)
    if not args.quiet:
        drawn = sum(g.atlas is not None for g in atlas.glyphs)
        print(f"baked {len(atlas.glyphs)} glyphs ({drawn} with outlines) as {options.type}, {atlas.width} x "
              f"{atlas.height} -> {png}, {meta}", file=sys.stderr)
    return 0


def run_text(args) -> int:
    """``baker text "TEXT" --font F -o OUT``: the text shaped, its glyphs baked, the label written as glTF."""
    text = args.text.replace("\\n", "\n")
    if Path(args.output).suffix.lower() not in (".glb", ".gltf"):
        raise BakerError(args.output, "output must end in .glb or .gltf")
    if args.em_size <= 0:
        raise BakerError(None, "--em-size must be > 0")
    if args.line_spacing <= 0:
        raise BakerError(None, "--line-spacing must be > 0")
    options = options_from(args)
    shaping = shaping_options(args)
    shaped = shape(text, args.font, options, max_width=args.max_width, align=args.align,
                   line_spacing=args.line_spacing, **shaping)
    glyph_ids = shaped_glyph_ids(shaped)
    if not glyph_ids and not args.glyphs__charset:
        chars = sorted(set(text) - {"\n"})
        if not chars:
            raise BakerError(None, "empty charset: the text has no characters to bake")
        shown = ", ".join(f"U+{ord(c):04X}" for c in chars[:5]) + (" ..." if len(chars) > 5 else "")
        raise BakerError(args.font[0] if len(args.font) == 1 else ", ".join(args.font),
                         f"none of the {len(chars)} requested characters has a glyph in "
                         f"{'this font' if len(args.font) == 1 else 'these fonts'} ({shown})")
    atlas = font_atlas(args.font, options, charset=options.charset if args.glyphs__charset else None,
                       glyph_ids=glyph_ids, warn=False)
    if shaped.missing:
        print(f"baker: warning: {len(shaped.missing)} character(s) of the text are in none of the fonts: "
              f"{''.join(shaped.missing[:20])!r}", file=sys.stderr)
    written = {k: v for k, v in shaping.items() if v}
    if args.features:
        written["features"] = args.features
    if args.max_width:
        written["maxWidth"] = float(args.max_width)
    doc, missing = text_document(text, atlas, em_size=args.em_size, align=args.align, color=parse_color(args.color),
                                 outline_width=args.outline_width, outline_color=parse_color(args.outline_color),
                                 line_spacing=args.line_spacing, shaped=shaped, shaping=written)
    doc.save(args.output)
    if not args.quiet:
        print(f"wrote {len(text)} characters as {len(shaped.glyphs)} shaped glyphs from {len(atlas.font.faces)} "
              f"font(s) ({options.type}, atlas {atlas.width} x {atlas.height}, {len(atlas.glyphs)} glyphs) -> "
              f"{args.output}", file=sys.stderr)
    return 0
