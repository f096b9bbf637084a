"""Text shaping with HarfBuzz: font fallback, script and bidi runs, line breaking, alignment -> glyph ids at em positions.

A label in a complex script is unreadable when glyphs are placed by code point (RTR4 15.5 draws glyphs; what glyphs
and where is the shaper's job): ligatures (``fi``), Arabic joining forms, mark positioning and most OpenType features
exist only as glyph substitutions and positionings that HarfBuzz applies. The pipeline, per paragraph (``\\n``):

1. every character gets a **face**: the first font of the fallback list whose cmap maps it; a Common/Inherited
   character (space, punctuation, combining mark) stays in the previous character's face when that face has it,
   so a space between two Arabic words is shaped with the Arabic font;
2. **lines**: greedy breaking at spaces so that no line is wider than ``max_width`` em (a single longer word stays
   whole on its line);
3. per line, **runs** of equal bidi embedding level (Unicode Bidirectional Algorithm, UAX #9, by ``python-bidi``),
   script (ISO 15924 by ``fontTools.unicodedata``, Common/Inherited resolved to the neighbouring script) and face;
   each run is shaped by HarfBuzz with the whole line as context, direction from the level's parity;
4. runs are reordered visually (UAX #9 rule L2; HarfBuzz already returns an RTL run's glyphs left to right), pen
   positions accumulate the advances, HarfBuzz's offsets place each glyph, lines are aligned on x = 0 and stacked by
   the primary font's line height.

Positions are in em (HarfBuzz's font units / units per em of the glyph's face).
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from baker.errors import BakerError
from baker.readers.sniff import check_input

DIRECTIONS = ("ltr", "rtl")
ALIGNMENTS = ("left", "center", "right")
NEUTRAL_SCRIPTS = ("Zyyy", "Zinh", "Zzzz")  # Common, Inherited, Unknown: take the script of their neighbours


@dataclass(frozen=True)
class FaceSource:
    """One font of the fallback list: a file and the face inside it (collections: .ttc/.otc)."""

    path: str
    face_index: int = 0


@dataclass(frozen=True)
class ShapedGlyph:
    face: int  # index into the fallback list
    glyph_id: int
    cluster: int  # index of the first character (code point) of the text this glyph comes from
    x: float  # em: where the glyph's origin goes (pen position + HarfBuzz offset), y up, first baseline at 0
    y: float
    advance: float  # em, HarfBuzz's x advance (kerning included)


@dataclass
class ShapedText:
    glyphs: list  # [ShapedGlyph] in visual order, line after line
    lines: int
    width: float  # em, the widest line
    missing: list  # characters no font of the fallback list maps


def parse_features(spec: str | None) -> dict:
    """``liga,kern,-calt,ss01=2`` -> {"liga": True, "kern": True, "calt": False, "ss01": 2} (HarfBuzz features)."""
    features = {}
    for part in (spec or "").split(","):
        part = part.strip()
        if not part:
            continue
        value: bool | int = True
        if part[0] in "+-":
            value, part = part[0] == "+", part[1:]
        if "=" in part:
            part, _, number = part.partition("=")
            if not number.strip().isdigit():
                raise BakerError(None, f"bad feature value in {spec!r}: {number!r} (use tag=integer)")
            value = int(number)
        if not re.fullmatch(r"[A-Za-z0-9 ]{1,4}", part):
            raise BakerError(None, f"bad OpenType feature tag {part!r} in {spec!r} (four letters, e.g. liga)")
        features[part] = value
    return features


def face_source(spec: str, default_index: int = 0) -> FaceSource:
    """``PATH`` or ``PATH#N`` (face N of a collection); ``default_index`` applies to collections only."""
    path, sep, number = str(spec).rpartition("#")
    if sep and number.isdigit() and Path(path).suffix:
        return FaceSource(path, int(number))
    path = str(spec)
    return FaceSource(path, default_index if is_collection(path) else 0)


def is_collection(path) -> bool:
    if not Path(path).is_file():  # a named pipe is not opened (it would block); open_font says what it is
        return False
    try:
        with open(path, "rb") as f:
            return f.read(4) == b"ttcf"
    except OSError:
        return False


class ShapingFace:
    """A HarfBuzz face and font at its own units per em (so advances come out in font units)."""

    def __init__(self, source: FaceSource, variations: dict | None = None):
        import uharfbuzz as hb

        path = Path(source.path)
        check_input(path, "font")
        try:
            blob = hb.Blob.from_file_path(str(path))
            count = _face_count(path)
            if source.face_index >= count:
                raise BakerError(path, f"face {source.face_index} asked for, the file has {count}")
            self.face = hb.Face(blob, source.face_index)
        except BakerError:
            raise
        except Exception as exc:  # noqa: BLE001 (HarfBuzz refuses unreadable blobs in several ways)
            raise BakerError(path, f"not a readable TrueType/OpenType font: {exc}") from None
        self.upem = int(self.face.upem)
        if self.face.glyph_count == 0 or self.upem <= 0:
            raise BakerError(path, f"face {source.face_index} has no glyphs (not a TrueType/OpenType font?)")
        self.font = hb.Font(self.face)
        if variations:  # the variable font's instance the outlines are read at (outline.variation_location)
            self.font.set_variations(dict(variations))
        self.source = source

    def has(self, codepoint: int) -> bool:
        return self.font.get_nominal_glyph(codepoint) is not None


def _face_count(path) -> int:
    """Faces in a font file: a collection's header count (checked against the file size), else 1."""
    import struct

    with open(path, "rb") as f:
        head = f.read(12)
    if head[:4] != b"ttcf":
        return 1
    if len(head) < 12:
        raise BakerError(path, "truncated font collection header")
    count = struct.unpack(">I", head[8:12])[0]
    if 12 + 4 * count > Path(path).stat().st_size:
        raise BakerError(path, f"font collection header names {count} faces, more than the file holds")
    return count


def open_faces(sources: list, variations: dict | None = None) -> list:
    """HarfBuzz faces of the fallback list; ``variations`` apply to the first (as outline.load_fonts' instance)."""
    if not sources:
        raise BakerError(None, "no font given")
    return [ShapingFace(s, variations if k == 0 else None) for k, s in enumerate(sources)]


# ---------------------------------------------------------------------------------------------------- itemizing
def character_faces(text: str, faces: list) -> tuple[list, list]:
    """Per character the face index of the fallback list (-1: none has it), and the characters none has."""
    from fontTools import unicodedata

    out, missing = [], []
    for i, ch in enumerate(text):
        cp = ord(ch)
        prev = out[-1] if out else -1
        if prev >= 0 and unicodedata.script(ch) in NEUTRAL_SCRIPTS and faces[prev].has(cp):
            out.append(prev)
            continue
        face = next((k for k, f in enumerate(faces) if f.has(cp)), -1)
        if face < 0:
            face = prev if prev >= 0 else 0  # drawn as .notdef by the face around it, reported
            if ch not in missing and not ch.isspace() and unicodedata.category(ch)[0] != "C":
                missing.append(ch)
        out.append(face)
    return out, missing


def character_scripts(text: str, forced: str | None = None) -> list:
    """ISO 15924 tags per character; Common/Inherited take the previous script (else the next one)."""
    from fontTools import unicodedata

    if forced:
        return [forced] * len(text)
    scripts = [unicodedata.script(ch) for ch in text]
    last = None
    for i, s in enumerate(scripts):
        if s in NEUTRAL_SCRIPTS:
            scripts[i] = last
        else:
            last = s
    following = None
    for i in range(len(scripts) - 1, -1, -1):
        if scripts[i] is None:
            scripts[i] = following or "Zyyy"
        else:
            following = scripts[i]
    return scripts


_LEVEL = re.compile(r"Level\(\s*(\d+)\s*,?\s*\)")


def bidi_levels(text: str, base: str | None) -> list:
    """UAX #9 embedding levels per character (python-bidi computes them per UTF-8 byte; we read its report).

    python-bidi 0.6 documents only ``get_display`` and ``get_base_level``: its levels are public only through the
    ``debug=True`` report (unicode-bidi's ``BidiInfo``), hence the pinned version range in pyproject.toml and the
    loud failure below when the report does not hold one level per byte. Its pure-Python ``bidi.algorithm`` keeps
    levels in a storage dict, but implements an older UAX #9 (no bracket pairs, N0), so lines with brackets would
    reorder differently."""
    from bidi import get_display

    if not text:
        return []
    base_dir = {"ltr": "L", "rtl": "R"}.get(base) if base else None
    report = get_display(text, base_dir=base_dir, debug=True)
    section = report.split("levels:", 1)[1].split("paragraphs:", 1)[0] if "levels:" in report else ""
    per_byte = [int(v) for v in _LEVEL.findall(section)]
    encoded = text.encode("utf-8")
    if len(per_byte) != len(encoded):
        raise RuntimeError(f"python-bidi reported {len(per_byte)} levels for {len(encoded)} bytes")
    levels, offset = [], 0
    for ch in text:
        levels.append(per_byte[offset])
        offset += len(ch.encode("utf-8"))
    return levels


def visual_order(levels: list) -> list:
    """UAX #9 rule L2 over runs: indices of ``levels`` (one per run) in visual order."""
    order = list(range(len(levels)))
    if not levels:
        return order
    highest = max(levels)
    lowest_odd = min((lv for lv in levels if lv % 2), default=highest + 1)
    for level in range(highest, lowest_odd - 1, -1):
        i = 0
        while i < len(order):
            if levels[order[i]] >= level:
                j = i
                while j < len(order) and levels[order[j]] >= level:
                    j += 1
                order[i:j] = order[i:j][::-1]
                i = j
            else:
                i += 1
    return order


# ---------------------------------------------------------------------------------------------------- shaping
@dataclass
class _Options:
    direction: str | None
    script: str | None
    language: str | None
    features: dict


def _shape_line(text: str, start: int, faces: list, char_faces: list, opts: _Options, base: str | None):
    """Shape ``text`` (one line; ``start``: its offset in the whole text) -> ([ShapedGlyph at y = 0], width em)."""
    import uharfbuzz as hb

    if not text:
        return [], 0.0
    levels = bidi_levels(text, base)
    scripts = character_scripts(text, opts.script)
    runs = []  # (begin, end, level, script, face)
    for i in range(len(text)):
        key = (levels[i], scripts[i], char_faces[start + i])
        if runs and tuple(runs[-1][2:]) == key:
            runs[-1][1] = i + 1
        else:
            runs.append([i, i + 1, *key])
    codepoints = [ord(c) for c in text]
    shaped_runs = []
    for begin, end, level, script, face in runs:
        buf = hb.Buffer()
        buf.add_codepoints(codepoints, begin, end - begin)  # the whole line is the context of the run
        buf.direction = "rtl" if level % 2 else "ltr"
        buf.script = script if script not in NEUTRAL_SCRIPTS else "Latn"
        if opts.language:
            buf.language = opts.language
        hb.shape(faces[face].font, buf, opts.features)
        upem = float(faces[face].upem)
        shaped_runs.append([(face, info.codepoint, start + info.cluster, pos.x_advance / upem, pos.x_offset / upem,
                             pos.y_offset / upem) for info, pos in zip(buf.glyph_infos, buf.glyph_positions)])
    pen, glyphs = 0.0, []
    for r in visual_order([run[2] for run in runs]):
        for face, gid, cluster, advance, dx, dy in shaped_runs[r]:
            glyphs.append(ShapedGlyph(face, gid, cluster, pen + dx, dy, advance))
            pen += advance
    return glyphs, pen


def _line_width(text, start, faces, char_faces, opts, base) -> float:
    return _shape_line(text, start, faces, char_faces, opts, base)[1]


def _break_lines(paragraph: str, start: int, faces, char_faces, opts, base, max_width) -> list:
    """[(line text, offset in the text)]: greedy at spaces, no line wider than ``max_width`` em when avoidable."""
    if max_width is None or " " not in paragraph:
        return [(paragraph, start)]
    words = [(m.start(), m.end()) for m in re.finditer(r"[^ ]+", paragraph)]
    if not words:
        return [(paragraph, start)]
    lines, first, last = [], words[0][0], words[0][1]
    for b, e in words[1:]:
        candidate = paragraph[first:e]
        if _line_width(candidate, start + first, faces, char_faces, opts, base) > max_width:
            lines.append((paragraph[first:last], start + first))
            first = b
        last = e
    lines.append((paragraph[first:last], start + first))
    return lines


def shape_text(text: str, faces: list, *, direction: str | None = None, script: str | None = None,
               language: str | None = None, features: dict | None = None, max_width: float | None = None,
               align: str = "left", line_height: float = 1.0) -> ShapedText:
    """Shape ``text`` with the fallback list ``faces`` (:func:`open_faces`); see the module docstring."""
    if align not in ALIGNMENTS:
        raise BakerError(None, f"unknown alignment {align!r} (known: {', '.join(ALIGNMENTS)})")
    if direction is not None and direction not in DIRECTIONS:
        raise BakerError(None, f"unknown direction {direction!r} (known: {', '.join(DIRECTIONS)})")
    if script is not None and not re.fullmatch(r"[A-Z][a-z]{3}", script):
        raise BakerError(None, f"bad script {script!r}: an ISO 15924 tag such as Latn, Arab, Hani")
    if max_width is not None and not max_width > 0:
        raise BakerError(None, "--max-width must be > 0 (em)")
    opts = _Options(direction, script, language, dict(features or {}))
    char_faces, missing = character_faces(text, faces)
    glyphs, row, widest, offset = [], 0, 0.0, 0
    for paragraph in text.split("\n"):
        base = direction or _paragraph_direction(paragraph)
        for line, start in _break_lines(paragraph, offset, faces, char_faces, opts, base, max_width):
            shaped, width = _shape_line(line, start, faces, char_faces, opts, base)
            shift = {"left": 0.0, "center": -width / 2.0, "right": -width}[align]
            y = -row * line_height
            glyphs.extend(ShapedGlyph(g.face, g.glyph_id, g.cluster, g.x + shift, g.y + y, g.advance)
                          for g in shaped)
            widest = max(widest, width)
            row += 1
        offset += len(paragraph) + 1
    return ShapedText(glyphs, row, widest, missing)


def _paragraph_direction(paragraph: str) -> str:
    """UAX #9 rules P2-P3: the first strong character decides (ltr without one)."""
    import unicodedata

    for ch in paragraph:
        kind = unicodedata.bidirectional(ch)
        if kind == "L":
            return "ltr"
        if kind in ("R", "AL"):
            return "rtl"
    return "ltr"
