"""``baker glyphs FONT -o OUT_BASENAME`` (a glyph atlas PNG and its metrics JSON, msdf-atlas-gen layout or BMFont,
from a TrueType/OpenType font) and ``baker text "Hello" --font F -o label.glb`` (a glTF label drawn from a baked
atlas): the parsers; the work is :func:`baker.techniques.glyphs.step.run_glyphs` and
:func:`~baker.techniques.glyphs.step.run_text`, imported when it runs. Options come from
:class:`~baker.techniques.glyphs.options.GlyphOptions`."""
from __future__ import annotations

from baker.options import add_arguments
from baker.technique import lazy
from baker.techniques.glyphs.options import GlyphOptions

PREFIX = "glyphs"


def add_parser(subparsers) -> None:
    add_glyphs_parser(subparsers)
    add_text_parser(subparsers)


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


def add_glyphs_parser(subparsers) -> None:
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
    p.set_defaults(func=lazy("baker.techniques.glyphs.step:run_glyphs"))


def add_text_parser(subparsers) -> None:
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
    p.set_defaults(func=lazy("baker.techniques.glyphs.step:run_text"))
