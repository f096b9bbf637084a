"""``runtime-shaders/baker_hair_shading.glsl``: compiles as GLSL ES 3.00 and 3.30 core; a headless render (EGL)
evaluating ``baker_hair_shading`` and ``baker_hair_shading_single`` at 4096 random fibre/light/view/melanin/fibre
count samples, with the baked tables uploaded as half-float textures with linear filtering, agrees with the numpy
twins (``baker.api.hair_shade`` and ``hair_bsdf`` on the same tables) to the precision of float32 arithmetic and of
the GPU's bilinear filter."""
from __future__ import annotations

import numpy as np
import pytest

from . import twins_hair_shading as twins
from .glsl import HEADERS, REPO, assert_compiles

MODULE = (REPO / "runtime-shaders" / "baker_hair_shading.glsl").read_text()
SIZE = 64

FS = """
uniform sampler2D u_m;
uniform sampler2D u_n;
uniform sampler2D u_dual;
uniform sampler2D u_tangent;   // xyz
uniform sampler2D u_light;     // xyz, w = fibres crossed
uniform sampler2D u_view;      // xyz
uniform sampler2D u_sigma;     // rgb: sigma_a per fibre radius
uniform vec4 u_variances;
uniform vec4 u_params;         // tilt, slices, alphaF, betaF
layout(location = 0) out vec4 o_shade;
layout(location = 1) out vec4 o_single;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 light = texelFetch(u_light, p, 0);
    vec3 T = texelFetch(u_tangent, p, 0).xyz;
    vec3 V = texelFetch(u_view, p, 0).xyz;
    vec3 sigma = texelFetch(u_sigma, p, 0).rgb;
    BakerHairShading h = BakerHairShading(u_variances, u_params.x, u_params.y, u_params.z, u_params.w, 1.0, 1.0);
    o_shade = vec4(baker_hair_shading(u_m, u_n, u_dual, h, T, light.xyz, V, light.w, sigma), 1.0);
    o_single = vec4(baker_hair_shading_single(u_m, u_n, h, T, light.xyz, V, sigma), 1.0);
}
"""
VS = """
in vec2 a_position;
void main() { gl_Position = vec4(a_position, 0.0, 1.0); }
"""


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, stage):
    text = HEADERS[version] + MODULE + (VS if stage == "vert" else FS)
    assert_compiles(glslang_validator, tmp_path, version, "hair_shading", stage, text)


def samples(count, seed=11):
    rng = np.random.default_rng(seed)

    def unit():
        v = rng.normal(size=(count, 3))
        return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)

    crossed = rng.choice([0.0, 0.0, 0.4, 1.0, 2.0, 3.0, 5.0, 9.0], count).astype(np.float32)
    eumelanin = rng.choice([0.0, 0.3, 1.3, 8.0], count)
    sigma = twins.baker_hair_shading_melanin(eumelanin, rng.uniform(0, 0.5, count)).astype(np.float32)
    return unit(), unit(), unit(), crossed, sigma


def rgba(array):
    a = np.asarray(array, np.float32).reshape(SIZE, SIZE, -1)
    return np.concatenate([a, np.zeros((SIZE, SIZE, 4 - a.shape[2]), np.float32)], 2) if a.shape[2] < 4 else a


def test_render_matches_hair_shade(gl_context):
    import moderngl

    from baker.techniques.hair_shading.dual import dual_table_for
    from baker.techniques.hair_shading.tables import as_half, bake_tables

    ctx = gl_context
    tables = as_half(bake_tables(0.3, 0.3, 1.55))
    dual = dual_table_for(0.3, 0.3, 1.55, 2.0)
    h = twins.params(tables, dual)
    T, L, V, crossed, sigma = samples(SIZE * SIZE)
    prog = ctx.program(vertex_shader=HEADERS["330 core"] + VS, fragment_shader=HEADERS["330 core"] + MODULE + FS)
    m_rgba = np.concatenate([tables.longitudinal, np.zeros(tables.longitudinal.shape[:2] + (1,), np.float32)], 2)
    textures = {}
    for unit, (name, image, half) in enumerate((("u_m", m_rgba, True), ("u_n", tables.azimuthal, True),
                                                ("u_dual", dual.table, True), ("u_tangent", rgba(T), False),
                                                ("u_light", rgba(np.concatenate([L, crossed[:, None]], 1)), False),
                                                ("u_view", rgba(V), False), ("u_sigma", rgba(sigma), False))):
        data = np.ascontiguousarray(image, np.float16 if half else np.float32)
        tex = ctx.texture((image.shape[1], image.shape[0]), 4, data.tobytes(), dtype="f2" if half else "f4")
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR) if half else (moderngl.NEAREST, moderngl.NEAREST)
        tex.repeat_x = tex.repeat_y = False
        tex.use(unit)
        prog[name].value = unit
        textures[name] = tex
    prog["u_variances"].value = tuple(float(v) for v in h["variances"])
    prog["u_params"].value = (h["tilt"], float(h["slices"]), h["alphaF"], h["betaF"])
    quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], "f4").tobytes())
    vao = ctx.vertex_array(prog, [(quad, "2f", "a_position")])
    targets = [ctx.texture((SIZE, SIZE), 4, dtype="f4") for _ in range(2)]
    fbo = ctx.framebuffer(targets)
    fbo.use()
    vao.render(moderngl.TRIANGLE_STRIP)
    ctx.finish()
    shade, single = (np.frombuffer(t.read(), np.float32).reshape(-1, 4)[:, :3].astype(float) for t in targets)
    want_shade = twins.baker_hair_shading(m_rgba, tables.azimuthal, dual.table, h, T, L, V, crossed, sigma)
    want_single = twins.baker_hair_shading_single(m_rgba, tables.azimuthal, h, T, L, V, sigma)
    for name, got, want in (("hair_shade", shade, want_shade), ("hair_bsdf", single, want_single)):
        assert np.isfinite(got).all()
        error = np.abs(got - want)
        scale = np.abs(want).max()
        relative = (error / np.maximum(np.abs(want), 1e-30))[np.abs(want) > 0.01 * scale]
        print(f"{name}: max |GLSL - twin| {error.max():.3g} (max value {scale:.3g}); relative where above 1% of the "
              f"max: 99th percentile {np.percentile(relative, 99):.3g}, max {relative.max():.3g}")
        # float32 on llvmpipe: acos / asin of the angles near +-1 keep half the digits (a few 1e-4 rad), and the
        # narrow lobes (TT's width is 0.15 rad) turn that into a few 0.1%; the bilinear filter of half-float texels
        # adds little (8-bit filter weights in the twin change the error by 10%)
        assert np.all(error <= 1e-2 * np.abs(want) + 3e-4 * scale), name
    # the samples cover what matters: lit and shadowed, blond and black, the highlights and the backlit glow
    assert (want_shade > 5 * np.median(want_shade)).any() and (crossed > 1).sum() > 1000
