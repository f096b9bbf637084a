"""The compiled outline reader (HarfBuzz's draw API, ``OutlineReader``) against fontTools' segment pen, glyph by
glyph: the same segments (degree and every control point, exactly), in the same contours and order, for every glyph
of a TrueType font (quadratic; composites, one-point contours and contours starting off-curve included), a CFF font
(cubic) and a variable font at its default and at an interpolated location."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from baker.techniques.glyphs.harfbuzz_outline import HarfBuzzOutlines
from baker.techniques.glyphs.outline import OutlineReader, glyph_shape, load_fonts, open_font

DEJAVU = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
CANTARELL = Path("/usr/share/fonts/opentype/cantarell/Cantarell-Regular.otf")  # CFF (scripts/test installs it)


def same_segments(a, b) -> bool:
    return (a.points.shape == b.points.shape and np.array_equal(a.degree, b.degree)
            and np.array_equal(a.contour_start, b.contour_start) and np.array_equal(a.points, b.points))


def differing_glyphs(path, location=None) -> tuple[list, int]:
    """(glyph names whose outlines differ between the reader and fontTools' pen, glyphs compared)."""
    font, glyph_set = open_font(path)
    if location:
        glyph_set = font.getGlyphSet(location=location)
    reader = OutlineReader(font, glyph_set, path, 0, location)
    order = font.getGlyphOrder()
    return [name for gid, name in enumerate(order)
            if not same_segments(reader.shape(name, gid), glyph_shape(glyph_set, name))], len(order)


@pytest.mark.parametrize("path", [DEJAVU, CANTARELL], ids=["truetype", "cff"])
def test_every_glyph_has_fonttools_segments(path):
    assert path.is_file(), f"{path} missing (scripts/test installs it)"
    bad, count = differing_glyphs(path)
    assert count > 1000 and not bad, bad[:10]


def test_harfbuzz_draws_cff_itself():
    """Not a fallback in disguise: HarfBuzz alone gives fontTools' cubic segments for every drawn CFF glyph."""
    font, glyph_set = open_font(CANTARELL)
    outlines = HarfBuzzOutlines(CANTARELL)
    drawn = 0
    for gid, name in enumerate(font.getGlyphOrder()):
        shape = outlines.shape(gid)
        if shape is not None:
            drawn += 1
            assert same_segments(shape, glyph_shape(glyph_set, name)), name
            assert set(shape.degree.tolist()) <= {1, 3}
    assert drawn > 1000


@pytest.fixture(scope="module")
def variable_font(tmp_path_factory):
    """A TrueType variable font (one axis, wght 100..900, default 400) made of DejaVu Sans glyphs whose points move
    with the axis by different amounts per point (gvar deltas), so an interpolated location has fractional points."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.ttLib import TTFont
    from fontTools.ttLib.tables.TupleVariation import TupleVariation

    source = TTFont(str(DEJAVU))
    names = [".notdef", "O", "a", "i", "H", "s"]
    glyf = source["glyf"]
    glyphs = {n: glyf[n] for n in names}
    for n in names:
        glyphs[n].expand(glyf)
    fb = FontBuilder(source["head"].unitsPerEm, isTTF=True)
    fb.setupGlyphOrder(names)
    fb.setupCharacterMap({ord(n): n for n in names if len(n) == 1})
    fb.setupGlyf(glyphs)
    fb.setupHorizontalMetrics({n: (source["hmtx"][n][0], glyphs[n].xMin if glyphs[n].numberOfContours else 0)
                               for n in names})
    fb.setupHorizontalHeader(ascent=1900, descent=-500)
    fb.setupNameTable({"familyName": "Var", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    fb.setupFvar([("wght", 100, 400, 900, "Weight")], [])
    variations = {}
    for n in names:
        count = len(glyphs[n].coordinates) if glyphs[n].numberOfContours > 0 else 0
        deltas = [((7 * k) % 23 + 3, (11 * k) % 17 - 5) for k in range(count)] + [(0, 0)] * 4  # + phantom points
        variations[n] = [TupleVariation({"wght": (0.0, 1.0, 1.0)}, deltas)]
    fb.setupGvar(variations)
    path = tmp_path_factory.mktemp("var") / "var.ttf"
    fb.save(str(path))
    return path


def test_variable_font_default_and_interpolated(variable_font):
    bad, count = differing_glyphs(variable_font)
    assert count == 6 and not bad, bad
    location = {"wght": 712.5}
    bad, _ = differing_glyphs(variable_font, location)
    assert not bad, bad
    # the location moves the points (fractionally), and HarfBuzz' own interpolation lands on fontTools' points up to
    # float rounding: the reader still takes fontTools' doubles there, so atlases keep their bytes
    font, _ = open_font(variable_font)
    moved = font.getGlyphSet(location=location)
    outlines = HarfBuzzOutlines(variable_font, 0, location)
    gid = font.getGlyphID("O")
    ours, theirs = outlines.shape(gid), glyph_shape(moved, "O")
    default = glyph_shape(font.getGlyphSet(), "O")
    assert np.array_equal(ours.degree, theirs.degree)
    assert np.abs(theirs.points - default.points).max() > 1.0
    assert np.any(theirs.points % 1.0 != 0.0)
    assert np.abs(ours.points - theirs.points).max() < 1e-3


def test_fallback_fonts_are_scaled_like_fonttools():
    """load_fonts scales a fallback face's outlines to the first face's units per em: same floats as fontTools'."""
    cjk = Path("/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc")
    assert cjk.is_file(), "fonts-noto-cjk missing (scripts/test installs it)"
    font = load_fonts([(str(DEJAVU), 0), (str(cjk), 2)], "str:A你好")
    assert [g.face for g in font.glyphs] == [0, 1, 1]
    cff, glyph_set = open_font(cjk, 2)
    scale = 2048 / 1000
    for g in font.glyphs[1:]:
        assert same_segments(g.shape, glyph_shape(glyph_set, g.name, scale)), g.name
