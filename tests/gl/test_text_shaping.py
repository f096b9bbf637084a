"""Shaped text (HarfBuzz) drawn through ``runtime-shaders/baker_text.glsl`` against FreeType's rasterisation.

Three labels, each written by ``baker text`` and read back from the .glb as a runtime reads it (BAKER_text.glyphs:
glyph-table index + origin per glyph; the table's planeBounds/atlasBounds, glyphIndex and face):

- English with an ``fi`` ligature and kerning (DejaVu Sans),
- Arabic, joined forms right to left (Noto Sans Arabic),
- Latin + Chinese with font fallback (Noto Sans, then Noto Sans CJK SC from the .ttc collection).

Truth is independent of baker's code: glyph ids and positions come from calling HarfBuzz directly on each run; the
coverage reference is FreeType's exact-area antialiased rasterisation (``freetype-py``, no hinting) of those glyphs at
those positions. The label is drawn headlessly (moderngl, EGL) with the module's ``baker_text_shade`` (fill only).

The rendered-vs-FreeType figure is an outline-level error: sum |coverage difference| over the image divided by the
outline length in pixels (sum |grad coverage| of FreeType's image), i.e. the mean distance in pixels between the two
edges. A distance-field edge is a 1-pixel linear ramp where FreeType integrates the exact area, bilinear
interpolation of an 8-bit field at 32 px/em adds ~range/255 px, so a correct render sits well under 0.1 px; a
glyph missing, in the wrong form or moved by 0.05 em (2 px, a typical kerning pair) moves it past 0.2 (the
last test); measured: 0.02-0.03 px on all three labels.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from baker.cli import main as baker_main
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image

from .glsl import HEADERS
from .test_text import QUAD_VS

REPO = Path(__file__).parents[2]
MODULE = (REPO / "runtime-shaders" / "baker_text.glsl").read_text()
DEJAVU = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
NOTO = Path("/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf")
ARABIC = Path("/usr/share/fonts/truetype/noto/NotoSansArabic-Regular.ttf")
CJK = Path("/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc")
CJK_SC = 2  # Noto Sans CJK SC inside the collection
PPEM = 40.0  # render scale, pixels per em (the atlas is 32 px/em: magnified 1.25x)
MARGIN = 6  # pixels around the label
EDGE_ERROR = 0.1  # mean edge distance, pixels (see the module docstring)

# the quad vertex shader of tests/gl/test_text.py (u_bounds = the image in pixels) and baker preview's host fragment
# shader for BAKER_text (runtime-shaders/hosts/text.frag.glsl), with the module in place of its marker
HOST_FS = (REPO / "runtime-shaders" / "hosts" / "text.frag.glsl").read_text()

STYLE = {"color": (1.0, 1.0, 1.0, 1.0), "softness": 0.0, "outlineColor": (0.0, 0.0, 0.0, 0.0), "outlineWidth": 0.0,
         "glowColor": (0.0, 0.0, 0.0, 0.0), "glowWidth": 0.0, "shadowColor": (0.0, 0.0, 0.0, 0.0),
         "shadowSoftness": 0.0}


# ---------------------------------------------------------------------------------------------------- truth
def harfbuzz_run(path: Path, face_index: int, text: str, direction: str, script: str) -> list:
    """HarfBuzz's own glyphs for one run: [(glyph id, x, y, advance)] in em, pen from 0."""
    import uharfbuzz as hb

    face = hb.Face(hb.Blob.from_file_path(str(path)), face_index)
    font = hb.Font(face)
    buf = hb.Buffer()
    buf.add_str(text)
    buf.direction, buf.script = direction, script
    hb.shape(font, buf, {})
    pen, out = 0.0, []
    for info, pos in zip(buf.glyph_infos, buf.glyph_positions):
        out.append((info.codepoint, pen + pos.x_offset / face.upem, pos.y_offset / face.upem, pos.x_advance / face.upem))
        pen += pos.x_advance / face.upem
    return out


def freetype_coverage(glyphs: list, shape: tuple, origin: tuple) -> np.ndarray:
    """FreeType's antialiased coverage of [(path, face index, glyph id, x em, y em)], composited with "over"."""
    import freetype

    height, width = shape
    image = np.zeros(shape, np.float64)
    faces = {}
    for path, face_index, gid, x, y in glyphs:
        key = (str(path), face_index)
        if key not in faces:
            faces[key] = freetype.Face(str(path), index=face_index)
            faces[key].set_char_size(int(round(PPEM * 64)))
        face = faces[key]
        px, py = origin[0] + x * PPEM, origin[1] + y * PPEM
        ix, iy = int(np.floor(px)), int(np.floor(py))
        delta = freetype.Vector(int(round((px - ix) * 64)), int(round((py - iy) * 64)))
        face.set_transform(freetype.Matrix(0x10000, 0, 0, 0x10000), delta)
        face.load_glyph(int(gid), freetype.FT_LOAD_NO_HINTING | freetype.FT_LOAD_NO_BITMAP | freetype.FT_LOAD_RENDER)
        bitmap = face.glyph.bitmap
        if bitmap.width == 0 or bitmap.rows == 0:
            continue
        cov = np.array(bitmap.buffer, np.float64).reshape(bitmap.rows, bitmap.pitch)[:, :bitmap.width] / 255.0
        left = ix + face.glyph.bitmap_left
        top_row = height - (iy + face.glyph.bitmap_top)  # image rows go down from the top
        r0, c0 = max(top_row, 0), max(left, 0)
        r1, c1 = min(top_row + bitmap.rows, height), min(left + bitmap.width, width)
        assert r1 > r0 and c1 > c0, "glyph outside the image"
        block = cov[r0 - top_row: r1 - top_row, c0 - left: c1 - left]
        image[r0:r1, c0:c1] = block + image[r0:r1, c0:c1] * (1.0 - block)
    return image


def edge_error(rendered: np.ndarray, reference: np.ndarray) -> float:
    """Mean distance between the rendered and the reference edges, pixels (see the module docstring)."""
    gy, gx = np.gradient(reference)
    length = np.hypot(gx, gy).sum()
    return float(np.abs(rendered - reference).sum() / length)


# ---------------------------------------------------------------------------------------------------- baker side
def bake(tmp_path, name, text, fonts, *extra) -> dict:
    out = tmp_path / f"{name}.glb"
    args = ["text", text, "-o", str(out), "--size", "32", "--range", "4", "-q"]
    for f in fonts:
        args += ["--font", f]
    assert baker_main(args + list(extra)) == 0
    doc = GltfDocument.load(out)
    node = doc.json["nodes"][0]
    ext = node["extensions"]["BAKER_text"]
    font = doc.json["extensions"]["BAKER_glyph_atlas"]["fonts"][ext["font"]]
    table = {k: doc.accessor(v) for k, v in font["glyphs"].items() if k != "count"}
    glyph = doc.accessor(ext["glyphs"]["glyph"]).astype(np.int64)
    return {
        "font": font,
        "atlas": decode_image(doc.image_bytes(doc.json["textures"][font["texture"]]["source"]), ".png"),
        "table": table,
        "glyph": glyph,
        "position": doc.accessor(ext["glyphs"]["position"]).astype(np.float64),
        "gid": table["glyphIndex"][glyph].astype(np.int64),
        "face": table["face"][glyph].astype(np.int64) if "face" in table else np.zeros(len(glyph), np.int64),
        "mesh": doc.accessor(doc.json["meshes"][node["mesh"]]["primitives"][0]["attributes"]["POSITION"]),
    }


def quads(label: dict, origin: tuple) -> np.ndarray:
    """Vertices (x px, y px, u, v) of the label's glyphs, as a runtime builds them from BAKER_text.glyphs."""
    W, H = float(label["font"]["width"]), float(label["font"]["height"])
    verts = []
    for k, (x, y) in zip(label["glyph"], label["position"]):
        l, b, r, t = label["table"]["planeBounds"][k]
        al, ab, ar, at = label["table"]["atlasBounds"][k]
        if r <= l:
            continue
        corners = [(l, b, al, ab), (r, b, ar, ab), (r, t, ar, at), (l, b, al, ab), (r, t, ar, at), (l, t, al, at)]
        for cx, cy, u, v in corners:
            verts.append((origin[0] + (x + cx) * PPEM, origin[1] + (y + cy) * PPEM, u / W, 1.0 - v / H))
    return np.array(verts, np.float32)


def render(ctx, label: dict, shape: tuple, origin: tuple) -> np.ndarray:
    import moderngl

    height, width = shape
    header = HEADERS["330 core"]
    assert "// @baker:modules" in HOST_FS
    prog = ctx.program(vertex_shader=header + QUAD_VS, fragment_shader=header + HOST_FS.replace("// @baker:modules",
                                                                                                MODULE))
    img = label["atlas"]
    atlas = ctx.texture((img.shape[1], img.shape[0]), img.shape[2], np.ascontiguousarray(img).tobytes())
    atlas.filter = (moderngl.LINEAR, moderngl.LINEAR)
    atlas.repeat_x = atlas.repeat_y = False
    atlas.use(0)
    prog["u_atlas"].value = 0
    prog["u_bounds"].value = (0.0, 0.0, float(width), float(height))  # vertices in pixels
    prog["u_atlasSize"].value = (float(img.shape[1]), float(img.shape[0]))
    prog["u_distanceRange"].value = float(label["font"]["distanceRange"])
    prog["u_fieldType"].value = 2  # msdf
    for key, value in STYLE.items():
        prog[f"u_style.{key}"].value = tuple(value) if isinstance(value, tuple) else value
    target = ctx.texture((width, height), 4, dtype="f4")
    fbo = ctx.framebuffer([target])
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, 0.0)
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.enable(moderngl.BLEND)
    ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA  # premultiplied, as the module's docs say
    vbo = ctx.buffer(quads(label, origin).tobytes())
    ctx.vertex_array(prog, [(vbo, "2f 2f", "a_position", "a_uv")]).render(moderngl.TRIANGLES)
    ctx.finish()
    ctx.disable(moderngl.BLEND)
    rgba = np.frombuffer(target.read(), np.float32).reshape(height, width, 4)
    return rgba[::-1, :, 3].astype(np.float64)  # GL rows go up: flip to image rows


def frame(label: dict) -> tuple[tuple, tuple]:
    """Image shape and the pixel position of the label's em origin, from the reference glyph boxes."""
    pb = label["table"]["planeBounds"][label["glyph"]]
    pos = label["position"]
    left, right = (pos[:, 0] + pb[:, 0]).min(), (pos[:, 0] + pb[:, 2]).max()
    bottom, top = (pos[:, 1] + pb[:, 1]).min(), (pos[:, 1] + pb[:, 3]).max()
    width = int(np.ceil((right - left) * PPEM)) + 2 * MARGIN
    height = int(np.ceil((top - bottom) * PPEM)) + 2 * MARGIN
    return (height, width), (MARGIN - left * PPEM, MARGIN - bottom * PPEM)


def check_positions(label: dict, expected: list) -> None:
    """``expected``: [(face, glyph id, x em, y em)] from HarfBuzz; float32 storage: within 1e-5 em."""
    got = [(int(f), int(g)) for f, g in zip(label["face"], label["gid"])]
    assert got == [(f, g) for f, g, _, _ in expected]
    np.testing.assert_allclose(label["position"], np.array([(x, y) for _, _, x, y in expected]), atol=1e-5)


def check_coverage(gl_context, label: dict, paths: list) -> float:
    shape, origin = frame(label)
    rendered = render(gl_context, label, shape, origin)
    glyphs = [(*paths[f], g, x, y) for f, g, (x, y) in zip(label["face"], label["gid"], label["position"])]
    reference = freetype_coverage(glyphs, shape, origin)
    assert reference.sum() > 50  # there is ink
    error = edge_error(rendered, reference)
    assert error < EDGE_ERROR, f"mean edge distance {error:.3f} px"
    return error


def one_font_label(tmp_path, text: str, path: Path, direction: str, script: str):
    """Bake ``text`` with one font, check its glyphs and positions against HarfBuzz; (label, FreeType face)."""
    import freetype

    label = bake(tmp_path, script, text, [str(path)])
    check_positions(label, [(0, g, x, y) for g, x, y, _ in harfbuzz_run(path, 0, text, direction, script)])
    return label, freetype.Face(str(path))


# ---------------------------------------------------------------------------------------------------- tests
def test_english_ligature_and_kerning(gl_context, tmp_path):
    text = "fine AVA"
    label, ft = one_font_label(tmp_path, text, DEJAVU, "ltr", "Latn")
    # the ligature: "fi" is one glyph, and not the glyph of "f" or of "i"
    f_id, i_id = ft.get_char_index("f"), ft.get_char_index("i")
    assert len(label["gid"]) == len(text) - 1 and label["gid"][0] not in (f_id, i_id)
    # kerning: A to V is closer than A's advance
    a_id = ft.get_char_index("A")
    k = list(label["gid"]).index(a_id)
    nominal = label["table"]["advance"][label["glyph"][k]]
    assert label["position"][k + 1, 0] - label["position"][k, 0] < nominal - 0.02
    # the plain-glTF quads are the same glyph boxes (viewers without BAKER_text)
    assert len(label["mesh"]) == 4 * sum(label["table"]["planeBounds"][k][2] > label["table"]["planeBounds"][k][0]
                                         for k in label["glyph"])
    check_coverage(gl_context, label, [(DEJAVU, 0)])


def test_arabic_joined_right_to_left(gl_context, tmp_path):
    text = "مرحبا بكم"
    label, ft = one_font_label(tmp_path, text, ARABIC, "rtl", "Arab")
    nominal = {ft.get_char_index(c) for c in text}
    joined = [g for g in label["gid"] if g not in nominal]
    assert len(joined) >= 5, "initial/medial/final forms replace the isolated ones"
    # right to left: the first letter's glyph is the rightmost
    first = ft.get_char_index(text[0])
    assert label["position"][:, 0].argmax() == len(label["gid"]) - 1 and label["gid"][-1] != first  # an initial form
    check_coverage(gl_context, label, [(ARABIC, 0)])


def test_latin_chinese_fallback(gl_context, tmp_path):
    latin, chinese = "Hello ", "你好世界"
    label = bake(tmp_path, "mixed", latin + chinese, [str(NOTO), f"{CJK}#{CJK_SC}"])
    assert [f["file"] for f in label["font"]["faces"]] == [NOTO.name, CJK.name]
    assert label["font"]["faces"][1]["faceIndex"] == CJK_SC
    first = harfbuzz_run(NOTO, 0, latin, "ltr", "Latn")
    pen = sum(a for *_, a in first)
    second = harfbuzz_run(CJK, CJK_SC, chinese, "ltr", "Hani")
    expected = [(0, g, x, y) for g, x, y, _ in first] + [(1, g, pen + x, y) for g, x, y, _ in second]
    check_positions(label, expected)
    check_coverage(gl_context, label, [(NOTO, 0), (CJK, CJK_SC)])


def test_misplaced_glyph_is_caught(gl_context, tmp_path):
    """The coverage check can fail: the same label with one glyph moved by 0.05 em is over the threshold."""
    label = bake(tmp_path, "en", "AVA", [str(DEJAVU)])
    shape, origin = frame(label)
    rendered = render(gl_context, label, shape, origin)
    moved = [(DEJAVU, 0, g, x + (0.05 if k == 1 else 0.0), y)
             for k, (g, (x, y)) in enumerate(zip(label["gid"], label["position"]))]
    assert edge_error(rendered, freetype_coverage(moved, shape, origin)) > 2 * EDGE_ERROR
