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


def options_from(args, **overrides) -> GlyphOptions:
    try:
        options = from_args(GlyphOptions, PREFIX, args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    return dataclasses.replace(options, **overrides) if overrides else options


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("glyphs", help="bake an SDF/PSDF/MSDF/MTSDF glyph atlas (PNG + JSON) from a font")
    p.add_argument("font", help="TrueType/OpenType font (.ttf .otf .ttc)")
    p.add_argument("-o", "--output", required=True, help="output basename: writes OUT.png and OUT.json")
    p.add_argument("--format", choices=("msdf-atlas-gen", "bmfont"), default="msdf-atlas-gen",
                   help="metrics JSON layout (default: msdf-atlas-gen)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    add_option_flags(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from baker.techniques.glyphs.step import font_atlas, write_atlas_files

    options = options_from(args)
    atlas = font_atlas(args.font, options)
    png, meta = write_atlas_files(atlas, args.output, args.format)
    if not args.quiet:
        drawn = sum(g.atlas is not None for g in atlas.glyphs)
        print(f"baked {len(atlas.glyphs)} glyphs ({drawn} with outlines) as {options.type}, {atlas.width} x "
              f"{atlas.height} -> {png}, {meta}", file=sys.stderr)
    return 0
