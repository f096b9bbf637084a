"""``runtime-shaders/baker_hatching.glsl`` and ``baker_toon.glsl``: compile as GLSL ES 3.00 and 3.30 core, and render
what their numpy twins (``tests/gl/twins_hatching.py``, ``twins_toon.py``) say.

The sphere test goes through the whole data path: a sphere with planar UVs is baked with ``--bakes tam``, written to
.glb, and read back; the TAM's level PNGs are uploaded as the custom mip chains of two RGBA8 textures, exactly as a
runtime would (level i with glTexImage2D level i, TEXTURE_MAX_LEVEL = levels - 1). Pass 1 stores the fragment
inputs (tile coordinates, LOD, darkness) in RGBA32F; pass 2 shades with the module into RGBA8; the twin shades
pass 1's inputs and must agree within 2/255 on every covered pixel. The rendered darkness must then grow
monotonically from the lit to the shadowed side, close to the tone the shader was asked for.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

import baker
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image
from baker.pipeline import save

from . import twins_hatching as twins
from . import twins_toon as toon_twins
from .test_translucency import look_at, perspective

from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
HATCHING = (REPO / "runtime-shaders" / "baker_hatching.glsl").read_text()
TOON = (REPO / "runtime-shaders" / "baker_toon.glsl").read_text()
SIZE = 256
TOLERANCE = 2.0 / 255.0
EYE = np.array([0.0, 0.0, 4.0])
LIGHT = np.array([1.0, 0.35, 0.2]) / np.linalg.norm([1.0, 0.35, 0.2])
TILES = 2.0  # TAM tiles per UV unit

SPHERE_VS = """
in vec3 POSITION;
in vec3 NORMAL;
in vec2 TEXCOORD_0;
uniform mat4 u_viewProjection;
out vec3 v_normal;
out vec2 v_uv;
void main() {
    v_normal = NORMAL;
    v_uv = TEXCOORD_0;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""

# pass 1: what the shading pass computes before it samples: tile coordinates, LOD and darkness
INPUTS_FS = """
in vec3 v_normal;
in vec2 v_uv;
uniform float u_scale;
uniform float u_finestSize;
uniform float u_levelCount;
uniform vec3 u_light;
layout(location = 0) out vec4 o_tileLod;
void main() {
    vec2 tile = baker_tam_coord(v_uv, u_scale, u_finestSize);
    float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_finestSize, u_levelCount);
    float darkness = baker_hatching_darkness(normalize(v_normal), u_light, 1.0);
    o_tileLod = vec4(tile, lod, darkness);
}
"""

SHADE_FS = """
in vec3 v_normal;
in vec2 v_uv;
uniform sampler2D u_tones012;
uniform sampler2D u_tones345;
uniform vec3 u_tonesA;
uniform vec3 u_tonesB;
uniform float u_scale;
uniform float u_finestSize;
uniform float u_levelCount;
uniform vec3 u_light;
layout(location = 0) out vec4 o_color;
void main() {
    vec2 tile = baker_tam_coord(v_uv, u_scale, u_finestSize);
    float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_finestSize, u_levelCount);
    float darkness = baker_hatching_darkness(normalize(v_normal), u_light, 1.0);
    float brightness = baker_hatching(u_tones012, u_tones345, tile, lod, darkness, u_tonesA, u_tonesB);
    o_color = vec4(vec3(brightness), 1.0);
}
"""

FULLSCREEN_VS = """
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

# the volume TAM on arbitrary inputs read from a float texture (tile.xy, lod, darkness)
VOLUME_FS = """
uniform sampler2D u_inputs;
uniform highp sampler2DArray u_volume;
uniform float u_toneCount;
uniform float u_darkest;
layout(location = 0) out vec4 o_value;
void main() {
    vec4 s = texelFetch(u_inputs, ivec2(gl_FragCoord.xy), 0);
    o_value = vec4(baker_hatching_volume(u_volume, s.xy, s.z, s.w, u_toneCount, u_darkest), 0.0, 0.0, 1.0);
}
"""

# every toon function on arbitrary inputs read from float textures
TOON_FS = """
uniform sampler2D u_inputs;   // N.L, detail, z, u
uniform sampler2D u_colors;   // rgb
uniform sampler2D u_ramp;
uniform sampler2D u_xtoon;
uniform float u_bands;
uniform float u_softness;
uniform float u_shadow;
uniform float u_levels;
layout(location = 0) out vec4 o_shades;
layout(location = 1) out vec4 o_hsv;
layout(location = 2) out vec4 o_ycbcr;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 s = texelFetch(u_inputs, p, 0);
    vec3 c = texelFetch(u_colors, p, 0).rgb;
    o_shades = vec4(baker_toon_ramp(u_ramp, s.x), baker_xtoon(u_xtoon, s.x, s.y),
                    baker_toon_bands(s.w, u_bands, u_softness, u_shadow), baker_xtoon_detail_depth(s.z, 1.0, 50.0));
    float facing = baker_xtoon_detail_orientation(normalize(c - 0.37), vec3(0.0, 0.0, 1.0), 2.0);
    o_hsv = vec4(baker_posterize_hsv(c, u_levels), facing);
    o_ycbcr = vec4(baker_posterize_ycbcr(c, u_levels), 1.0);
}
"""

PROGRAMS = {
    "inputs": (SPHERE_VS, INPUTS_FS, HATCHING),
    "shade": (SPHERE_VS, SHADE_FS, HATCHING),
    "volume": (FULLSCREEN_VS, VOLUME_FS, HATCHING),
    "toon": (FULLSCREEN_VS, TOON_FS, TOON),
}


def shader_source(version: str, module: str, body: str) -> str:
    return HEADERS[version] + module + body


def program(ctx, name: str, version: str = "330 core"):
    vs, fs, module = PROGRAMS[name]
    return ctx.program(vertex_shader=shader_source(version, module, vs),
                       fragment_shader=shader_source(version, module, fs))


# ---------------------------------------------------------------------------------------------------------- modules
@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    vs, fs, module = PROGRAMS[name]
    assert_compiles(glslang_validator, tmp_path, version, name, stage, shader_source(version, module, vs if stage == "vert" else fs))


# ---------------------------------------------------------------------------------------------------------- sphere
@pytest.fixture(scope="module")
def baked_sphere(tmp_path_factory):
    """A unit sphere with planar UVs (u, v) = (x, -y) / 2 + 1/2 baked with a TAM, written, and read back."""
    folder = tmp_path_factory.mktemp("hatching")
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    uv = np.stack([mesh.vertices[:, 0], -mesh.vertices[:, 1]], 1) * 0.5 + 0.5
    mesh.visual = trimesh.visual.TextureVisuals(uv=uv)
    source = folder / "sphere.glb"
    mesh.export(str(source), include_normals=True)
    # the sphere's own planar UVs (--tam-strokes uv): their stretch towards the rim spans the TAM's levels
    asset = baker.bake(str(source), bakes=["tam"], seed=1, options={"tam": {"scale": TILES * 256, "strokes": "uv"}})
    out = folder / "sphere_tam.glb"
    save(asset, out)

    doc = GltfDocument.load(out)
    primitive = doc.json["meshes"][0]["primitives"][0]
    ext = doc.json["materials"][primitive["material"]]["extensions"]["BAKER_tonal_art_map"]
    attributes = primitive["attributes"]
    chains = [[], []]
    for level in ext["levels"]:
        for j, info in enumerate(level["textures"]):
            rgb = decode_image(doc.image_bytes(doc.json["textures"][info["index"]]["source"]))
            rgba = np.full(rgb.shape[:2] + (4,), 255, np.uint8)
            rgba[..., :3] = rgb
            chains[j].append(rgba)
    return {
        "positions": doc.accessor(attributes["POSITION"]).astype(np.float32),
        "normals": doc.accessor(attributes["NORMAL"]).astype(np.float32),
        "uv": doc.accessor(attributes[f"TEXCOORD_{ext['texCoord']}"]).astype(np.float32),
        "indices": doc.accessor(primitive["indices"]).astype(np.uint32),
        "ext": ext,
        "chains": chains,
    }


def upload_chain(ctx, chain, dtype: str = "f1"):
    """A texture with the TAM levels as its mip chain: allocate the levels, then write each one (level i = i).

    ``f1`` is RGBA8 UNORM, what a runtime uploads; ``f4`` holds the same values (k / 255) as floats, so that the
    GPU's filtering is exact and only the module's arithmetic is compared with the twin."""
    import moderngl

    def data(level):
        return level.tobytes() if dtype == "f1" else (level.astype(np.float32) / np.float32(255.0)).tobytes()

    size = chain[0].shape[0]
    texture = ctx.texture((size, size), 4, data(chain[0]), dtype=dtype)
    texture.build_mipmaps(0, len(chain) - 1)  # allocates levels and sets BASE/MAX_LEVEL; contents replaced below
    for i, level in enumerate(chain):
        texture.write(data(level), level=i)
    texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = True
    return texture


@pytest.fixture(scope="module")
def renders(gl_context, baked_sphere):
    import moderngl

    ctx = gl_context
    b, ext = baked_sphere, baked_sphere["ext"]
    view_projection = perspective(35.0, 1.0, 0.5, 10.0) @ look_at(EYE, np.zeros(3), np.array([0.0, 1.0, 0.0]))
    matrix = view_projection.T.astype(np.float32).tobytes()
    buffers = [ctx.buffer(b[k].tobytes()) for k in ("positions", "normals", "uv")]
    index_buffer = ctx.buffer(b["indices"].tobytes())
    layout = list(zip(buffers, ("3f", "3f", "2f"), ("POSITION", "NORMAL", "TEXCOORD_0")))
    size = (SIZE, SIZE)
    depth = ctx.depth_renderbuffer(size)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.disable(moderngl.BLEND)
    uniforms = {"u_viewProjection": None, "u_scale": ext["scale"], "u_finestSize": float(ext["levels"][0]["size"]),
                "u_levelCount": float(len(ext["levels"])), "u_light": tuple(LIGHT)}

    def setup(prog):
        prog["u_viewProjection"].write(matrix)
        for name, value in uniforms.items():
            if value is not None and name in prog:
                prog[name].value = value

    out = {}
    inputs = program(ctx, "inputs")
    setup(inputs)
    target = ctx.texture(size, 4, dtype="f4")
    fbo = ctx.framebuffer([target], depth)
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, -1.0, depth=1.0)
    ctx.vertex_array(inputs, layout, index_buffer=index_buffer, index_element_size=4).render(moderngl.TRIANGLES)
    ctx.finish()
    out["inputs"] = np.frombuffer(target.read(), np.float32).reshape(SIZE, SIZE, 4)

    shade = program(ctx, "shade")
    setup(shade)
    shade["u_tonesA"].value = tuple(ext["tones"][:3])
    shade["u_tonesB"].value = tuple(ext["tones"][3:])
    vao = ctx.vertex_array(shade, layout, index_buffer=index_buffer, index_element_size=4)
    for texture_type in ("f1", "f4"):  # the TAM as RGBA8 (as a runtime uploads it) and as exact floats
        textures = [upload_chain(ctx, chain, texture_type) for chain in b["chains"]]
        for unit, (name, texture) in enumerate(zip(("u_tones012", "u_tones345"), textures)):
            texture.use(unit)
            shade[name].value = unit
        for dtype in ("u1", "f4"):  # target RGBA8 UNORM (read as bytes), and RGBA32F
            color = ctx.texture(size, 4, dtype="f1" if dtype == "u1" else dtype)
            fbo = ctx.framebuffer([color], depth)
            fbo.use()
            fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
            vao.render(moderngl.TRIANGLES)
            ctx.finish()
            out[texture_type, dtype] = np.frombuffer(color.read(), np.dtype(dtype)).reshape(SIZE, SIZE, 4)
    return out


def twin_image(renders, baked_sphere) -> np.ndarray:
    ext = baked_sphere["ext"]
    inputs = renders["inputs"]
    chains = [[level.astype(np.float32) / 255.0 for level in chain] for chain in baked_sphere["chains"]]
    return twins.baker_hatching(chains[0], chains[1], inputs[..., :2], inputs[..., 2], inputs[..., 3],
                                ext["tones"][:3], ext["tones"][3:])


def test_inputs_span_levels_and_tones(renders):
    inputs = renders["inputs"]
    covered = inputs[..., 3] >= 0.0
    assert 0.2 < covered.mean() < 0.8
    lod, dark = inputs[..., 2][covered], inputs[..., 3][covered]
    # the sphere samples at least two of the custom levels, and the whole range of tones
    assert lod.min() < 1.5 and lod.max() > 2.5
    assert dark.min() < 0.1 and dark.max() > 0.9


def test_render_matches_twin(renders, baked_sphere):
    """Float TAM textures: the GPU filters exactly, and the RGBA8 image must match the twin within 2/255 (in RGBA32F
    within float rounding). RGBA8 TAM textures, as a runtime uploads them: GPUs filter 8-bit textures with ~8-bit
    sub-texel weights (llvmpipe, like D3D-class hardware), which moves a stroke edge by up to ~2/255 more."""
    covered = renders["inputs"][..., 3] >= 0.0
    twin = np.clip(twin_image(renders, baked_sphere)[covered], 0.0, 1.0)
    for texture_type in ("f4", "f1"):
        image = renders[texture_type, "u1"]
        np.testing.assert_array_equal(image[..., 3] == 255, covered)
        gpu = image[..., 0][covered].astype(np.float32) / 255.0
        difference = np.abs(gpu - twin).max()
        unquantized = np.abs(renders[texture_type, "f4"][..., 0][covered] - twin).max()
        print(f"\nhatched sphere, TAM as {'RGBA8' if texture_type == 'f1' else 'RGBA32F'}: max |GPU - twin| = "
              f"{difference * 255:.3f}/255 (RGBA8 target), {unquantized * 255:.3f}/255 (RGBA32F target) over "
              f"{covered.sum()} pixels")
        if texture_type == "f4":
            assert difference <= TOLERANCE
            assert unquantized <= 1e-4
        else:
            assert difference <= 2 * TOLERANCE
            assert np.mean(np.abs(gpu - twin) > TOLERANCE) < 1e-3  # and only at a handful of stroke edges


def test_darkness_grows_from_lit_to_shadowed_side(renders):
    """Binned by the darkness asked for (1 - (0.5 + 0.5 N.L)), the rendered mean darkness rises bin after bin and
    stays close to what was asked: the blend of nested tones reproduces the tone."""
    inputs = renders["inputs"]
    covered = inputs[..., 3] >= 0.0
    asked = inputs[..., 3][covered]
    rendered = 1.0 - renders["f1", "u1"][..., 0][covered].astype(np.float64) / 255.0  # as a runtime renders it
    edges = np.linspace(0.0, 1.0, 9)
    means, centres = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (asked >= lo) & (asked < hi)
        if sel.sum() >= 200:
            means.append(rendered[sel].mean())
            centres.append(asked[sel].mean())
    means, centres = np.array(means), np.array(centres)
    print("\nasked   " + " ".join(f"{c:.3f}" for c in centres) + "\nrendered " + " ".join(f"{m:.3f}" for m in means))
    assert len(means) >= 6
    assert np.all(np.diff(means) > 0)
    assert np.abs(means - centres).max() < 0.06


# ---------------------------------------------------------------------------------------------------------- volume
def write_array_level(array, level: int, layers: np.ndarray) -> None:
    """glTexSubImage3D of one mip level of a GL_TEXTURE_2D_ARRAY (uint8 red, (layers, h, w))."""
    import ctypes

    egl = ctypes.CDLL("libEGL.so.1")
    egl.eglGetProcAddress.restype = ctypes.c_void_p
    egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
    sub_image = ctypes.CFUNCTYPE(None, *[ctypes.c_uint] + [ctypes.c_int] * 7 + [ctypes.c_uint] * 2 + [ctypes.c_void_p])(
        egl.eglGetProcAddress(b"glTexSubImage3D"))
    pixel_store = ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_int)(egl.eglGetProcAddress(b"glPixelStorei"))
    data = np.ascontiguousarray(layers, np.uint8)
    array.use(7)  # binds it to GL_TEXTURE_2D_ARRAY on unit 7 (the active unit)
    pixel_store(0x0CF5, 1)  # GL_UNPACK_ALIGNMENT
    sub_image(0x8C1A, level, 0, 0, 0, data.shape[2], data.shape[1], data.shape[0], 0x1903, 0x1401,
              data.ctypes.data)  # GL_TEXTURE_2D_ARRAY, GL_RED, GL_UNSIGNED_BYTE


def test_volume_matches_twin(gl_context):
    """Webb's volume TAM through a sampler2DArray with spatial-only mips, against the twin on random inputs."""
    import moderngl

    from baker.techniques.tam.options import TamOptions
    from baker.techniques.tam.kernel import generate_tam

    ctx = gl_context
    tones, levels = 8, 3
    tam = generate_tam(TamOptions(tones=tones, levels=levels, size=64, layout="volume"), seed=4)
    size = 64
    array = ctx.texture_array((size, size, tones), 1, tam.brightness_u8(0).tobytes())
    array.build_mipmaps(0, levels - 1)
    for i in range(1, levels):  # moderngl writes array levels > 0 only through GL itself
        write_array_level(array, i, tam.brightness_u8(i))
    array.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    array.repeat_x = array.repeat_y = True
    n = 48
    rng = np.random.default_rng(1)
    inputs = np.stack([rng.uniform(-2, 2, (n, n)), rng.uniform(-2, 2, (n, n)), rng.uniform(0, levels - 1, (n, n)),
                       rng.uniform(0, 1, (n, n))], -1).astype(np.float32)
    inputs[0, :4, 3] = (0.0, 1.0, tam.targets[-1], tam.targets[0])  # paper, black, exactly on two targets
    tex = ctx.texture((n, n), 4, inputs.tobytes(), dtype="f4")
    tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    prog = program(ctx, "volume")
    tex.use(0)
    array.use(1)
    prog["u_inputs"].value, prog["u_volume"].value = 0, 1
    prog["u_toneCount"].value, prog["u_darkest"].value = float(tones), float(tam.options.darkest)
    target = ctx.texture((n, n), 4, dtype="f4")
    fbo = ctx.framebuffer([target])
    fbo.use()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
    ctx.finish()
    gpu = np.frombuffer(target.read(), np.float32).reshape(n, n, 4)[..., 0]
    layers = [tam.brightness_u8(i).astype(np.float32) / 255.0 for i in range(levels)]
    twin = twins.baker_hatching_volume(layers, inputs[..., :2], inputs[..., 2], inputs[..., 3], tones,
                                       tam.options.darkest)
    assert np.abs(gpu - twin).max() <= TOLERANCE
    assert gpu[0, 0] == pytest.approx(1.0) and gpu[0, 1] == pytest.approx(0.0, abs=1e-6)


# ---------------------------------------------------------------------------------------------------------- toon
def test_toon_functions_match_twins(gl_context):
    import moderngl

    from baker.techniques.toon.options import ToonOptions
    from baker.techniques.toon.extension import toon_pixels

    ctx = gl_context
    n = 40
    rng = np.random.default_rng(5)
    inputs = np.stack([rng.uniform(-1.2, 1.2, (n, n)), rng.uniform(0, 1, (n, n)), rng.uniform(0.5, 80, (n, n)),
                       rng.uniform(0, 1, (n, n))], -1).astype(np.float32)
    colors = np.concatenate([rng.uniform(0, 1, (n, n, 3)), np.ones((n, n, 1))], -1).astype(np.float32)
    colors[0, 0, :3] = (0.5, 0.5, 0.5)  # gray: no hue
    colors[0, 1, :3] = (0.0, 0.0, 0.0)
    bands, softness, shadow, levels = 4.0, 0.3, 0.2, 4.0
    ramp_u8 = toon_pixels(ToonOptions(bands=4, softness=0.3, shadow=0.2))
    xtoon_u8 = toon_pixels(ToonOptions(bands=4, softness=0.3, shadow=0.2, xtoon="orientation", height=32))

    def float_texture(a):
        t = ctx.texture((a.shape[1], a.shape[0]), 4, a.tobytes(), dtype="f4")
        t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return t

    def gray_texture(a):
        t = ctx.texture((a.shape[1], a.shape[0]), 1, np.ascontiguousarray(a).tobytes())
        t.filter = (moderngl.LINEAR, moderngl.LINEAR)
        t.repeat_x = t.repeat_y = False
        return t

    prog = program(ctx, "toon")
    for unit, (name, tex) in enumerate((("u_inputs", float_texture(inputs)), ("u_colors", float_texture(colors)),
                                        ("u_ramp", gray_texture(ramp_u8)), ("u_xtoon", gray_texture(xtoon_u8)))):
        tex.use(unit)
        prog[name].value = unit
    for name, value in (("u_bands", bands), ("u_softness", softness), ("u_shadow", shadow), ("u_levels", levels)):
        prog[name].value = value
    targets = [ctx.texture((n, n), 4, dtype="f4") for _ in range(3)]
    fbo = ctx.framebuffer(targets)
    fbo.use()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
    ctx.finish()
    shades, hsv, ycc = (np.frombuffer(t.read(), np.float32).reshape(n, n, 4) for t in targets)

    ramp = ramp_u8[..., None].astype(np.float32) / 255.0
    xmap = xtoon_u8[..., None].astype(np.float32) / 255.0
    ndl, detail, z, u = (inputs[..., k] for k in range(4))
    assert np.abs(shades[..., 0] - toon_twins.baker_toon_ramp(ramp, ndl)).max() <= TOLERANCE
    assert np.abs(shades[..., 1] - toon_twins.baker_xtoon(xmap, ndl, detail)).max() <= TOLERANCE
    np.testing.assert_allclose(shades[..., 2], toon_twins.baker_toon_bands(u, bands, softness, shadow), atol=1e-5)
    np.testing.assert_allclose(shades[..., 3], toon_twins.baker_xtoon_detail_depth(z, 1.0, 50.0), atol=1e-5)
    rgb = colors[..., :3]
    np.testing.assert_allclose(hsv[..., :3], toon_twins.baker_posterize_hsv(rgb, levels), atol=1e-5)
    np.testing.assert_allclose(ycc[..., :3], toon_twins.baker_posterize_ycbcr(rgb, levels), atol=1e-5)
    centred = rgb - np.float32(0.37)
    normal = centred / np.linalg.norm(centred, axis=-1, keepdims=True)
    np.testing.assert_allclose(hsv[..., 3], toon_twins.baker_xtoon_detail_orientation(normal, [0, 0, 1], 2.0), atol=1e-5)
    # hue-preserving: posterized colours keep their hue (where saturated enough to have one)
    before, after = toon_twins.baker_rgb_to_hsv(rgb), toon_twins.baker_rgb_to_hsv(hsv[..., :3])
    sel = (before[..., 1] > 0.1) & (after[..., 2] > 0.05)
    hue_shift = np.abs(((before[..., 0] - after[..., 0]) + 0.5) % 1.0 - 0.5)[sel]
    assert hue_shift.max() < 1e-4
    assert len(np.unique(np.round(after[..., 2], 5))) <= levels
