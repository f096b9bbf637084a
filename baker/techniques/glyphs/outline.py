"""Fonts -> glyph outlines (HarfBuzz's draw API where it gives fontTools' segments, see :class:`OutlineReader`),
metrics and kerning (fontTools).

Reads TrueType/OpenType (``.ttf .otf``, quadratic or cubic outlines), collections (``.ttc``, by ``font_number``) and
named instances of variable fonts (``instance``: the instance's subfamily name, e.g. "Bold Condensed", or axis
values such as ``wght=700,wdth=75``). Outlines come out as :class:`~baker.techniques.glyphs.shape.Shape` in font units
(y up); metrics as the font declares them (``hhea``, ``post``); kerning from GPOS pair adjustment (``kern``
feature, formats 1 and 2, extension lookups included) or, when a font has no GPOS kerning, from the legacy ``kern``
table (format 0).

Charsets (see :func:`parse_charset`): ``ascii`` (0x20-0x7E, the default), ``latin1``, code-point ranges and single
code points (``0x20-0x7E,0xA0-0xFF,U+20AC,65``), ``str:TEXT`` (the characters of TEXT) or ``file:PATH`` (the
characters of a UTF-8 text file). Code points the font has no glyph for are reported in ``Font.missing``, never
silently dropped.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.readers.sniff import check_input
from baker.techniques.glyphs.shape import Shape, from_contours

ASCII = tuple(range(0x20, 0x7F))
LATIN1 = tuple(range(0x20, 0x7F)) + tuple(range(0xA0, 0x100))


@dataclass(frozen=True)
class FontMetrics:
    """Font-wide metrics in font units (y up, baseline at 0)."""

    units_per_em: int
    ascender: float
    descender: float  # negative below the baseline
    line_height: float  # ascender - descender + line gap
    underline_y: float  # centre of the underline stroke
    underline_thickness: float


@dataclass
class Glyph:
    """One glyph: its code point (-1: a glyph no code point maps to, e.g. a ligature), glyph name and id in its
    face, advance (font units of the first face) and outline (same units), and its face in the fallback list."""

    codepoint: int
    name: str
    index: int
    advance: float
    shape: Shape
    face: int = 0


@dataclass(frozen=True)
class FaceInfo:
    """One font of an atlas' fallback list: the file (its name only leaves baker), face index, family, units/em."""

    path: str
    face_index: int
    family: str
    units_per_em: int


@dataclass
class Font:
    path: str
    family: str
    metrics: FontMetrics
    glyphs: list  # [Glyph], in charset order
    kerning: dict = field(default_factory=dict)  # (codepoint1, codepoint2) -> advance adjustment, font units
    missing: list = field(default_factory=list)  # code points of the charset the font has no glyph for
    faces: list = field(default_factory=list)  # [FaceInfo] the fallback list (one entry for a single font)


# ---------------------------------------------------------------------------------------------------- charsets
def parse_charset(spec: str | None) -> list[int]:
    """Code points from a charset spec (see the module docstring), in order, without duplicates."""
    spec = "ascii" if spec is None else spec
    if spec.startswith("str:"):
        points = [ord(c) for c in spec[4:]]
    elif spec.startswith("file:"):
        path = Path(spec[5:])
        try:
            text = path.read_text("utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise BakerError(path, f"cannot read charset file: {exc}") from None
        points = [ord(c) for c in text if ord(c) >= 0x20 and c not in "\u2028\u2029"]
    else:
        points = []
        for item in (s.strip() for s in spec.split(",")):
            if not item:
                continue
            low = item.lower()
            if low == "ascii":
                points.extend(ASCII)
                continue
            if low == "latin1":
                points.extend(LATIN1)
                continue
            m = re.fullmatch(r"((?:0x|u\+)?[0-9a-f]+)(?:\s*-\s*((?:0x|u\+)?[0-9a-f]+))?", low)
            if not m:
                raise BakerError(None, f"bad charset item {item!r} (use ascii, latin1, 0x20-0x7E, U+00E9, 65, "
                                       "str:TEXT or file:PATH)")
            lo = _codepoint(m.group(1))
            hi = _codepoint(m.group(2)) if m.group(2) else lo
            if hi < lo or hi > 0x10FFFF:
                raise BakerError(None, f"bad charset range {item!r}")
            points.extend(range(lo, hi + 1))
    seen, out = set(), []
    for p in points:
        if p not in seen:
            seen.add(p)
            out.append(p)
    return out


def _codepoint(text: str) -> int:
    if text.startswith(("0x", "u+")):
        return int(text[2:], 16)
    return int(text, 10)


# ---------------------------------------------------------------------------------------------------- loading
def open_font(path, font_number: int = 0, instance: str | None = None):
    """(TTFont, glyph set) for a font file, at the named instance of a variable font if asked."""
    from fontTools.ttLib import TTFont, TTLibError

    path = Path(path)
    check_input(path, "font")  # a directory, a named pipe, a PNG: one line saying what it is
    try:
        font = TTFont(str(path), fontNumber=font_number, lazy=True)
        font["head"]
    except (TTLibError, OSError, KeyError, AssertionError, Exception) as exc:  # fontTools raises many kinds
        raise BakerError(path, f"not a readable TrueType/OpenType font: {exc}") from None
    location = None
    if instance:
        location = _instance_location(font, instance, path)
    try:
        glyph_set = font.getGlyphSet(location=location) if location else font.getGlyphSet()
    except Exception as exc:  # noqa: BLE001 (a truncated glyf/CFF table fails here, as TTLibError, struct.error, ...)
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise BakerError(path, f"damaged or truncated font: {detail}") from None
    return font, glyph_set


def _instance_location(font, instance: str, path) -> dict:
    if "fvar" not in font:
        raise BakerError(path, f"instance {instance!r} asked for, but this is not a variable font")
    fvar = font["fvar"]
    if "=" in instance:
        axes = {a.axisTag for a in fvar.axes}
        loc = {}
        for part in instance.split(","):
            tag, _, value = part.partition("=")
            tag = tag.strip()
            if tag not in axes:
                raise BakerError(path, f"unknown axis {tag!r} (axes: {', '.join(sorted(axes))})")
            loc[tag] = float(value)
        return loc
    names = []
    for inst in fvar.instances:
        name = font["name"].getDebugName(inst.subfamilyNameID) or ""
        names.append(name)
        if name.lower() == instance.lower():
            return dict(inst.coordinates)
    raise BakerError(path, f"no named instance {instance!r} (instances: {', '.join(names)})")


def variation_location(path, font_number: int = 0, instance: str | None = None) -> dict:
    """Axis values ({tag: value}) of a variable font's named instance or ``axis=value,...`` string ({}: none)."""
    if not instance:
        return {}
    font, _ = open_font(path, font_number)
    return _instance_location(font, instance, path)


def face_metrics(path, font_number: int = 0) -> FontMetrics:
    """The metrics of one face (font units), without reading any glyph."""
    font, _ = open_font(path, font_number)
    return font_metrics(font)


def font_metrics(font) -> FontMetrics:
    upem = int(font["head"].unitsPerEm)
    hhea = font["hhea"]
    ascender, descender, gap = float(hhea.ascent), float(hhea.descent), float(hhea.lineGap)
    if ascender == 0 and descender == 0 and "OS/2" in font:  # as FreeType: fall back to the typo metrics
        os2 = font["OS/2"]
        ascender, descender, gap = float(os2.sTypoAscender), float(os2.sTypoDescender), float(os2.sTypoLineGap)
    post = font["post"] if "post" in font else None
    thickness = float(post.underlineThickness) if post else upem / 20.0
    # post.underlinePosition is the top of the stroke; report its centre (as FreeType does)
    underline = float(post.underlinePosition) - thickness / 2.0 if post else -upem / 10.0
    return FontMetrics(upem, ascender, descender, ascender - descender + gap, underline, thickness)


class _OutlinePen:
    """A fontTools segment pen collecting (degree, control points) per contour; components are decomposed."""

    def __init__(self, glyph_set):
        from fontTools.pens.basePen import BasePen

        outer = self

        class Pen(BasePen):
            def _moveTo(self, pt):
                outer._close()
                outer.start = outer.current = pt

            def _lineTo(self, pt):
                outer._add(1, [outer.current, pt])

            def _qCurveToOne(self, pt1, pt2):
                outer._add(2, [outer.current, pt1, pt2])

            def _curveToOne(self, pt1, pt2, pt3):
                outer._add(3, [outer.current, pt1, pt2, pt3])

            def _closePath(self):
                outer._close()

            def _endPath(self):
                outer._close()  # open contours are closed: the fill rule closes them anyway

        self.pen = Pen(glyph_set)
        self.contours: list = []
        self.segments: list = []
        self.start = self.current = None

    def _add(self, degree, points):
        self.segments.append((degree, [tuple(map(float, p)) for p in points]))
        self.current = points[-1]

    def _close(self):
        if self.segments:
            if tuple(map(float, self.current)) != tuple(map(float, self.start)):
                self._add(1, [self.current, self.start])
            self.contours.append(self.segments)
        self.segments = []
        self.current = self.start


def glyph_shape(glyph_set, name: str, scale: float = 1.0) -> Shape:
    """The outline of glyph ``name`` in font units (times ``scale``)."""
    pen = _OutlinePen(glyph_set)
    glyph_set[name].draw(pen.pen)
    pen._close()
    contours = pen.contours
    if scale != 1.0:
        contours = [[(d, [(x * scale, y * scale) for x, y in pts]) for d, pts in c] for c in contours]
    return from_contours(contours)


class OutlineReader:
    """Glyph outlines of one opened face: HarfBuzz's compiled interpreters (:mod:`.harfbuzz_outline`) wherever they
    give exactly the segments fontTools' pen gives, fontTools' pen elsewhere.

    CFF outlines (the slow case: fontTools interprets charstrings in Python) always come from HarfBuzz. TrueType
    glyphs come from HarfBuzz when they are simple glyphs whose contours start on an on-curve point and whose
    ``hmtx`` left side bearing equals their ``xMin``: fontTools starts a contour at its first on-curve point and
    shifts a glyph by ``lsb - xMin`` (as FreeType does), HarfBuzz does neither; composites (component offsets and
    rounding flags) stay with fontTools. A variable font at a location other than its default also stays with
    fontTools (HarfBuzz interpolates in C floats, fontTools in doubles: the last bits may differ).
    """

    def __init__(self, font, glyph_set, path, face_index: int = 0, location: dict | None = None):
        from baker.techniques.glyphs.harfbuzz_outline import HarfBuzzOutlines

        self.glyph_set = glyph_set
        self.glyf = font["glyf"] if "glyf" in font else None
        self.hmtx = font["hmtx"] if self.glyf is not None and "hmtx" in font else None
        cff = "CFF " in font or "CFF2" in font
        usable = (self.glyf is not None and self.hmtx is not None) or cff
        self.harfbuzz = HarfBuzzOutlines(path, face_index) if usable and not location else None

    def shape(self, name: str, glyph_id: int, scale: float = 1.0) -> Shape:
        """The outline of glyph ``name`` (id ``glyph_id``) in font units, times ``scale``."""
        if self.harfbuzz is not None:
            single, count = self._single_point_contours(name) if self.glyf is not None else ((), None)
            if single is not None:
                shape = self.harfbuzz.shape(glyph_id, scale, drop_contours=single, contours=count)
                if shape is not None:
                    return shape
        # fontTools: what HarfBuzz does not draw the same way, and glyphs HarfBuzz drew nothing for (empty glyphs,
        # or a table HarfBuzz's sanitizer rejected: fontTools then raises the damaged-font error)
        return glyph_shape(self.glyph_set, name, scale)

    def _single_point_contours(self, name: str):
        """For a TrueType glyph HarfBuzz draws as fontTools would: (the indices of its one-point contours (fontTools'
        pen draws nothing for them, HarfBuzz a zero-length line), its contour count); (None, 0) when fontTools must
        draw the glyph."""
        glyph = self.glyf[name]  # parsed by fontTools (arrays, no pen): raises on a damaged glyph
        if glyph.isComposite() or getattr(glyph, "numberOfContours", 0) <= 0:
            return None, 0
        if self.hmtx[name][1] != glyph.xMin:
            return None, 0
        ends = list(glyph.endPtsOfContours)
        starts = [0] + [e + 1 for e in ends[:-1]]
        flags = glyph.flags
        if any(not flags[s] & 1 for s in starts):
            return None, 0
        return tuple(k for k, (s, e) in enumerate(zip(starts, ends)) if s == e), len(ends)


def load_font(path, charset=None, *, font_number: int = 0, instance: str | None = None,
              kerning: bool = True) -> Font:
    """Read the glyphs of ``charset`` (a spec string or a list of code points) from a font file."""
    codepoints = parse_charset(charset) if charset is None or isinstance(charset, str) else list(charset)
    if not codepoints:
        raise BakerError(None, f"empty charset {charset!r}: no characters to bake")
    font, glyph_set = open_font(path, font_number, instance)
    try:
        # fontTools reads tables lazily: a truncated or damaged glyf, cmap, name or kerning table fails only here
        reader = OutlineReader(font, glyph_set, path, font_number,
                               _instance_location(font, instance, path) if instance else None)
        cmap = font.getBestCmap() or {}
        glyph_ids = {name: i for i, name in enumerate(font.getGlyphOrder())}
        glyphs, missing = [], []
        for cp in codepoints:
            name = cmap.get(cp)
            if name is None or name not in glyph_set:
                missing.append(cp)
                continue
            g = glyph_set[name]
            gid = glyph_ids.get(name, 0)
            glyphs.append(Glyph(cp, name, gid, float(g.width), reader.shape(name, gid)))
        family = _family(font, path)
        metrics = font_metrics(font)
        result = Font(str(path), family, metrics, glyphs, missing=missing,
                      faces=[FaceInfo(str(path), font_number, family, metrics.units_per_em)])
        if kerning and glyphs:
            result.kerning = kerning_pairs(font, [(g.codepoint, g.name) for g in glyphs])
    except BakerError:
        raise
    except Exception as exc:  # noqa: BLE001 (fontTools raises struct.error, TTLibError, IndexError, KeyError, ...)
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise BakerError(path, f"damaged or truncated font: {detail}") from None
    return result


def _family(font, path) -> str:
    return (font["name"].getDebugName(1) or Path(path).stem) if "name" in font else Path(path).stem


def load_fonts(sources: list, charset=None, glyph_ids=(), *, instance: str | None = None,
               kerning: bool = True) -> Font:
    """Glyphs from a fallback list of fonts, as one :class:`Font` in the first face's units.

    ``sources``: [(path, face index)]. ``charset`` (spec or code points): each code point comes from the first face
    whose cmap maps it (reported in ``missing`` when none does). ``glyph_ids``: [(face, glyph id)] wanted as well
    (shaped text: ligatures, contextual forms); such a glyph carries the code point its face maps to it when that
    face is the code point's first face (so code points stay unique), else -1. Outlines and advances of the other
    faces are scaled to the first face's units per em; kerning pairs are read per face among its own glyphs.
    ``instance`` applies to the first font (a variable font's named instance or axis values).
    """
    if not sources:
        raise BakerError(None, "no font given")
    codepoints = [] if charset is None and glyph_ids else (
        parse_charset(charset) if charset is None or isinstance(charset, str) else list(charset))
    if not codepoints and not glyph_ids:
        raise BakerError(None, f"empty charset {charset!r}: no characters to bake")
    opened, readers = [], []
    for k, (path, number) in enumerate(sources):
        font, glyph_set = open_font(path, number, instance if k == 0 else None)
        opened.append((path, number, font, glyph_set))
        location = _instance_location(font, instance, path) if instance and k == 0 else None
        readers.append(OutlineReader(font, glyph_set, path, number, location))
    glyphs, missing, taken, faces, cmaps, orders = [], [], set(), [], [], []
    upem0 = None
    try:
        for path, number, font, glyph_set in opened:
            metrics = font_metrics(font)
            upem0 = upem0 or metrics.units_per_em
            faces.append(FaceInfo(str(path), number, _family(font, path), metrics.units_per_em))
            cmaps.append(font.getBestCmap() or {})
            orders.append(font.getGlyphOrder())
        owner = {}  # code point -> its first face

        def owner_of(cp):
            if cp not in owner:
                owner[cp] = next((k for k, cmap in enumerate(cmaps) if cp in cmap and cmap[cp] in opened[k][3]), -1)
            return owner[cp]

        def add(face, gid, cp):
            if (face, gid) in taken:
                return
            taken.add((face, gid))
            _, _, font, glyph_set = opened[face]
            name = orders[face][gid]
            scale = upem0 / faces[face].units_per_em
            glyphs.append(Glyph(cp, name, gid, float(glyph_set[name].width) * scale,
                                readers[face].shape(name, gid, scale), face))

        for cp in codepoints:
            face = owner_of(cp)
            if face < 0:
                missing.append(cp)
                continue
            add(face, opened[face][2].getGlyphID(cmaps[face][cp]), cp)
        reverse = [None] * len(opened)
        for face, gid in sorted(set((int(f), int(g)) for f, g in glyph_ids)):
            if not 0 <= face < len(opened):
                raise BakerError(None, f"glyph ids of font {face} asked for, {len(opened)} font(s) given")
            if not 0 <= gid < len(orders[face]):
                raise BakerError(sources[face][0], f"glyph id {gid} does not exist (the font has "
                                                   f"{len(orders[face])} glyphs)")
            if reverse[face] is None:
                reverse[face] = {}
                for cp, name in sorted(cmaps[face].items()):
                    reverse[face].setdefault(name, []).append(cp)
            cps = [c for c in reverse[face].get(orders[face][gid], []) if owner_of(c) == face]
            add(face, gid, cps[0] if cps else -1)
        primary = opened[0]
        result = Font(str(primary[0]), faces[0].family, font_metrics(primary[2]), glyphs, missing=missing,
                      faces=faces)
        if kerning:
            for face in range(len(opened)):
                own = [(g.codepoint, g.name) for g in glyphs if g.face == face and g.codepoint >= 0]
                if own:
                    scale = upem0 / faces[face].units_per_em
                    for pair, v in kerning_pairs(opened[face][2], own).items():
                        result.kerning[pair] = v * scale
    except BakerError:
        raise
    except Exception as exc:  # noqa: BLE001 (fontTools raises struct.error, TTLibError, IndexError, KeyError, ...)
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise BakerError(sources[0][0], f"damaged or truncated font: {detail}") from None
    return result


# ---------------------------------------------------------------------------------------------------- kerning
def kerning_pairs(font, chars: list) -> dict:
    """{(codepoint1, codepoint2): x-advance adjustment in font units} between the given (codepoint, glyph name)s.

    GPOS ``kern`` lookups apply in lookup order and add up; within a lookup the first subtable that applies to a
    pair wins (OpenType). Without GPOS kerning, the legacy ``kern`` table is used.
    """
    names = [n for _, n in chars]
    found = _gpos_kerning(font, names)
    if found is None:
        legacy = _legacy_kerning(font, names)
        found = None if legacy is None else (np.arange(len(names)), legacy)
    if found is None:
        return {}
    rows, matrix = found
    i, j = np.nonzero(matrix)
    return {(chars[a][0], chars[b][0]): float(matrix[r, b])
            for r, a, b in zip(i.tolist(), rows[i].tolist(), j.tolist())}


def _kern_features(table) -> list:
    """The ``kern`` feature records a shaper applies to Latin text: those of the ``latn`` script's default language
    system, else ``DFLT``'s, else every ``kern`` feature. A font may hold one kern feature per script, with lookups
    shared between them (DejaVu Sans: latn [15], arab [14, 15]); their union would apply a pair twice."""
    records = table.FeatureList.FeatureRecord
    scripts = {r.ScriptTag: r.Script for r in (table.ScriptList.ScriptRecord if table.ScriptList else [])}
    for tag in ("latn", "DFLT"):
        langsys = scripts[tag].DefaultLangSys if tag in scripts else None
        if langsys is not None:
            chosen = [records[i] for i in langsys.FeatureIndex if records[i].FeatureTag == "kern"]
            if chosen:
                return chosen
    return [r for r in records if r.FeatureTag == "kern"]


def _pair_subtables(table, lookups: list):
    """Per lookup index, its pair-adjustment subtables (extension subtables unwrapped)."""
    out = []
    for li in lookups:
        lookup = table.LookupList.Lookup[li]
        subtables = []
        for st in lookup.SubTable:
            if lookup.LookupType == 9:
                if st.ExtensionLookupType != 2:
                    continue
                st = st.ExtSubTable
            elif lookup.LookupType != 2:
                continue
            subtables.append(st)
        out.append(subtables)
    return out


def _gpos_kerning(font, names: list):
    """(rows, matrix): the indices of ``names`` some kern subtable covers as a first glyph (sorted), and their
    adjustments against every name, (len(rows), len(names)). Only covered rows are held: a CJK charset of 3,500
    glyphs would otherwise need several 3,500 x 3,500 matrices (~0.2 GB) for the few pairs a CJK font kerns."""
    if "GPOS" not in font:
        return None
    table = font["GPOS"].table
    if not table.FeatureList or not table.LookupList:
        return None
    lookups = sorted({i for rec in _kern_features(table) for i in rec.Feature.LookupListIndex})
    if not lookups:
        return None
    per_lookup = _pair_subtables(table, lookups)
    firsts_covered = set()
    for subtables in per_lookup:
        for st in subtables:
            firsts_covered.update(st.Coverage.glyphs if st.Coverage else [])
    rows = np.array([k for k, name in enumerate(names) if name in firsts_covered], np.int64)
    row_names = [names[k] for k in rows.tolist()]
    n, m = len(names), len(rows)
    position = {}
    for k, name in enumerate(names):
        position.setdefault(name, []).append(k)
    row_position = {}
    for r, name in enumerate(row_names):
        row_position.setdefault(name, []).append(r)
    total = np.zeros((m, n))
    for subtables in per_lookup:
        applied = np.zeros((m, n), bool)
        value = np.zeros((m, n))
        for st in subtables:
            covered = st.Coverage.glyphs if st.Coverage else []
            cover_index = {g: i for i, g in enumerate(covered)}
            if st.Format == 1:
                for name, firsts in row_position.items():
                    ci = cover_index.get(name)
                    if ci is None:
                        continue
                    for rec in st.PairSet[ci].PairValueRecord:
                        seconds = position.get(rec.SecondGlyph)
                        if not seconds:
                            continue
                        adv = float(getattr(rec.Value1, "XAdvance", 0) or 0) if rec.Value1 else 0.0
                        for a in firsts:
                            for b in seconds:
                                if not applied[a, b]:
                                    applied[a, b] = True
                                    value[a, b] = adv
            elif st.Format == 2:
                first = np.array([name in cover_index for name in row_names], bool)
                if not first.any():
                    continue
                class1 = st.ClassDef1.classDefs if st.ClassDef1 else {}
                class2 = st.ClassDef2.classDefs if st.ClassDef2 else {}
                c1 = np.array([class1.get(name, 0) for name in row_names], np.int64)
                c2 = np.array([class2.get(name, 0) for name in names], np.int64)
                adv = np.array([[float(getattr(r.Value1, "XAdvance", 0) or 0) if r.Value1 else 0.0
                                 for r in rec.Class2Record] for rec in st.Class1Record])
                c1 = np.minimum(c1, len(adv) - 1)
                c2 = np.minimum(c2, adv.shape[1] - 1)
                here = first[:, None] & ~applied
                value = np.where(here, adv[c1[:, None], c2[None, :]], value)
                applied |= here
        total += value
    return rows, total


def _legacy_kerning(font, names: list):
    if "kern" not in font:
        return None
    n = len(names)
    total = np.zeros((n, n))
    index = {}
    for k, name in enumerate(names):
        index.setdefault(name, []).append(k)
    found = False
    for sub in font["kern"].kernTables:
        pairs = getattr(sub, "kernTable", None)
        if getattr(sub, "format", 0) != 0 or not pairs:
            continue
        found = True
        for (left, right), adv in pairs.items():
            if left in index and right in index:
                for a in index[left]:
                    for b in index[right]:
                        total[a, b] += adv
    return total if found else None
