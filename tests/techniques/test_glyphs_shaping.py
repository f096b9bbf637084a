"""Shaping, glyph-id atlases and font fallback (``baker text``, ``baker glyphs --glyphs/--text-file/--font``).

Independent truth: HarfBuzz called directly, FreeType's cmap (freetype-py), the written files read back as JSON/glTF.
The rendered comparison against FreeType is in tests/gl/test_text_shaping.py.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from baker.cli import main
from baker.gltf.document import GltfDocument
from baker.validate import validate_file
from conftest import assert_khronos_clean

DEJAVU = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
NOTO = Path("/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf")
ARABIC = Path("/usr/share/fonts/truetype/noto/NotoSansArabic-Regular.ttf")
CJK = Path("/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc")


def char_index(path: Path, ch: str, face: int = 0) -> int:
    import freetype

    return freetype.Face(str(path), index=face).get_char_index(ch)


def text_label(path: Path) -> dict:
    doc = GltfDocument.load(path)
    ext = doc.json["nodes"][0]["extensions"]["BAKER_text"]
    font = doc.json["extensions"]["BAKER_glyph_atlas"]["fonts"][ext["font"]]
    table = {k: doc.accessor(v) for k, v in font["glyphs"].items() if k != "count"}
    glyph = doc.accessor(ext["glyphs"]["glyph"]).astype(np.int64)
    face = table["face"][glyph].astype(np.int64) if "face" in table else np.zeros(len(glyph), np.int64)
    return {"ext": ext, "font": font, "table": table, "glyph": glyph, "face": face,
            "gid": table["glyphIndex"][glyph].astype(np.int64), "position": doc.accessor(ext["glyphs"]["position"])}


def test_issue_repro_three_fonts_every_script_drawn(tmp_path):
    """The issue's command: every --font is used, the Arabic and Chinese words are in the atlas and drawn."""
    out = tmp_path / "mixed.glb"
    assert main(["text", "Hello 你好 مرحبا", "--font", str(NOTO), "--font", str(ARABIC), "--font", f"{CJK}#2",
                 "-o", str(out), "-q"]) == 0
    lab = text_label(out)
    assert [f["file"] for f in lab["font"]["faces"]] == [NOTO.name, ARABIC.name, CJK.name]
    assert set(lab["face"].tolist()) == {0, 1, 2}
    # 5 Arabic letters; 2 hanzi and the space after them (a space stays in the face of the character before it)
    assert (lab["face"] == 1).sum() >= 5 and (lab["face"] == 2).sum() == 3
    assert char_index(CJK, "你", 2) in lab["gid"][lab["face"] == 2]
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0, report["issues"]
    assert_khronos_clean(out)


def test_bidi_mixed_line_visual_order(tmp_path):
    """LTR paragraph with a Hebrew word: the Hebrew letters are drawn right to left, between the Latin words."""
    out = tmp_path / "bidi.glb"
    text = "ab שלום cd"
    assert main(["text", text, "--font", str(DEJAVU), "-o", str(out), "-q"]) == 0
    lab = text_label(out)
    x = lab["position"][:, 0]
    assert np.all(np.diff(x) > 0)  # visual order, left to right
    hebrew = [char_index(DEJAVU, c) for c in "שלום"]
    assert list(lab["gid"][3:7]) == hebrew[::-1]  # the last Hebrew letter is leftmost
    assert list(lab["gid"][:2]) == [char_index(DEJAVU, c) for c in "ab"]
    # forced right-to-left paragraph: the Latin words swap sides
    out2 = tmp_path / "rtl.glb"
    assert main(["text", text, "--font", str(DEJAVU), "-o", str(out2), "--direction", "rtl", "-q"]) == 0
    lab2 = text_label(out2)
    assert list(lab2["gid"][:2]) == [char_index(DEJAVU, c) for c in "cd"]


def test_features_and_harfbuzz_positions(tmp_path):
    import uharfbuzz as hb

    out = tmp_path / "liga.glb"
    assert main(["text", "office", "--font", str(DEJAVU), "-o", str(out), "-q", "--features=-liga"]) == 0
    assert list(text_label(out)["gid"]) == [char_index(DEJAVU, c) for c in "office"]  # no ligature
    out2 = tmp_path / "liga2.glb"
    assert main(["text", "office", "--font", str(DEJAVU), "-o", str(out2), "-q"]) == 0
    lab = text_label(out2)
    font = hb.Font(hb.Face(hb.Blob.from_file_path(str(DEJAVU)), 0))
    buf = hb.Buffer()
    buf.add_str("office")
    buf.guess_segment_properties()
    hb.shape(font, buf, {})
    assert list(lab["gid"]) == [i.codepoint for i in buf.glyph_infos]
    assert len(lab["gid"]) == 4  # o, ffi, c, e
    pen = np.cumsum([0] + [p.x_advance for p in buf.glyph_positions])[:-1] / 2048.0
    np.testing.assert_allclose(lab["position"][:, 0], pen, atol=1e-6)
    # the ligature's atlas entry has the glyph id and the presentation-form code point the cmap gives it
    k = lab["glyph"][1]
    assert lab["table"]["glyphIndex"][k] == char_index(DEJAVU, "\ufb03")


def test_max_width_breaks_lines_at_spaces(tmp_path):
    out = tmp_path / "wrap.glb"
    assert main(["text", "one two three four", "--font", str(DEJAVU), "-o", str(out), "--max-width", "4.5",
                 "--align", "center", "-q"]) == 0
    lab = text_label(out)
    assert lab["ext"]["shaping"]["maxWidth"] == 4.5
    line_height = lab["font"]["metrics"]["lineHeight"]
    ys = sorted(set(np.round(lab["position"][:, 1], 5).tolist()), reverse=True)
    assert len(ys) >= 2
    np.testing.assert_allclose(ys, -line_height * np.arange(len(ys)), atol=1e-5)
    advance = lab["table"]["advance"]
    for y in ys:
        on = np.isclose(lab["position"][:, 1], y)
        left = lab["position"][on, 0].min()
        right = (lab["position"][on, 0] + advance[lab["glyph"][on]]).max()
        assert right - left <= 4.5
        assert left == pytest.approx(-right, abs=0.02)  # centred (no kerning at the line ends)
    assert len(lab["gid"]) == len("one two three four") - (len(ys) - 1)  # the spaces at the breaks are dropped
    # greedy: the first word of each next line would not have fitted on the line before
    import uharfbuzz as hb

    font = hb.Font(hb.Face(hb.Blob.from_file_path(str(DEJAVU)), 0))

    def width(s):
        buf = hb.Buffer()
        buf.add_str(s)
        buf.guess_segment_properties()
        hb.shape(font, buf, {})
        return sum(p.x_advance for p in buf.glyph_positions) / 2048.0

    words = "one two three four".split()
    lines, current = [], words[0]
    for w in words[1:]:
        if width(current + " " + w) > 4.5:
            lines.append(current)
            current = w
        else:
            current += " " + w
    assert len(lines) + 1 == len(ys)


def test_glyphs_text_file_glyph_ids_and_fallback(tmp_path):
    text = tmp_path / "words.txt"
    text.write_text("office مرحبا", "utf-8")
    out = tmp_path / "atlas"
    assert main(["glyphs", str(NOTO), "--font", str(ARABIC), "--text-file", str(text), "-o", str(out), "-q",
                 "--size", "16"]) == 0
    layout = json.loads((tmp_path / "atlas.json").read_text("utf-8"))
    assert [f["file"] for f in layout["fonts"]] == [NOTO.name, ARABIC.name]
    arabic = [g for g in layout["glyphs"] if g["font"] == 1]
    assert len(arabic) >= 5
    nominal = {char_index(ARABIC, c) for c in "مرحبا"}
    assert len({g["index"] for g in arabic} - nominal) >= 3, "joined forms, not only the isolated glyphs"
    assert all("index" in g for g in layout["glyphs"])
    assert {g["unicode"] for g in layout["glyphs"] if g["font"] == 0} == set(map(ord, "oce \ufb03"))  # ffi ligature
    # a ligature: DejaVu Sans' ffi
    assert main(["glyphs", str(DEJAVU), "--text-file", str(text), "-o", str(tmp_path / "dv"), "-q",
                 "--size", "16"]) == 0
    dv = json.loads((tmp_path / "dv.json").read_text("utf-8"))
    assert char_index(DEJAVU, "\ufb03") in {g["index"] for g in dv["glyphs"]}
    assert char_index(DEJAVU, "f") not in {g["index"] for g in dv["glyphs"]}
    # --glyphs gid: bakes exactly those ids; BMFont leaves the glyphs without code point out
    out2 = tmp_path / "ids"
    gid = char_index(DEJAVU, "\ufb01")
    assert main(["glyphs", str(DEJAVU), "--glyphs", f"gid:{gid},3", "-o", str(out2), "-q"]) == 0
    ids = json.loads((tmp_path / "ids.json").read_text("utf-8"))
    assert sorted(g["index"] for g in ids["glyphs"]) == sorted([gid, 3])
    assert "fonts" not in ids  # one font: the layout stays msdf-atlas-gen's
    # a glyph no code point maps to: written with its index only, and left out of BMFont
    import freetype

    ft = freetype.Face(str(DEJAVU))
    mapped = {gi for _, gi in ft.get_chars()}
    lonely = next(g for g in range(1, ft.num_glyphs) if g not in mapped)
    assert main(["glyphs", str(DEJAVU), "--glyphs", f"gid:{lonely}", "--charset", "str:A", "-o",
                 str(tmp_path / "lonely"), "-q"]) == 0
    entries = json.loads((tmp_path / "lonely.json").read_text("utf-8"))["glyphs"]
    assert {g["index"]: g.get("unicode") for g in entries} == {lonely: None, char_index(DEJAVU, "A"): 65}
    assert main(["glyphs", str(DEJAVU), "--glyphs", f"gid:{lonely}", "--charset", "str:A", "--format", "bmfont",
                 "-o", str(tmp_path / "lonelybm"), "-q"]) == 0
    assert [c["id"] for c in json.loads((tmp_path / "lonelybm.json").read_text("utf-8"))["chars"]] == [65]
    out3 = tmp_path / "bm"
    assert main(["glyphs", str(DEJAVU), "--text-file", str(text), "--format", "bmfont", "-o", str(out3),
                 "-q"]) == 0
    bm = json.loads((tmp_path / "bm.json").read_text("utf-8"))
    assert all(isinstance(c["id"], int) and c["id"] >= 0 for c in bm["chars"])


def test_fallback_charset_takes_first_font_that_has_it(tmp_path):
    out = tmp_path / "fb"
    assert main(["glyphs", str(NOTO), "--font", f"{CJK}#2", "--charset", "str:A你", "-o", str(out), "-q",
                 "--size", "16"]) == 0
    layout = json.loads((tmp_path / "fb.json").read_text("utf-8"))
    by_cp = {g["unicode"]: g for g in layout["glyphs"]}
    assert by_cp[ord("A")]["font"] == 0 and by_cp[ord("你")]["font"] == 1
    assert by_cp[ord("你")]["index"] == char_index(CJK, "你", 2)
    assert layout["fonts"][1]["faceIndex"] == 2 and layout["fonts"][1]["unitsPerEm"] == 1000


def test_deterministic(tmp_path):
    args = ["text", "Hello 你好 fi", "--font", str(DEJAVU), "--font", f"{CJK}#2", "-q"]
    assert main(args + ["-o", str(tmp_path / "a.glb")]) == 0
    assert main(args + ["-o", str(tmp_path / "b.glb")]) == 0
    assert (tmp_path / "a.glb").read_bytes() == (tmp_path / "b.glb").read_bytes()


@pytest.mark.parametrize("extra, needle", [
    (["--features", "li=ga"], "feature"),
    (["--script", "latin"], "ISO 15924"),
    (["--font", "/nonexistent/font.ttf"], "font file not found"),
    (["--font", f"{CJK}#99"], "face 99"),
    (["--max-width", "0"], "max-width"),
])
def test_bad_shaping_input_exit_2(tmp_path, capsys, extra, needle):
    assert main(["text", "hi", "--font", str(DEJAVU), "-o", str(tmp_path / "x.glb"), "-q", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err
    assert not (tmp_path / "x.glb").exists()


def test_bad_glyph_ids_exit_2(tmp_path, capsys):
    assert main(["glyphs", str(DEJAVU), "--glyphs", "gid:999999", "-o", str(tmp_path / "x"), "-q"]) == 2
    assert "glyph id 999999" in capsys.readouterr().err
    assert main(["glyphs", str(DEJAVU), "--glyphs", "3,4", "-o", str(tmp_path / "x"), "-q"]) == 2


def test_validator_checks_shaped_glyphs(tmp_path):
    out = tmp_path / "t.glb"
    assert main(["text", "ok", "--font", str(DEJAVU), "-o", str(out), "-q"]) == 0
    doc = GltfDocument.load(out)
    ext = doc.json["nodes"][0]["extensions"]["BAKER_text"]
    glyph = ext["glyphs"]["glyph"]
    data = doc.accessor(glyph).copy()
    data[0] = 7.0  # past the two-glyph table
    ext["glyphs"]["glyph"] = doc.add_accessor(data.astype(np.float32), target=None)
    bad = tmp_path / "bad.glb"
    doc.save(bad)
    codes = {m["code"] for m in validate_file(bad, khronos=False)["issues"]["messages"]}
    assert "BAKER_TEXT_GLYPHS_INDEX" in codes
