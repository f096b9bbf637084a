"""``runtime-shaders/baker_hair_cards.glsl``: compiles as GLSL ES 3.00 and 3.30 core; a headless render of baked
cards, alpha-tested with the module, covers the pixels a numpy rasteriser of the same mesh and atlas covers, and
its shading matches the numpy twins (``tests/gl/twins_hair_cards.py``) on the GPU's interpolated inputs."""
from __future__ import annotations

import numpy as np
import pytest

from . import twins_hair_cards as twins
from .glsl import HEADERS, REPO, assert_compiles

MODULE = (REPO / "runtime-shaders" / "baker_hair_cards.glsl").read_text()

CARDS_VS = """
in vec3 a_position;
in vec3 a_normal;
in vec4 a_tangent;
in vec2 a_uv;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec3 u_forward;
uniform vec2 u_low;
uniform float u_span;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
out vec3 v_world;
void main() {
    v_world = a_position;
    vec2 p = (vec2(dot(a_position, u_right), dot(a_position, u_up)) - u_low) / u_span;
    gl_Position = vec4(p * 2.0 - 1.0, 0.5 - 0.1 * dot(a_position, u_forward), 1.0);
    v_normal = a_normal;
    v_tangent = a_tangent;
    v_uv = a_uv;
}
"""

CARDS_FS = """
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in vec3 v_world;
uniform sampler2D u_color;
uniform sampler2D u_data;
uniform sampler2D u_flow;
uniform float u_cutoff;
uniform float u_depthRange;
uniform vec3 u_light;
uniform vec3 u_view;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_flow;      // world strand direction, depth
layout(location = 2) out vec4 o_normal;    // interpolated normal, data r
layout(location = 3) out vec4 o_tangent;   // interpolated tangent
layout(location = 4) out vec4 o_texels;    // flow texel rgb, data g
layout(location = 5) out vec4 o_more;      // base rgb, data b
layout(location = 6) out vec4 o_frame;     // the derivative frame
void main() {
    vec4 base = texture(u_color, v_uv);
    if (baker_hair_cards_cut(base.a, u_cutoff)) discard;
    vec3 data = texture(u_data, v_uv).rgb;
    vec3 flowTexel = texture(u_flow, v_uv).rgb;
    vec3 T = baker_hair_cards_flow(flowTexel, v_normal, v_tangent);
    o_color = vec4(baker_hair_cards_shade(base.rgb, T, v_normal, u_light, u_view, vec3(1.0), data.g, data.b,
                                          40.0, 0.1, 0.4), 1.0);
    o_flow = vec4(T, baker_hair_cards_depth(data.r, u_depthRange));
    o_normal = vec4(v_normal, data.r);
    o_tangent = v_tangent;
    o_texels = vec4(flowTexel, data.g);
    o_more = vec4(base.rgb, data.b);
    o_frame = baker_hair_cards_frame(normalize(v_normal), dFdx(v_world), dFdy(v_world), dFdx(v_uv), dFdy(v_uv));
}
"""


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, stage):
    text = HEADERS[version] + MODULE + (CARDS_VS if stage == "vert" else CARDS_FS)
    assert_compiles(glslang_validator, tmp_path, version, "hair_cards", stage, text)


@pytest.fixture(scope="module")
def cards():
    from baker.techniques.cards.kernel import make_cards
    from baker.techniques.cards.options import CardsOptions
    from baker.techniques.hair.guide_solver import resample_strands
    from techniques.cards_groom import make_groom

    curves, widths = make_groom(strands=600, clumps=20, seed=4)
    counts = np.array([len(c) for c in curves])
    strands, lengths, w = resample_strands(np.concatenate(curves), counts, 24, np.concatenate(widths))
    return make_cards(strands, lengths, w, CardsOptions(cards=20, atlas_size=512))


def test_cards_render_alpha_tested_and_shaded_as_the_twins(gl_context, cards):
    import moderngl

    ctx = gl_context
    size = 192
    right, up, forward = np.eye(3, dtype=np.float32)
    xy = np.stack([cards.positions @ right, cards.positions @ up], 1)
    low = xy.min(0) - 0.005
    span = float((xy.max(0) + 0.005 - low).max())
    prog = ctx.program(vertex_shader=HEADERS["330 core"] + MODULE + CARDS_VS,
                       fragment_shader=HEADERS["330 core"] + MODULE + CARDS_FS)
    light = np.array([0.3, 0.6, 0.74], np.float32)
    light /= np.linalg.norm(light)
    view = np.array([0.0, 0.0, 1.0], np.float32)
    uniforms = {"u_right": tuple(right), "u_up": tuple(up), "u_forward": tuple(forward), "u_low": tuple(low),
                "u_span": span, "u_cutoff": cards.alpha_cutoff, "u_depthRange": cards.depth_range,
                "u_light": tuple(light), "u_view": tuple(view)}
    for name, value in uniforms.items():
        prog[name].value = value
    images = {"u_color": cards.base_color, "u_data": cards.data, "u_flow": cards.flow}
    for unit, (name, pixels) in enumerate(images.items()):
        rgba = pixels if pixels.shape[2] == 4 else np.concatenate(
            [pixels, np.full(pixels.shape[:2] + (1,), 255, np.uint8)], 2)
        # glTF's uv (0, 0) is the image's first row: upload rows as they are and sample at uv directly
        tex = ctx.texture((rgba.shape[1], rgba.shape[0]), 4, np.ascontiguousarray(rgba).tobytes())
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        tex.use(unit)
        prog[name].value = unit
    vertices = np.concatenate([cards.positions, cards.normals, cards.tangents, cards.texcoords], 1).astype("f4")
    vbo = ctx.buffer(vertices.tobytes())
    ibo = ctx.buffer(cards.indices.astype("u4").tobytes())
    vao = ctx.vertex_array(prog, [(vbo, "3f 3f 4f 2f", "a_position", "a_normal", "a_tangent", "a_uv")], ibo,
                           index_element_size=4)
    targets = [ctx.texture((size, size), 4, dtype="f4") for _ in range(7)]
    depth = ctx.depth_texture((size, size))
    fbo = ctx.framebuffer(targets, depth)
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.disable(moderngl.CULL_FACE)
    vao.render(moderngl.TRIANGLES)
    ctx.finish()
    color, flow, normal, tangent, texels, more, frame = (np.frombuffer(t.read(), np.float32).reshape(size, size, 4)
                                                  for t in targets)
    covered = color[..., 3] > 0.5

    # coverage: pixel centres on a card at a texel that passes the cutoff, rasterised here in numpy
    expected = np.zeros((size, size), bool)
    pix = (xy - low) / span * size
    cutoff = round(cards.alpha_cutoff * 255)
    for tri in cards.indices.reshape(-1, 3):
        a, b, c = pix[tri]
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if abs(det) < 1e-9:
            continue
        x0, y0 = np.maximum(np.floor(np.minimum(np.minimum(a, b), c)).astype(int), 0)
        x1, y1 = np.minimum(np.ceil(np.maximum(np.maximum(a, b), c)).astype(int), size)
        gx, gy = np.meshgrid(np.arange(x0, x1) + 0.5, np.arange(y0, y1) + 0.5)
        px, py = gx.ravel(), gy.ravel()
        l1 = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / det
        l2 = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / det
        inside = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        uv = np.stack([1 - l1 - l2, l1, l2], 1)[inside] @ cards.texcoords[tri].astype(np.float64)
        texel = np.clip(np.floor(uv * cards.base_color.shape[0]).astype(int), 0, cards.base_color.shape[0] - 1)
        hit = cards.base_color[texel[:, 1], texel[:, 0], 3] >= cutoff
        expected[py[inside][hit].astype(int), px[inside][hit].astype(int)] = True
    iou = (covered & expected).sum() / (covered | expected).sum()
    assert iou > 0.9, iou
    # the alpha test does cut: the cards' triangles cover far more than what is drawn
    assert covered.mean() > 0.05

    # shading and decoding match the twins on the GPU's own interpolated inputs
    n, t = normal[covered][:, :3], tangent[covered]
    T = twins.baker_hair_cards_flow(texels[covered][:, :3], n, t)
    np.testing.assert_allclose(flow[covered][:, :3], T, atol=2e-4)
    np.testing.assert_allclose(flow[covered][:, 3], twins.baker_hair_cards_depth(normal[covered][:, 3],
                                                                                  cards.depth_range), atol=1e-6)
    assert np.abs(flow[covered][:, 3]).max() <= cards.depth_range * (1 + 1e-5)
    shade = twins.baker_hair_cards_shade(more[covered][:, :3], T, n, light, view, np.ones(3, np.float32),
                                         texels[covered][:, 3], more[covered][:, 3], 40.0, 0.1, 0.4)
    np.testing.assert_allclose(color[covered][:, :3], shade, atol=2e-3)
    # the derivative frame is the card's TANGENT (direction and handedness) where the card is not seen edge-on
    facing = np.abs(normal[covered][:, 2]) > 0.5
    dots = (frame[covered][:, :3] * t[:, :3]).sum(1) / np.linalg.norm(t[:, :3], axis=1)
    assert np.median(dots[facing]) > 0.95 and (frame[covered][:, 3] == t[:, 3])[facing].mean() > 0.95
    # the flow points along the cards (root -> tip) far more than across: |f.B| dominates on average
    b = np.cross(n, t[:, :3]) * t[:, 3:4]
    along = np.abs((T * b).sum(1)) / np.linalg.norm(b, axis=1)
    assert np.median(along) > 0.8
