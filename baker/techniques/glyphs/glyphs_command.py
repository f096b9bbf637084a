"""``baker glyphs FONT -o OUT_BASENAME``: bake a glyph atlas (PNG) and its metrics (JSON, msdf-atlas-gen layout or
BMFont) from a TrueType/OpenType font. Options come from :class:`~baker.techniques.glyphs.options.GlyphOptions`."""
from __future__ import annotations

import dataclasses
import sys

from baker.techniques.glyphs.options import GlyphOptions
from baker.errors import BakerError
from baker.options import add_arguments, from_args

PREFIX = "glyphs"


def add_option_flags(parser, skip=()) -> None:
    """One ``--<name>`` flag per glyph option (no prefix: these commands have a single option set)."""
    add_arguments(parser, GlyphOptions, PREFIX, prefixed_flags=False, skip=skip)


def add_shaping_flags(parser) -> None:
    """HarfBuzz shaping flags (``baker text``, ``baker glyphs --text-file``)."""
    parser.add_argument("--script", default=None,
                        help="ISO 15924 script for every run, e.g. Latn, Arab, Hani (default: detected per run)")
    parser.add_argument("--direction", choices=("ltr", "rtl"), default=None,
                        help="paragraph direction (default: the first strong character's, Unicode bidi)")
    parser.add_argument("--language", default=None, help="BCP 47 language for the shaper, e.g. en, ar, zh-Hans")
    parser.add_argument("--features", default=None,
                        help="OpenType features, e.g. liga,kern,-calt,ss01=1 (default: the shaper's)")


def shaping_options(args) -> dict:
    from baker.techniques.glyphs.shaping import parse_features

    return {"direction": args.direction, "script": args.script, "language": args.language,
            "features": parse_features(args.features)}


def options_from(args, **overrides) -> GlyphOptions:
    try:
        options = from_args(GlyphOptions, PREFIX, args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    return dataclasses.replace(options, **overrides) if overrides else options


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("glyphs", help="bake an SDF/PSDF/MSDF/MTSDF glyph atlas (PNG + JSON) from a font")
    p.add_argument("font", nargs="?", default=None, help="TrueType/OpenType font (.ttf .otf .ttc; PATH#N: face N "
                                                         "of a collection)")
    p.add_argument("--font", dest="fallback_fonts", action="append", default=[], metavar="FONT",
                   help="a (further) font, repeatable: a glyph missing from the first comes from the next")
    p.add_argument("--glyphs", dest="glyph_ids", default=None, metavar="gid:LIST",
                   help="glyph ids of the first font to bake as well, e.g. gid:3,17-20 (written with their index)")
    p.add_argument("--text-file", default=None, metavar="PATH",
                   help="UTF-8 text: shape it (HarfBuzz) and bake every glyph it uses, ligatures and contextual "
                        "forms included (with --charset: those characters as well)")
    p.add_argument("-o", "--output", required=True, help="output basename: writes OUT.png and OUT.json")
    p.add_argument("--format", choices=("msdf-atlas-gen", "bmfont"), default="msdf-atlas-gen",
                   help="metrics JSON layout (default: msdf-atlas-gen)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_shaping_flags(p)
    add_option_flags(p)
    p.set_defaults(func=run)


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


def run(args) -> int:
    from pathlib import Path

    from baker.techniques.glyphs.step import font_atlas, shape, shaped_glyph_ids, write_atlas_files

    options = options_from(args)
    fonts = ([args.font] if args.font else []) + list(args.fallback_fonts)
    glyph_ids = parse_glyph_ids(args.glyph_ids) if args.glyph_ids else []
    if args.text_file:
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
