"""``runtime-shaders/baker_text.glsl``: compiles as GLSL ES 3.00 and 3.30 core; a baked label renders as its twin says.

The render goes through the whole data path: ``baker text`` writes a .glb (MTSDF atlas, outline), the test reads the
written file back (quads, atlas PNG, BAKER_glyph_atlas / BAKER_text fields) and draws it headlessly (moderngl, EGL).
Pass 1 stores what the shading pass's fragment shader sees (the atlas sample, the shadow sample and fwidth(uv)) in
RGBA32F targets; pass 2 shades with the module into RGBA8; the numpy twin shades pass 1's values and must agree
within 2/255 on every pixel.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from baker.cli import main as baker_main
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image

from . import twins_text as twins

from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
MODULE = (REPO / "runtime-shaders" / "baker_text.glsl").read_text()
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
TOLERANCE = 2.0 / 255.0
SIZE = (384, 160)

QUAD_VS = """
in vec2 a_position;
in vec2 a_uv;
uniform vec4 u_bounds;  // left, bottom, right, top of the label in node units -> the viewport
out vec2 v_uv;
void main() {
    v_uv = a_uv;
    vec2 ndc = (a_position - u_bounds.xy) / (u_bounds.zw - u_bounds.xy) * 2.0 - 1.0;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
"""

INPUTS_FS = """
in vec2 v_uv;
uniform sampler2D u_atlas;
uniform vec2 u_shadowOffset;
layout(location = 0) out vec4 o_texel;
layout(location = 1) out vec4 o_shadowTexel;
layout(location = 2) out vec4 o_uvFwidth;
void main() {
    o_texel = texture(u_atlas, v_uv);
    o_shadowTexel = texture(u_atlas, v_uv - u_shadowOffset);
    o_uvFwidth = vec4(fwidth(v_uv), 0.0, 1.0);
}
"""

SHADE_FS = """
in vec2 v_uv;
uniform sampler2D u_atlas;
uniform vec2 u_shadowOffset;
uniform vec2 u_atlasSize;
uniform float u_distanceRange;
uniform int u_fieldType;
uniform BakerTextStyle u_style;
layout(location = 0) out vec4 o_color;
void main() {
    vec4 texel = texture(u_atlas, v_uv);
    vec4 shadowTexel = texture(u_atlas, v_uv - u_shadowOffset);
    float screenPxRange = baker_text_screen_px_range(u_distanceRange, u_atlasSize, fwidth(v_uv));
    o_color = baker_text_shade(u_style, texel, shadowTexel, u_fieldType, u_distanceRange, screenPxRange);
}
"""

FULLSCREEN_VS = """
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

# each function on arbitrary texels read from float textures, every field type
FUNCTIONS_FS = """
uniform sampler2D u_texels;
uniform sampler2D u_shadow;
uniform sampler2D u_fw;
uniform int u_fieldType;
uniform float u_distanceRange;
uniform vec2 u_atlasSize;
uniform BakerTextStyle u_style;
layout(location = 0) out vec4 o_shade;
layout(location = 1) out vec4 o_scalars;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 t = texelFetch(u_texels, p, 0);
    vec4 s = texelFetch(u_shadow, p, 0);
    vec2 fw = texelFetch(u_fw, p, 0).xy;
    float spr = baker_text_screen_px_range(u_distanceRange, u_atlasSize, fw);
    o_shade = baker_text_shade(u_style, t, s, u_fieldType, u_distanceRange, spr);
    o_scalars = vec4(spr, baker_text_edge_distance(t, u_fieldType), baker_text_true_distance(t, u_fieldType),
                     baker_text_msdf_opacity(t.rgb, spr));
}
"""

PROGRAMS = {"inputs": (QUAD_VS, INPUTS_FS), "shade": (QUAD_VS, SHADE_FS), "functions": (FULLSCREEN_VS, FUNCTIONS_FS)}
FUNCTIONS = ("baker_text_median", "baker_text_screen_px_range", "baker_text_edge_distance", "baker_text_true_distance",
             "baker_text_coverage", "baker_text_msdf_opacity", "baker_text_over", "baker_text_shade")


def source(version: str, body: str) -> str:
    return HEADERS[version] + MODULE + body


def program(ctx, name: str, version: str = "330 core"):
    vs, fs = PROGRAMS[name]
    return ctx.program(vertex_shader=source(version, vs), fragment_shader=source(version, fs))


def set_style(prog, style: dict) -> None:
    for key, value in style.items():
        prog[f"u_style.{key}"].value = tuple(value) if isinstance(value, (list, tuple)) else value


def test_module_takes_derivatives_as_inputs():
    code = re.sub(r"//[^\n]*", "", MODULE)
    assert "fwidth" not in code and "dFdx" not in code  # derivatives are the caller's: any stage can include it
    for name in FUNCTIONS:
        assert re.search(rf"\b{name}\s*\(", code), name
        assert hasattr(twins, name), f"no numpy twin for {name}"


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    body = PROGRAMS[name][0 if stage == "vert" else 1]
    assert_compiles(glslang_validator, tmp_path, version, name, stage, source(version, body))


# ---------------------------------------------------------------------------------------------------------- label
@pytest.fixture(scope="module")
def label(tmp_path_factory):
    if not FONT.is_file():
        pytest.skip(f"{FONT} not found")
    out = tmp_path_factory.mktemp("label") / "label.glb"
    code = baker_main(["text", "Baker 42\ng&$@!", "--font", str(FONT), "-o", str(out), "--type", "mtsdf",
                       "--size", "32", "--outline-width", "0.04", "--outline-color", "0.1,0.2,0.9,1",
                       "--color", "1,0.8,0.2,1", "-q"])
    assert code == 0
    doc = GltfDocument.load(out)
    node = doc.json["nodes"][0]
    text = node["extensions"]["BAKER_text"]
    font = doc.json["extensions"]["BAKER_glyph_atlas"]["fonts"][text["font"]]
    prim = doc.json["meshes"][node["mesh"]]["primitives"][0]
    atlas = decode_image(doc.image_bytes(doc.json["textures"][font["texture"]]["source"]), ".png")
    return {
        "path": out,
        "positions": doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32),
        "uvs": doc.accessor(prim["attributes"]["TEXCOORD_0"]).astype(np.float32),
        "indices": doc.accessor(prim["indices"]).astype(np.uint32),
        "atlas": atlas,
        "font": font,
        "text": text,
    }


def label_style(lab) -> dict:
    text, font = lab["text"], lab["font"]
    return {
        "color": text["color"],
        "softness": 0.0,
        "outlineColor": text["outline"]["color"],
        "outlineWidth": text["outline"]["width"] * font["size"],  # em -> atlas pixels
        "glowColor": (1.0, 0.3, 0.1, 0.6),
        "glowWidth": 1.5,
        "shadowColor": (0.0, 0.0, 0.0, 0.7),
        "shadowSoftness": 0.8,
    }


def test_label_matches_twin(gl_context, label):
    import moderngl

    ctx = gl_context
    lab = label
    font = lab["font"]
    assert font["type"] == "mtsdf" and lab["atlas"].shape[2] == 4
    atlas = ctx.texture((lab["atlas"].shape[1], lab["atlas"].shape[0]), 4, np.ascontiguousarray(lab["atlas"]).tobytes())
    atlas.filter = (moderngl.LINEAR, moderngl.LINEAR)
    atlas.repeat_x = atlas.repeat_y = False
    pos = lab["positions"]
    margin = 0.1
    bounds = (pos[:, 0].min() - margin, pos[:, 1].min() - margin, pos[:, 0].max() + margin, pos[:, 1].max() + margin)
    shadow_offset = (1.5 / font["width"], -1.5 / font["height"])  # 1.5 atlas pixels right and down

    vbo = ctx.buffer(np.hstack([pos[:, :2], lab["uvs"]]).astype(np.float32).tobytes())
    ibo = ctx.buffer(lab["indices"].tobytes())
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE | moderngl.BLEND)

    def draw(prog, targets):
        prog["u_bounds"].value = tuple(float(b) for b in bounds)
        prog["u_atlas"].value = 0
        prog["u_shadowOffset"].value = shadow_offset
        atlas.use(0)
        fbo = ctx.framebuffer(targets)
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        ctx.vertex_array(prog, [(vbo, "2f 2f", "a_position", "a_uv")], index_buffer=ibo,
                         index_element_size=4).render(moderngl.TRIANGLES)
        ctx.finish()

    inputs = [ctx.texture(SIZE, 4, dtype="f4") for _ in range(3)]
    draw(program(ctx, "inputs"), inputs)
    texel, shadow_texel, fw = (np.frombuffer(t.read(), np.float32).reshape(SIZE[1], SIZE[0], 4) for t in inputs)

    style = label_style(lab)
    shade = program(ctx, "shade")
    shade["u_atlasSize"].value = (float(font["width"]), float(font["height"]))
    shade["u_distanceRange"].value = float(font["distanceRange"])
    shade["u_fieldType"].value = twins.MTSDF
    set_style(shade, style)
    color = ctx.texture(SIZE, 4)
    draw(shade, [color])
    gpu = np.frombuffer(color.read(), np.uint8).reshape(SIZE[1], SIZE[0], 4).astype(np.float32) / 255.0

    covered = fw[..., 3] > 0  # pixels a quad covers
    spr = twins.baker_text_screen_px_range(font["distanceRange"], (font["width"], font["height"]), fw[..., :2])
    twin = twins.baker_text_shade(style, texel, shadow_texel, twins.MTSDF, font["distanceRange"], spr)
    twin = np.where(covered[..., None], np.clip(twin, 0, 1), 0.0)
    diff = np.abs(gpu - twin)
    assert diff.max() <= TOLERANCE + 1e-6, f"max |gpu - twin| = {diff.max() * 255:.2f}/255"
    # and it is text: a good share of the label is fill, outline and shadow, and the fill is the text color
    fill = (gpu[..., 3] > 0.99) & (np.abs(gpu[..., :3] - np.array(style["color"][:3])).max(-1) < 0.02)
    assert fill.sum() > 0.04 * covered.sum()
    assert (gpu[..., 2] > 0.5).sum() > 0  # the blue outline shows


def test_functions_match_twins(gl_context):
    """Every function on random texels (all field types) and extreme screen-pixel ranges."""
    import moderngl

    ctx = gl_context
    rng = np.random.default_rng(5)
    n = 32
    texels = rng.uniform(0, 1, (n, n, 4)).astype(np.float32)
    shadow = rng.uniform(0, 1, (n, n, 4)).astype(np.float32)
    fw = np.exp(rng.uniform(np.log(1e-4), np.log(0.2), (n, n, 4))).astype(np.float32)
    texels[0, :4] = 0.5  # exactly on the edge
    fw[1, :4, :2] = 1.0  # minified: the range clamps to 1
    style = {"color": (0.9, 0.8, 0.1, 0.9), "softness": 0.7, "outlineColor": (0.0, 0.3, 1.0, 1.0), "outlineWidth": 1.2,
             "glowColor": (1.0, 0.2, 0.2, 0.5), "glowWidth": 1.7, "shadowColor": (0.0, 0.0, 0.0, 0.6),
             "shadowSoftness": 0.4}

    def upload(a):
        t = ctx.texture((n, n), 4, np.ascontiguousarray(a).tobytes(), dtype="f4")
        t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return t

    prog = program(ctx, "functions")
    for unit, (name, data) in enumerate((("u_texels", texels), ("u_shadow", shadow), ("u_fw", fw))):
        upload(data).use(unit)
        prog[name].value = unit
    prog["u_distanceRange"].value = 4.0
    prog["u_atlasSize"].value = (256.0, 128.0)
    set_style(prog, style)
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE | moderngl.BLEND)
    for field_type in (twins.SDF, twins.PSDF, twins.MSDF, twins.MTSDF):
        prog["u_fieldType"].value = field_type
        shade_t, scal_t = ctx.texture((n, n), 4, dtype="f4"), ctx.texture((n, n), 4, dtype="f4")
        fbo = ctx.framebuffer([shade_t, scal_t])
        fbo.use()
        fbo.clear()
        ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
        ctx.finish()
        gpu_shade = np.frombuffer(shade_t.read(), np.float32).reshape(n, n, 4)
        gpu_scal = np.frombuffer(scal_t.read(), np.float32).reshape(n, n, 4)
        spr = twins.baker_text_screen_px_range(4.0, (256.0, 128.0), fw[..., :2])
        np.testing.assert_allclose(gpu_scal[..., 0], spr, rtol=1e-5)
        np.testing.assert_allclose(gpu_scal[..., 1], twins.baker_text_edge_distance(texels, field_type), atol=1e-6)
        np.testing.assert_allclose(gpu_scal[..., 2], twins.baker_text_true_distance(texels, field_type), atol=1e-6)
        np.testing.assert_allclose(gpu_scal[..., 3], twins.baker_text_msdf_opacity(texels[..., :3], spr), atol=2e-5)
        twin = twins.baker_text_shade(style, texels, shadow, field_type, 4.0, spr)
        np.testing.assert_allclose(gpu_shade, twin, atol=5e-5)
        assert np.all(np.isfinite(gpu_shade))
    assert np.all(spr[1, :4] == 1.0)
