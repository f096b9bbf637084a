"""``runtime-shaders/baker_hair.glsl`` and ``baker_fur.glsl``: compile as GLSL ES 3.00 and 3.30 core, and compute
what their numpy twins (``tests/gl/twins_hair.py``, ``twins_fur.py``) say, on the GPU (moderngl, EGL, llvmpipe).

- shading functions: a full-screen pass reads per-pixel inputs (random unit T, L, V, N) from float textures and
  writes RGBA8; the twin shades the same inputs; every pixel must agree within 2/255;
- vertex functions (ribbon expansion, fur shells and fins): transform feedback captures what the vertex shader
  computes from strands baked by ``baker hair`` and read back from the written .glb, compared with the twin.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from . import twins_fur as fur_twins
from . import twins_hair as twins

from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
MODULES = {name: (REPO / "runtime-shaders" / f"baker_{name}.glsl").read_text() for name in ("hair", "fur")}
SIZE = 64
TOLERANCE = 2.0 / 255.0

FULLSCREEN_VS = """
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

SHADE_FS = """
uniform sampler2D u_t;
uniform sampler2D u_l;
uniform sampler2D u_v;
uniform sampler2D u_n;
uniform int u_mode;
layout(location = 0) out vec4 o_color;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 T = texelFetch(u_t, p, 0).xyz;
    vec3 L = texelFetch(u_l, p, 0).xyz;
    vec3 V = texelFetch(u_v, p, 0).xyz;
    vec3 N = texelFetch(u_n, p, 0).xyz;
    float s = texelFetch(u_n, p, 0).w;  // a per-pixel scalar in [0, 1]
    vec3 c;
    if (u_mode == 0) {
        c = 0.4 * baker_hair_kajiya_kay(T, L, V, vec3(0.6, 0.4, 0.2), vec3(0.9, 0.85, 0.8), 24.0);
    } else if (u_mode == 1) {
        c = 0.4 * baker_hair_scheuermann(T, N, V, L, vec3(0.5, 0.3, 0.2), vec3(0.7, 0.7, 0.7), vec3(0.6, 0.4, 0.3),
                                         -0.1, 0.15, 60.0, 12.0, s);
    } else if (u_mode == 2) {
        c = 0.6 * baker_hair_marschner(T, V, L, vec3(0.55, 0.35, 0.2), 0.45, 0.05);
    } else if (u_mode == 3) {
        vec3 n0, n1;
        baker_fur_fin_face_normals(vec3(0.0), T, L, V, n0, n1);
        c = vec3(baker_fur_fin_weight(n0, n1, N, 0.5), 0.5 + 0.5 * n0.x, 0.5 + 0.5 * n1.y);
    } else {
        float h = baker_fur_shell_height(floor(s * 16.0), 16.0);
        c = baker_fur_shell_shade(vec4(0.5 + 0.5 * T, s), h, 0.3).rgb;
    }
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
"""

RIBBON_VS = """
in vec3 POSITION;
in vec3 TANGENT;
in float PARAM;
in float WIDTHSCALE;
uniform vec3 u_eye;
uniform float u_rootWidth;
uniform float u_tipWidth;
uniform float u_pixelScale;  // tan(fovy / 2) / viewport height x 2
out vec3 o_side0;
out vec3 o_side1;
out vec2 o_coverage;
void main() {
    float width = baker_hair_width(u_rootWidth, u_tipWidth, PARAM, WIDTHSCALE);
    float pixel = baker_hair_pixel_size(length(u_eye - POSITION), u_pixelScale, 1.0);
    o_coverage = baker_hair_coverage(width, pixel);
    o_side0 = baker_hair_ribbon_position(POSITION, TANGENT, u_eye, o_coverage.x, 0.0);
    o_side1 = baker_hair_ribbon_position(POSITION, TANGENT, u_eye, o_coverage.x, 1.0);
    gl_Position = vec4(0.0);
}
"""

FUR_VS = """
in vec3 V0;
in vec3 V1;
in vec3 NORMAL;
in float CORNER;
uniform float u_shell;
uniform float u_spacing;
uniform vec3 u_displacement;
out vec3 o_shell;
out vec3 o_fin;
void main() {
    o_shell = baker_fur_shell_position(V0, NORMAL, u_shell, u_spacing, 16.0, u_displacement);
    o_fin = baker_fur_fin_position(V0, V1, NORMAL, CORNER, 0.25);
    gl_Position = vec4(0.0);
}
"""

CHILD_VS = """
in vec3 ROOT;
in vec3 WEIGHTS;
in vec3 G0;
in vec3 R0;
in vec3 G1;
in vec3 R1;
in vec3 G2;
in vec3 R2;
uniform float u_lodWidthScale;
uniform int u_strandCount;
uniform int u_verticesPerStrand;
out vec3 o_child;
out vec2 o_lod;
void main() {
    o_child = baker_hair_offset_child(ROOT, WEIGHTS, G0, R0, G1, R1, G2, R2);
    o_lod = vec2(baker_hair_lod_width(0.75, u_lodWidthScale),
                 float(baker_hair_lod_index_count(u_strandCount, u_verticesPerStrand)));
    gl_Position = vec4(0.0);
}
"""

TRIVIAL_FS = "out vec4 o_color;\nvoid main() { o_color = vec4(1.0); }\n"
STAGES = {"shade": (FULLSCREEN_VS, SHADE_FS), "ribbon": (RIBBON_VS, TRIVIAL_FS), "fur": (FUR_VS, TRIVIAL_FS),
          "child": (CHILD_VS, TRIVIAL_FS)}


def source(version: str, body: str) -> str:
    return HEADERS[version] + MODULES["hair"] + MODULES["fur"] + body


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(STAGES))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    assert_compiles(glslang_validator, tmp_path, version, name, stage, source(version, STAGES[name][0 if stage == "vert" else 1]))


def _unit(rng, shape):
    v = rng.normal(size=shape + (3,))
    return (v / np.linalg.norm(v, axis=-1, keepdims=True)).astype(np.float32)


@pytest.fixture(scope="module")
def inputs():
    rng = np.random.default_rng(7)
    t, l, v, n = (_unit(rng, (SIZE, SIZE)) for _ in range(4))
    s = rng.random((SIZE, SIZE)).astype(np.float32)
    return t, l, v, n, s


def _render(ctx, mode, inputs):
    t, l, v, n, s = inputs
    prog = ctx.program(vertex_shader=source("330 core", FULLSCREEN_VS), fragment_shader=source("330 core", SHADE_FS))
    textures = []
    for unit, (name, data) in enumerate((("u_t", t), ("u_l", l), ("u_v", v), ("u_n", n))):
        rgba = np.concatenate([data, (s if name == "u_n" else np.zeros_like(s))[..., None]], axis=-1)
        tex = ctx.texture((SIZE, SIZE), 4, np.ascontiguousarray(rgba, np.float32).tobytes(), dtype="f4")
        tex.filter = (ctx.NEAREST, ctx.NEAREST)
        tex.use(unit)
        prog[name] = unit
        textures.append(tex)
    prog["u_mode"] = mode
    fbo = ctx.simple_framebuffer((SIZE, SIZE), components=4)
    fbo.use()
    ctx.vertex_array(prog, []).render(vertices=3)
    pixels = np.frombuffer(fbo.read(components=4), np.uint8).reshape(SIZE, SIZE, 4)[..., :3] / 255.0
    for tex in textures:
        tex.release()
    fbo.release()
    return pixels


def _twin(mode, inputs):
    t, l, v, n, s = inputs
    if mode == 0:
        c = 0.4 * twins.baker_hair_kajiya_kay(t, l, v, (0.6, 0.4, 0.2), (0.9, 0.85, 0.8), 24.0)
    elif mode == 1:
        c = 0.4 * twins.baker_hair_scheuermann(t, n, v, l, (0.5, 0.3, 0.2), (0.7, 0.7, 0.7), (0.6, 0.4, 0.3),
                                               -0.1, 0.15, 60.0, 12.0, s)
    elif mode == 2:
        c = 0.6 * twins.baker_hair_marschner(t, v, l, (0.55, 0.35, 0.2), 0.45, 0.05)
    elif mode == 3:
        n0, n1 = fur_twins.baker_fur_fin_face_normals(np.zeros_like(t), t, l, v)
        c = np.stack([fur_twins.baker_fur_fin_weight(n0, n1, n, 0.5), 0.5 + 0.5 * n0[..., 0], 0.5 + 0.5 * n1[..., 1]],
                     axis=-1)
    else:
        h = fur_twins.baker_fur_shell_height(np.floor(s * 16.0), 16.0)
        c = fur_twins.baker_fur_shell_shade(np.concatenate([0.5 + 0.5 * t, s[..., None]], axis=-1), h, 0.3)[..., :3]
    return np.clip(c, 0.0, 1.0)


@pytest.mark.parametrize("mode,name", [(0, "kajiya-kay"), (1, "scheuermann"), (2, "marschner"), (3, "fur fin weight"),
                                       (4, "fur shell shade")])
def test_shading_matches_twin(gl_context, inputs, mode, name):
    gpu = _render(gl_context, mode, inputs)
    cpu = _twin(mode, inputs)
    err = np.abs(gpu - cpu)
    assert err.max() <= TOLERANCE + 1e-6, f"{name}: max error {err.max() * 255:.2f}/255 at {np.unravel_index(err.argmax(), err.shape)}"
    # the test image is not flat: the function varies across the inputs
    assert cpu.std() > 0.02 and (cpu > 1.0 / 255).mean() > 0.2


@pytest.fixture(scope="module")
def baked_strands(tmp_path_factory):
    """Children baked on Spot by ``baker hair`` and read back from the written .glb."""
    from baker.techniques.hair.options import HairOptions
    from baker.techniques.hair.extension import read_strands
    from baker.techniques.hair.grow import make_hair, write_output
    from baker.gltf.document import GltfDocument

    out = tmp_path_factory.mktemp("hairgl") / "hair.glb"
    opts = HairOptions(guides=30, children=4, segments=8, length=0.3)
    asset, result = make_hair(REPO / "examples" / "spot" / "spot.obj", opts, seed=1)
    write_output(asset, result, opts, out)
    doc = GltfDocument.load(out)
    mesh = next(i for i, m in enumerate(doc.json["meshes"]) if m.get("name") == "hair")
    return read_strands(doc, mesh, 1)


def _transform(ctx, vs, varyings, arrays, uniforms):
    import moderngl

    prog = ctx.program(vertex_shader=source("330 core", vs), varyings=varyings)
    for k, v in uniforms.items():
        prog[k] = v
    n = len(next(iter(arrays.values())))
    buffers = [(ctx.buffer(np.ascontiguousarray(a, np.float32).tobytes()), f"{a.shape[1] if a.ndim > 1 else 1}f", k)
               for k, a in arrays.items()]
    vao = ctx.vertex_array(prog, buffers)
    widths = {"o_side0": 3, "o_side1": 3, "o_coverage": 2, "o_shell": 3, "o_fin": 3, "o_child": 3, "o_lod": 2}
    stride = sum(widths[v] for v in varyings)
    out = ctx.buffer(reserve=n * stride * 4)
    fbo = ctx.simple_framebuffer((4, 4))  # a surfaceless EGL context has no default framebuffer to bind
    fbo.use()
    vao.transform(out, mode=moderngl.POINTS, vertices=n)
    fbo.release()
    data = np.frombuffer(out.read(), np.float32).reshape(n, stride)
    result, col = {}, 0
    for v in varyings:
        result[v] = data[:, col:col + widths[v]]
        col += widths[v]
    return result


def test_ribbon_expansion_matches_twin(gl_context, baked_strands):
    d = baked_strands
    s, v = d["param"].shape
    pos = d["positions"].reshape(-1, 3)
    tangent = d["tangents"].reshape(-1, 3)
    param = d["param"].reshape(-1)
    scale = np.repeat(d["width_scale"], v)
    ext = d["ext"]
    eye = np.array([0.4, 0.6, 3.0], np.float32)
    pixel_scale = 2.0 * np.tan(np.radians(22.5)) / 256.0
    gpu = _transform(gl_context, RIBBON_VS, ["o_side0", "o_side1", "o_coverage"],
                     {"POSITION": pos, "TANGENT": tangent, "PARAM": param, "WIDTHSCALE": scale},
                     {"u_eye": tuple(eye), "u_rootWidth": ext["rootWidth"], "u_tipWidth": ext["tipWidth"],
                      "u_pixelScale": pixel_scale / 2.0})
    width = twins.baker_hair_width(ext["rootWidth"], ext["tipWidth"], param, scale)
    pixel = twins.baker_hair_pixel_size(np.linalg.norm(eye - pos, axis=1), pixel_scale / 2.0, 1.0)
    coverage = twins.baker_hair_coverage(width, pixel)
    side0 = twins.baker_hair_ribbon_position(pos, tangent, eye, coverage[:, 0], 0.0)
    side1 = twins.baker_hair_ribbon_position(pos, tangent, eye, coverage[:, 0], 1.0)
    assert np.allclose(gpu["o_coverage"], coverage, rtol=1e-4, atol=1e-7)
    assert np.abs(gpu["o_side0"] - side0).max() < 1e-5 and np.abs(gpu["o_side1"] - side1).max() < 1e-5
    # geometry: the ribbon spans the drawn width, perpendicular to the strand and to the view
    across = side1 - side0
    assert np.allclose(np.linalg.norm(across, axis=1), coverage[:, 0], rtol=1e-3)
    assert np.abs(np.einsum("ij,ij->i", across, tangent)).max() < 1e-6
    assert np.abs(np.einsum("ij,ij->i", across, eye - pos)).max() < 1e-6
    # sub-pixel strands: some are, and their opacity is their pixel coverage
    thin = coverage[:, 1] < 1.0
    assert thin.any() and np.allclose(coverage[thin, 1], width[thin] / pixel[thin], rtol=1e-5)
    # the ribbon index buffer addresses exactly these 2 x vertex count ribbon vertices
    assert d["ribbon"].max() == 2 * s * v - 1


def test_fur_vertex_functions_match_twin(gl_context):
    rng = np.random.default_rng(3)
    n = 512
    v0 = rng.normal(size=(n, 3)).astype(np.float32)
    v1 = v0 + rng.normal(scale=0.1, size=(n, 3)).astype(np.float32)
    normal = _unit(rng, (n,))
    corner = np.tile(np.arange(4, dtype=np.float32), n // 4)
    displacement = (0.0, -0.02, 0.01)
    for shell in (0.0, 7.0, 15.0):
        gpu = _transform(gl_context, FUR_VS, ["o_shell", "o_fin"], {"V0": v0, "V1": v1, "NORMAL": normal,
                                                                     "CORNER": corner},
                         {"u_shell": shell, "u_spacing": 0.01, "u_displacement": displacement})
        shell_pos = fur_twins.baker_fur_shell_position(v0, normal, np.full(n, shell, np.float32), 0.01, 16.0,
                                                   displacement)
        fin_pos = fur_twins.baker_fur_fin_position(v0, v1, normal, corner, 0.25)
        assert np.abs(gpu["o_shell"] - shell_pos).max() < 1e-5
        assert np.abs(gpu["o_fin"] - fin_pos).max() < 1e-5
    # fin corners: 0, 1 on the edge; 2, 3 raised by the length over v1, v0
    assert np.allclose(fin_pos[corner == 2], v1[corner == 2] + 0.25 * normal[corner == 2], atol=1e-6)
    assert np.allclose(fin_pos[corner == 0], v0[corner == 0])


def test_offset_children_and_lods_match_twin(gl_context, tmp_path):
    """Children written by ``baker guides`` (from a ``baker hair`` groom) rebuilt on the GPU from their 3 guides
    with ``baker_hair_offset_child``: the twin agrees, and so does the offset formula in float64 on the file's data;
    LOD widths and prefix index counts from the file's ``lods``."""
    from baker.cli import main as cli_main
    from baker.gltf.document import GltfDocument
    from baker.techniques.hair.extension import read
    from baker.techniques.hair.grow import make_hair, write_output
    from baker.techniques.hair.options import HairOptions

    groom = tmp_path / "groom.glb"
    opts = HairOptions(guides=40, children=6, segments=8, length=0.3, curl_amplitude=0.1)
    asset, result = make_hair(REPO / "examples" / "spot" / "spot.obj", opts, seed=2)
    write_output(asset, result, opts, groom)
    out = tmp_path / "guides.glb"
    assert cli_main(["guides", str(groom), "-o", str(out), "--guides", "30", "--vertices-per-strand", "9",
                     "--quiet"]) == 0
    doc = GltfDocument.load(out)
    # the groom's emitter (spot) is carried beside the hair as its scalp: the strands are the "hair" mesh
    hair = next(i for i, m in enumerate(doc.json["meshes"]) if m.get("name") == "hair")
    guides, children = read(doc, hair, 0), read(doc, hair, 1)
    v = guides.vertices_per_strand
    gpos = guides.positions.reshape(-1, v, 3)
    cpos = children.positions.reshape(-1, v, 3)
    ids, w = children.guide_ids.astype(np.int64), children.guide_weights
    n = len(cpos) * v
    rep = lambda a: np.repeat(a, v, axis=0)  # noqa: E731  per strand -> per vertex
    arrays = {"ROOT": rep(cpos[:, 0]), "WEIGHTS": rep(w)}
    for k in range(3):
        arrays[f"G{k}"] = gpos[ids[:, k]].reshape(n, 3)
        arrays[f"R{k}"] = rep(gpos[ids[:, k], 0])
    lod_count, lod_scale = children.lods[-1]
    gpu = _transform(gl_context, CHILD_VS, ["o_child", "o_lod"], arrays,
                     {"u_lodWidthScale": lod_scale, "u_strandCount": lod_count, "u_verticesPerStrand": v})
    twin = twins.baker_hair_offset_child(arrays["ROOT"], arrays["WEIGHTS"], arrays["G0"], arrays["R0"],
                                         arrays["G1"], arrays["R1"], arrays["G2"], arrays["R2"])
    assert np.abs(gpu["o_child"] - twin).max() < 1e-5
    exact = cpos[:, :1] + np.einsum("sk,skvd->svd", w, gpos[ids] - gpos[ids][:, :, :1])
    assert np.abs(gpu["o_child"].reshape(-1, v, 3) - exact).max() < 1e-5
    assert np.allclose(gpu["o_lod"][:, 0], twins.baker_hair_lod_width(0.75, lod_scale))
    assert (gpu["o_lod"][:, 1] == twins.baker_hair_lod_index_count(lod_count, v)).all()
    assert twins.baker_hair_lod_index_count(lod_count, v) == 6 * (v - 1) * lod_count
