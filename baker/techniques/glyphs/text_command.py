"""``baker text "Hello" --font F -o label.glb``: a glTF label drawn from a baked glyph atlas.

The output holds the atlas (``BAKER_glyph_atlas`` on the root), a node with ``BAKER_text`` and, for viewers that know
neither, plain quads with an alpha-tested distance-field texture (see :mod:`baker.techniques.glyphs.extension`).
"""
from __future__ import annotations

import sys
from pathlib import Path

from baker.errors import BakerError
from baker.techniques.glyphs.glyphs_command import add_option_flags, add_shaping_flags, options_from, shaping_options


def _color(text: str) -> tuple:
    try:
        parts = [float(v) for v in text.split(",")]
    except ValueError:
        raise BakerError(None, f"bad color {text!r} (use r,g,b or r,g,b,a in 0..1)") from None
    if len(parts) == 3:
        parts.append(1.0)
    if len(parts) != 4 or any(not 0.0 <= v <= 1.0 for v in parts):
        raise BakerError(None, f"bad color {text!r} (use r,g,b or r,g,b,a in 0..1)")
    return tuple(parts)


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("text", help="write a glTF label: BAKER_text + BAKER_glyph_atlas + plain quads")
    p.add_argument("text", help="the text (\\n starts a new line)")
    p.add_argument("--font", required=True, action="append", metavar="FONT",
                   help="TrueType/OpenType font (.ttf .otf .ttc; PATH#N: face N of a collection); repeat it for "
                        "fallback fonts: a character missing from the first comes from the next that has it")
    p.add_argument("-o", "--output", required=True, help="output .glb or .gltf")
    p.add_argument("--em-size", type=float, default=1.0, help="size of one em in scene units (default: 1.0)")
    p.add_argument("--align", choices=("left", "center", "right"), default="left", help="line alignment")
    p.add_argument("--color", default="1,1,1,1", help="text color, linear r,g,b[,a] (default: 1,1,1,1)")
    p.add_argument("--outline-width", type=float, default=0.0, help="outline width in em (0: none)")
    p.add_argument("--outline-color", default="0,0,0,1", help="outline color r,g,b[,a]")
    p.add_argument("--line-spacing", type=float, default=1.0, help="line height as a multiple of the font's")
    p.add_argument("--max-width", type=float, default=None,
                   help="break lines at spaces so none is wider than this, em (default: only at \\n)")
    add_shaping_flags(p)
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_option_flags(p, skip=("charset",))
    p.add_argument("--charset", dest="glyphs__charset", default=None,
                   help="characters to bake (default: those of the text)")
    p.set_defaults(func=run)


def run(args) -> int:
    from baker.techniques.glyphs.step import font_atlas, shape, shaped_glyph_ids, text_document

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
    doc, missing = text_document(text, atlas, em_size=args.em_size, align=args.align, color=_color(args.color),
                                 outline_width=args.outline_width, outline_color=_color(args.outline_color),
                                 line_spacing=args.line_spacing, shaped=shaped, shaping=written)
    doc.save(args.output)
    if not args.quiet:
        print(f"wrote {len(text)} characters as {len(shaped.glyphs)} shaped glyphs from {len(atlas.font.faces)} "
              f"font(s) ({options.type}, atlas {atlas.width} x {atlas.height}, {len(atlas.glyphs)} glyphs) -> "
              f"{args.output}", file=sys.stderr)
    return 0
