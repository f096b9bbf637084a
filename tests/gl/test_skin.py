"""``runtime-shaders/baker_skin.glsl``: compiles as GLSL ES 3.00 and 3.30 core, and renders what its twin says.

The render goes through the whole data path: an ellipsoid (a few cm, in metres) baked with ``curvature,skin``, the
.glb written and read back, its POSITION / NORMAL / _CURVATURE accessors, the LUT and penumbra PNGs and the
BAKER_skin_lut parameters fed to the GPU (moderngl, EGL, llvmpipe). Pass 1 stores the fragment shader's interpolated
inputs and their screen-space derivatives in RGBA32F targets; pass 2 shades with the module into RGBA8; the numpy twin
(tests/gl/twins_skin.py) shades pass 1's inputs and must agree within 2/255 on every covered pixel.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

import baker
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image
from baker.pipeline import save

from . import twins_skin as twins

from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
MODULE = (REPO / "runtime-shaders" / "baker_skin.glsl").read_text()
SIZE = 192
TOLERANCE = 2.0 / 255.0
EYE = np.array([0.0, 0.0, 0.1])
LIGHT = np.array([0.6, 0.5, 0.6])
PENUMBRA_WIDTH = 8.0  # mm

VS = """
in vec3 POSITION;
in vec3 NORMAL;
in float _CURVATURE;
in vec2 _PRINCIPAL_CURVATURES;
in vec3 _PRINCIPAL_DIRECTION;
uniform mat4 u_viewProjection;
out vec3 v_position;
out vec3 v_normal;
out float v_curvature;
out vec2 v_principal;
out vec3 v_direction;
void main() {
    v_position = POSITION;
    v_normal = NORMAL;
    v_curvature = _CURVATURE;
    v_principal = _PRINCIPAL_CURVATURES;
    // the mesh is drawn untransformed: the identity keeps the direction, as a host's model matrix would rotate it
    v_direction = baker_skin_direction_to(mat3(1.0), _PRINCIPAL_DIRECTION);
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""

INPUTS_FS = """
in vec3 v_position;
in vec3 v_normal;
in float v_curvature;
in vec2 v_principal;
in vec3 v_direction;
layout(location = 0) out vec4 o_normalCurvature;
layout(location = 1) out vec4 o_positionCovered;
layout(location = 2) out vec4 o_fwidthN;
layout(location = 3) out vec4 o_fwidthP;
layout(location = 4) out vec4 o_principal;
layout(location = 5) out vec4 o_direction;
void main() {
    o_normalCurvature = vec4(v_normal, v_curvature);
    o_positionCovered = vec4(v_position, 1.0);
    o_fwidthN = vec4(fwidth(v_normal), 0.0);
    o_fwidthP = vec4(fwidth(v_position), 0.0);
    o_principal = vec4(v_principal, 0.0, 0.0);
    o_direction = vec4(v_direction, 0.0);
}
"""

# u_variant: 0 LUT with the baked curvature, 1 normal blending + penumbra (struct path), 2 wrap lighting,
# 3 LUT with the per-pixel derivative curvature, 4 per-channel diffuse normals (BAKER_normal_blur's maps, here three
# detail normals of decreasing amplitude, red smoothest), 5 LUT with the curvature along the light (principal
# curvatures and direction)
SHADE_FS = """
in vec3 v_position;
in vec3 v_normal;
in float v_curvature;
in vec2 v_principal;
in vec3 v_direction;
uniform vec3 u_light;
uniform BakerSkin u_skin;
uniform sampler2D u_lut;
uniform sampler2D u_penumbra;
uniform float u_penumbraWidth;
uniform int u_variant;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 N = normalize(v_normal);
    vec3 L = normalize(u_light);
    vec3 rgb;
    if (u_variant == 0) {
        float k = baker_skin_curvature(v_curvature, u_skin.curvatureScale);
        rgb = baker_skin_lut(u_lut, dot(N, L), k, u_skin.curvatureRange);
    } else if (u_variant == 1) {
        vec3 detail = normalize(N + 0.35 * sin(v_position * 300.0));
        float shadow = clamp(v_position.x * 60.0 + 0.5, 0.0, 1.0);
        rgb = baker_skin_diffuse(u_skin, u_lut, N, detail, L, v_curvature)
            * baker_skin_penumbra(u_penumbra, shadow, u_penumbraWidth, u_skin.penumbraWidthRange);
    } else if (u_variant == 2) {
        rgb = baker_skin_wrap(dot(N, L), u_skin.wrap, u_skin.scatterWidth, u_skin.scatterColor);
    } else if (u_variant == 4) {
        vec3 bump = sin(v_position * 300.0);
        vec3 NdotL = vec3(dot(normalize(N + 0.1 * bump), L), dot(normalize(N + 0.25 * bump), L),
                          dot(normalize(N + 0.35 * bump), L));
        rgb = baker_skin_diffuse_normals(u_skin, u_lut, NdotL, v_curvature);
    } else if (u_variant == 5) {
        float k = baker_skin_curvature_along_light(v_principal, v_direction, N, L);
        rgb = baker_skin_lut(u_lut, dot(N, L), baker_skin_curvature(k, u_skin.curvatureScale), u_skin.curvatureRange);
    } else {
        float k = baker_skin_curvature_from_derivatives(fwidth(v_normal), fwidth(v_position));
        rgb = baker_skin_lut(u_lut, dot(N, L), baker_skin_curvature(k, u_skin.curvatureScale), u_skin.curvatureRange);
    }
    o_color = vec4(rgb, 1.0);
}
"""

PROGRAMS = {"inputs": (VS, INPUTS_FS), "shade": (VS, SHADE_FS)}
VARIANTS = {"lut": 0, "blend_penumbra": 1, "wrap": 2, "derivatives": 3, "diffuse_normals": 4, "along_light": 5}


def source(version: str, body: str) -> str:
    return HEADERS[version] + MODULE + body


def program(ctx, name: str, version: str = "330 core"):
    vs, fs = PROGRAMS[name]
    return ctx.program(vertex_shader=source(version, vs), fragment_shader=source(version, fs))


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    assert_compiles(glslang_validator, tmp_path, version, name, stage, source(version, PROGRAMS[name][0 if stage == "vert" else 1]))


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """An ellipsoid of 3 x 2 x 1.5 cm (metres) baked with curvature + skin, read back from the written .glb."""
    folder = tmp_path_factory.mktemp("skin_gl")
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    mesh.vertices *= np.array([0.03, 0.02, 0.015])
    mesh.export(str(folder / "ellipsoid.glb"), include_normals=True)
    options = {"skin": {"width": 64, "height": 32, "min_radius": 5.0, "max_radius": 50.0, "penumbra_size": 32}}
    out = folder / "ellipsoid_skin.glb"
    save(baker.bake(str(folder / "ellipsoid.glb"), bakes=["curvature", "skin"], options=options), out)
    doc = GltfDocument.load(out)
    prim = doc.json["meshes"][0]["primitives"][0]
    params = doc.json["materials"][prim["material"]]["extensions"]["BAKER_skin_lut"]

    def image(key):
        source_index = doc.json["textures"][params[key]["index"]]["source"]
        return decode_image(doc.image_bytes(source_index), ".png")

    return {
        "positions": doc.accessor(prim["attributes"]["POSITION"]).astype(np.float32),
        "normals": doc.accessor(prim["attributes"]["NORMAL"]).astype(np.float32),
        "curvature": doc.accessor(prim["attributes"][params["curvatureAttribute"]]).astype(np.float32)[:, 0],
        # as written: FLOAT VEC3 with H in x, bound as "3f" to `in float _CURVATURE` (GL reads x)
        "curvature_vec3": doc.accessor(prim["attributes"][params["curvatureAttribute"]]).astype(np.float32),
        "principal": doc.accessor(prim["attributes"]["_PRINCIPAL_CURVATURES"]).astype(np.float32),
        "direction": doc.accessor(prim["attributes"]["_PRINCIPAL_DIRECTION"]).astype(np.float32),
        "indices": doc.accessor(prim["indices"]).astype(np.uint32),
        "params": params,
        "lut": image("lutTexture"),
        "penumbra": image("penumbraTexture"),
    }


def look_at(eye, target, up):
    f = (target - eye) / np.linalg.norm(target - eye)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fovy_deg, aspect, near, far):
    f = 1.0 / math.tan(math.radians(fovy_deg) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def upload(ctx, pixels):
    import moderngl

    h, w, c = pixels.shape
    texture = ctx.texture((w, h), c, np.ascontiguousarray(pixels).tobytes(), dtype="nu2", alignment=2)
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = False  # CLAMP_TO_EDGE, as the glTF sampler says
    return texture


@pytest.fixture(scope="module")
def renders(gl_context, baked):
    import moderngl

    ctx = gl_context
    matrix = (perspective(40.0, 1.0, 0.01, 1.0) @ look_at(EYE, np.zeros(3), np.array([0.0, 1.0, 0.0])))
    matrix = matrix.T.astype(np.float32).tobytes()
    names = ("positions", "normals", "curvature_vec3", "principal", "direction")
    buffers = [ctx.buffer(np.ascontiguousarray(baked[k]).tobytes()) for k in names]
    layout = list(zip(buffers, [f"{baked[k].shape[1]}f" for k in names],
                      ("POSITION", "NORMAL", "_CURVATURE", "_PRINCIPAL_CURVATURES", "_PRINCIPAL_DIRECTION")))
    index_buffer = ctx.buffer(baked["indices"].tobytes())
    size = (SIZE, SIZE)
    depth = ctx.depth_renderbuffer(size)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.disable(moderngl.BLEND)

    inputs = program(ctx, "inputs")
    inputs["u_viewProjection"].write(matrix)
    targets = [ctx.texture(size, 4, dtype="f4") for _ in range(6)]
    fbo = ctx.framebuffer(targets, depth)
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.vertex_array(inputs, layout, index_buffer=index_buffer, index_element_size=4).render(moderngl.TRIANGLES)
    ctx.finish()
    names = ("normal_curvature", "position_covered", "fwidth_n", "fwidth_p", "principal", "direction")
    out = {n: np.frombuffer(t.read(), np.float32).reshape(SIZE, SIZE, 4) for n, t in zip(names, targets)}

    p = baked["params"]
    shade = program(ctx, "shade")
    shade["u_viewProjection"].write(matrix)
    shade["u_light"].value = tuple(LIGHT)
    shade["u_skin.curvatureRange"].value = tuple(p["curvatureRange"])
    shade["u_skin.curvatureScale"].value = p["curvatureScale"]
    shade["u_skin.penumbraWidthRange"].value = tuple(p["penumbraWidthRange"])
    shade["u_skin.normalBlend"].value = tuple(p["normalBlend"])
    shade["u_skin.wrap"].value = p["wrap"]
    shade["u_skin.scatterWidth"].value = p["scatterWidth"]
    shade["u_skin.scatterColor"].value = tuple(p["scatterColor"])
    shade["u_penumbraWidth"].value = PENUMBRA_WIDTH
    upload(ctx, baked["lut"]).use(0)
    upload(ctx, baked["penumbra"]).use(1)
    shade["u_lut"].value = 0
    shade["u_penumbra"].value = 1
    vao = ctx.vertex_array(shade, layout, index_buffer=index_buffer, index_element_size=4)
    color = ctx.texture(size, 4)
    fbo = ctx.framebuffer([color], depth)
    for name, code in VARIANTS.items():
        shade["u_variant"].value = code
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        vao.render(moderngl.TRIANGLES)
        ctx.finish()
        out[name] = np.frombuffer(color.read(), np.uint8).reshape(SIZE, SIZE, 4)
    return out


def twin_image(renders, baked, variant):
    nc, pc = renders["normal_curvature"], renders["position_covered"]
    p = baked["params"]
    lut = baked["lut"].astype(np.float32) / np.float32(65535.0)
    penumbra = baked["penumbra"].astype(np.float32) / np.float32(65535.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        N = twins.normalize(nc[..., :3])
        L = twins.normalize(LIGHT)
        ndotl = twins._dot(N, L)
        if variant == "lut":
            k = twins.baker_skin_curvature(nc[..., 3], p["curvatureScale"])
            rgb = twins.baker_skin_lut(lut, ndotl, k, p["curvatureRange"])
        elif variant == "blend_penumbra":
            position = pc[..., :3]
            detail = twins.normalize(N + np.float32(0.35) * np.sin(position * np.float32(300.0)))
            shadow = np.clip(position[..., 0] * np.float32(60.0) + np.float32(0.5), 0, 1)
            rgb = twins.baker_skin_diffuse(p, lut, N, detail, L, nc[..., 3]) * twins.baker_skin_penumbra(
                penumbra, shadow, PENUMBRA_WIDTH, p["penumbraWidthRange"])
        elif variant == "diffuse_normals":
            bump = np.sin(pc[..., :3] * np.float32(300.0))
            ndotl3 = np.stack([twins._dot(twins.normalize(N + np.float32(a) * bump), L) for a in (0.1, 0.25, 0.35)],
                              axis=-1)
            rgb = twins.baker_skin_diffuse_normals(p, lut, ndotl3, nc[..., 3])
        elif variant == "along_light":
            k = twins.baker_skin_curvature_along_light(renders["principal"][..., :2], renders["direction"][..., :3], N, L)
            rgb = twins.baker_skin_lut(lut, ndotl, twins.baker_skin_curvature(k, p["curvatureScale"]),
                                       p["curvatureRange"])
        elif variant == "wrap":
            rgb = twins.baker_skin_wrap(ndotl, p["wrap"], p["scatterWidth"], p["scatterColor"])
        else:
            k = twins.baker_skin_curvature_from_derivatives(renders["fwidth_n"][..., :3], renders["fwidth_p"][..., :3])
            rgb = twins.baker_skin_lut(lut, ndotl, twins.baker_skin_curvature(k, p["curvatureScale"]),
                                       p["curvatureRange"])
    return np.clip(rgb, 0.0, 1.0)


def test_pass1_inputs(renders, baked):
    covered = renders["position_covered"][..., 3] > 0.5
    assert 0.2 < covered.mean() < 0.8
    curvature = renders["normal_curvature"][..., 3][covered] * baked["params"]["curvatureScale"]
    low, high = baked["params"]["curvatureRange"]
    # an ellipsoid of 1.5..3 cm semi-axes: curvatures spread over the LUT's 5..50 mm radius range
    assert low < np.percentile(curvature, 5) and np.percentile(curvature, 95) < high
    assert np.percentile(curvature, 95) > 1.5 * np.percentile(curvature, 5)


@pytest.mark.parametrize("variant", sorted(VARIANTS))
def test_render_matches_twin(renders, baked, variant):
    covered = renders["position_covered"][..., 3] > 0.5
    image = renders[variant]
    np.testing.assert_array_equal(image[..., 3] == 255, covered)
    gpu = image[..., :3][covered].astype(np.float32) / 255.0
    twin = twin_image(renders, baked, variant)[covered]
    difference = np.abs(gpu - twin).max()
    print(f"\n{variant}: max |GPU - twin| = {difference * 255:.3f}/255 over {covered.sum()} pixels")
    assert difference <= TOLERANCE
    assert gpu.max() > 0.3  # something is lit


def test_render_shows_the_technique(renders, baked):
    covered = renders["position_covered"][..., 3] > 0.5
    lut = renders["lut"][..., :3].astype(np.float32)[covered]
    # near the terminator the pre-integrated light is red: scattering carries red furthest
    n = renders["normal_curvature"][..., :3][covered]
    ndotl = (n / np.linalg.norm(n, axis=1, keepdims=True)) @ (LIGHT / np.linalg.norm(LIGHT))
    band = np.abs(ndotl) < 0.1
    assert band.sum() > 50
    assert np.all(lut[band][:, 0] >= lut[band][:, 1]) and lut[band][:, 0].mean() > lut[band][:, 1].mean()
    # and past it (N.L < 0) only the pre-integrated light remains, red-dominated
    behind = (ndotl < -0.02) & (lut[:, 0] > 0)
    assert behind.sum() > 10 and np.all(lut[behind][:, 0] >= lut[behind][:, 2])
    # the per-pixel estimate follows the baked curvature (median within 25%)
    fw_n, fw_p = renders["fwidth_n"][..., :3][covered], renders["fwidth_p"][..., :3][covered]
    estimate = np.linalg.norm(fw_n, axis=1) / np.linalg.norm(fw_p, axis=1)
    baked_k = renders["normal_curvature"][..., 3][covered]
    assert abs(np.median(estimate / baked_k) - 1.0) < 0.25


def test_curvature_along_the_light_is_eulers_formula():
    """The twin of baker_skin_curvature_along_light against the shape operator S = k1 d1 d1^T + k2 d2 d2^T read along
    the light's tangent projection t (the normal curvature t^T S t / |t|^2, do Carmo 3.2): equal for unit directions
    whatever the light; k1 along d1, k2 across it; the mean curvature where the direction is zero or L is the normal;
    and the cos(2a) term scaled by the squared length of a shortened (interpolated) direction."""
    rng = np.random.default_rng(7)
    N = rng.normal(size=(500, 3))
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    d1 = np.cross(N, rng.normal(size=(500, 3)))
    d1 /= np.linalg.norm(d1, axis=1, keepdims=True)
    d2 = np.cross(N, d1)
    L = rng.normal(size=(500, 3))
    L /= np.linalg.norm(L, axis=1, keepdims=True)
    k = np.sort(rng.uniform(-5.0, 20.0, size=(500, 2)), axis=1)[:, ::-1]
    t = L - N * np.sum(N * L, axis=1, keepdims=True)
    S = k[:, 0, None, None] * d1[:, :, None] * d1[:, None, :] + k[:, 1, None, None] * d2[:, :, None] * d2[:, None, :]
    truth = np.einsum("ni,nij,nj->n", t, S, t) / np.sum(t * t, axis=1)
    along = twins.baker_skin_curvature_along_light(k, d1, N, L)
    np.testing.assert_allclose(along, truth, rtol=1e-4, atol=1e-4)
    # the sign of the line field does not matter
    np.testing.assert_allclose(twins.baker_skin_curvature_along_light(k, -d1, N, L), along, rtol=1e-5, atol=1e-5)
    # k1 along d1, k2 along d2 (lights tilted off the surface keep their tangent direction)
    np.testing.assert_allclose(twins.baker_skin_curvature_along_light(k, d1, N, 0.6 * d1 + 0.8 * N), k[:, 0], rtol=1e-4)
    np.testing.assert_allclose(twins.baker_skin_curvature_along_light(k, d1, N, 0.6 * d2 - 0.8 * N), k[:, 1], rtol=1e-4,
                               atol=1e-4)
    mean = k.mean(axis=1)
    np.testing.assert_allclose(twins.baker_skin_curvature_along_light(k, 0.0 * d1, N, L), mean, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(twins.baker_skin_curvature_along_light(k, d1, N, N), mean, rtol=1e-5, atol=1e-5)
    half = twins.baker_skin_curvature_along_light(k, 0.5 * d1, N, L)
    np.testing.assert_allclose(half - mean, 0.25 * (along - mean), rtol=1e-3, atol=1e-3)
    # into another space by a rotation and uniform scale: the length is kept, the direction rotated
    rotation = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    moved = twins.baker_skin_direction_to(3.0 * rotation, 0.5 * d1)
    np.testing.assert_allclose(moved, 0.5 * d1 @ rotation.T, rtol=1e-5, atol=1e-6)


def test_curvature_along_the_light_on_the_ellipsoid(renders, baked):
    """On the rendered ellipsoid the curvature along the light lies between k2 and k1 and differs from the mean
    curvature where the light crosses a principal direction (more than 10% of H on a fifth of the pixels at least)."""
    covered = renders["position_covered"][..., 3] > 0.5
    principal = renders["principal"][..., :2][covered]
    n = renders["normal_curvature"][..., :3][covered]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    L = np.broadcast_to(LIGHT / np.linalg.norm(LIGHT), n.shape)
    k = twins.baker_skin_curvature_along_light(principal, renders["direction"][..., :3][covered], n, L)
    assert np.all(k <= principal[:, 0] + 1e-3 * np.abs(principal[:, 0])) and np.all(k >= principal[:, 1] - 1e-3 * np.abs(principal[:, 1]))
    mean = principal.mean(axis=1)
    assert np.mean(np.abs(k - mean) > 0.1 * np.abs(mean)) > 0.2
