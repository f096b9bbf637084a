"""``runtime-shaders/baker_translucency.glsl``: compiles as GLSL ES 3.00 and 3.30 core, and renders what its twin says.

The render test goes through the whole data path: bake an icosphere, write the .glb, load the written file back, and
feed its POSITION / NORMAL / _THICKNESS accessors and BAKER_thickness parameters to the GPU (moderngl, EGL, llvmpipe).
Pass 1 stores the interpolated inputs the fragment shader sees in RGBA32F targets; pass 2 shades with the module into
RGBA8; the numpy twin shades pass 1's inputs and must agree within 2/255 on every covered pixel.
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
from baker.gltf.vertex_attributes import unpadded
from baker.pipeline import save

from . import twins_translucency as twins

from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
MODULE_PATH = REPO / "runtime-shaders" / "baker_translucency.glsl"
MODULE = MODULE_PATH.read_text()

# The includer's header (the module has none). highp sampler2D: WebGL2 defaults samplers to lowp in fragment shaders,
# too coarse for a 16-bit thickness texture.

SIZE = 256
TOLERANCE = 2.0 / 255.0

# ---------------------------------------------------------------------------------------------------------- shaders
SPHERE_VS = """
in vec3 POSITION;
in vec3 NORMAL;
in float _THICKNESS;
uniform mat4 u_viewProjection;
out vec3 v_position;
out vec3 v_normal;
out float v_thickness;
void main() {
    v_position = POSITION;  // model matrix = identity: mesh units are world units
    v_normal = NORMAL;
    v_thickness = _THICKNESS;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""

# pass 1: exactly what the shading pass's fragment shader receives, before it touches it
INPUTS_FS = """
in vec3 v_position;
in vec3 v_normal;
in float v_thickness;
layout(location = 0) out vec4 o_normalThickness;
layout(location = 1) out vec4 o_positionCovered;
void main() {
    o_normalThickness = vec4(v_normal, v_thickness);
    o_positionCovered = vec4(v_position, 1.0);
}
"""

# pass 2: a point light's translucent contribution; u_variant 0 = RTR4 eq. 14.30, 1 = GDC 2011 (through the struct)
SHADE_FS = """
in vec3 v_position;
in vec3 v_normal;
in float v_thickness;
uniform vec3 u_eye;
uniform vec3 u_lightPosition;
uniform vec3 u_lightColor;
uniform BakerThickness u_bakerThickness;
uniform int u_variant;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_position);
    vec3 L = normalize(u_lightPosition - v_position);
    vec3 translucency;
    if (u_variant == 0) {
        float tss = baker_thickness_transmittance(v_thickness, u_bakerThickness.attenuationDistance);
        translucency = baker_translucency_rtr(V, L, tss, u_bakerThickness.subsurfaceColor, u_bakerThickness.power);
    } else {
        translucency = baker_translucency(u_bakerThickness, N, V, L, v_thickness);
    }
    o_color = vec4(translucency * u_lightColor, 1.0);
}
"""

FULLSCREEN_VS = """
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));  // one triangle over the viewport
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

# one fragment per texel of KHR_materials_volume.thicknessTexture, sampled the way a runtime would (texture())
TEXTURE_FS = """
uniform sampler2D u_thicknessTexture;
uniform float u_thicknessFactor;
uniform float u_attenuationDistance;
layout(location = 0) out vec4 o_thickness;
void main() {
    vec2 uv = gl_FragCoord.xy / vec2(textureSize(u_thicknessTexture, 0));
    float thickness = baker_thickness_from_texture(texture(u_thicknessTexture, uv), u_thicknessFactor);
    o_thickness = vec4(thickness, baker_thickness_transmittance(thickness, u_attenuationDistance), 0.0, 1.0);
}
"""

# each function on arbitrary inputs read from float textures: edge cases a sphere never produces
FUNCTIONS_FS = """
uniform sampler2D u_n;
uniform sampler2D u_v;
uniform sampler2D u_l;
uniform sampler2D u_scalars;  // thickness, attenuationDistance, power, distortion
uniform vec3 u_subsurfaceColor;
uniform float u_scale;
uniform float u_ambient;
layout(location = 0) out vec4 o_rtr;
layout(location = 1) out vec4 o_gdc;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 N = texelFetch(u_n, p, 0).xyz;
    vec3 V = texelFetch(u_v, p, 0).xyz;
    vec3 L = texelFetch(u_l, p, 0).xyz;
    vec4 s = texelFetch(u_scalars, p, 0);
    float tss = baker_thickness_transmittance(s.x, s.y);
    o_rtr = vec4(baker_translucency_rtr(V, L, tss, u_subsurfaceColor, s.z), tss);
    o_gdc = vec4(baker_translucency_gdc(N, V, L, tss, u_subsurfaceColor, s.w, s.z, u_scale, u_ambient), 1.0);
}
"""

PROGRAMS = {
    "inputs": (SPHERE_VS, INPUTS_FS),
    "shade": (SPHERE_VS, SHADE_FS),
    "texture": (FULLSCREEN_VS, TEXTURE_FS),
    "functions": (FULLSCREEN_VS, FUNCTIONS_FS),
}


def shader_source(version: str, body: str) -> str:
    """A complete shader stage: the includer's header, the module, then the stage's own code."""
    return HEADERS[version] + MODULE + body


def program(ctx, name: str, version: str = "330 core"):
    vs, fs = PROGRAMS[name]
    return ctx.program(vertex_shader=shader_source(version, vs), fragment_shader=shader_source(version, fs))


# ---------------------------------------------------------------------------------------------------------- module
def test_module_has_the_documented_functions():
    code = re.sub(r"//[^\n]*", "", MODULE)
    for name in ("baker_thickness_from_texture", "baker_thickness_transmittance", "baker_translucency_rtr",
                 "baker_translucency_gdc", "baker_translucency"):
        assert re.search(rf"\b{name}\s*\(", code), name
        assert hasattr(twins, name), f"no numpy twin for {name}"


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    body = PROGRAMS[name][0 if stage == "vert" else 1]
    assert_compiles(glslang_validator, tmp_path, version, name, stage, shader_source(version, body))


# ---------------------------------------------------------------------------------------------------------- baked sphere
SPHERE_OPTIONS = {
    "rays": 32,
    "per_texel": False,
    # away from the defaults, so the round trip proves the runtime reads the written values (and RGB stays apart)
    "subsurface_color": (1.0, 0.45, 0.3),
    "ambient": 0.05,
    "distortion": 0.3,
    "power": 3.0,
}


@pytest.fixture(scope="module")
def baked_sphere(tmp_path_factory):
    """An icosphere (r = 1) baked and written to .glb, then read back from the file: arrays and BAKER_thickness."""
    folder = tmp_path_factory.mktemp("sphere")
    source = folder / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=4, radius=1.0).export(str(source), include_normals=True)
    asset = baker.bake(str(source), bakes=["thickness"], options={"thickness": SPHERE_OPTIONS})
    out = folder / "sphere_baked.glb"
    save(asset, out)

    doc = GltfDocument.load(out)
    primitive = doc.json["meshes"][0]["primitives"][0]
    material = doc.json["materials"][primitive["material"]]
    params = material["extensions"]["BAKER_thickness"]
    attributes = primitive["attributes"]
    thickness_accessor = doc.json["accessors"][attributes[params["attribute"]]]
    return {
        "positions": doc.accessor(attributes["POSITION"]).astype(np.float32),
        "normals": doc.accessor(attributes["NORMAL"]).astype(np.float32),
        "thickness": unpadded(doc.accessor(attributes[params["attribute"]]), 1).astype(np.float32),
        # as written (a thickness-only bake: SCALAR, the widest data of the run; VEC3 beside vectors, the value in
        # x), bound at its width to `in float _THICKNESS` (GL reads x of a wider buffer)
        "thickness_written": doc.accessor(attributes[params["attribute"]]).astype(np.float32),
        "thickness_range": (thickness_accessor["min"][0], thickness_accessor["max"][0]),
        "indices": doc.accessor(primitive["indices"]).astype(np.uint32),
        "params": params,
    }


def test_written_parameters(baked_sphere):
    """The file carries what the runtime needs, under the names of the GLSL struct's fields."""
    params = baked_sphere["params"]
    fields = re.search(r"struct\s+BakerThickness\s*\{(.*?)\}", MODULE, re.S).group(1)
    names = re.findall(r"^\s*(?:float|vec3|int)\s+(\w+)\s*;", fields, re.M)
    assert sorted(names) == sorted(["attenuationDistance", "distortion", "power", "scale", "ambient",
                                    "subsurfaceColor"])
    for name in names:
        assert name in params, name
    assert params["attribute"] == "_THICKNESS" and "thicknessTexture" not in params
    assert params["subsurfaceColor"] == list(SPHERE_OPTIONS["subsurface_color"])
    assert (params["ambient"], params["distortion"], params["power"]) == (0.05, 0.3, 3.0)


def look_at(eye, target, up) -> np.ndarray:
    f = (target - eye) / np.linalg.norm(target - eye)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fovy_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    f = 1.0 / math.tan(math.radians(fovy_deg) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


EYE = np.array([0.0, 0.0, 4.0])
LIGHT_COLOR = np.array([1.6, 1.5, 1.4], np.float32)
LIGHTS = {
    # behind the sphere and off axis: light leaks through towards the eye on the +x, +y side
    "back": np.array([0.8, 0.5, -3.0]),
    # in front: (v . -l) < 0 everywhere, eq. 14.30 is black
    "front": np.array([0.8, 0.5, 3.0]),
}
VARIANTS = {"rtr": 0, "gdc": 1}


@pytest.fixture(scope="module")
def renders(gl_context, baked_sphere):
    """Pass 1 (inputs, RGBA32F) once, pass 2 (shaded, RGBA8) for every light x variant."""
    import moderngl

    ctx = gl_context
    b = baked_sphere
    view_projection = perspective(35.0, 1.0, 0.5, 10.0) @ look_at(EYE, np.zeros(3), np.array([0.0, 1.0, 0.0]))
    matrix = view_projection.T.astype(np.float32).tobytes()  # GLSL matrices are column-major

    buffers = [ctx.buffer(b[k].tobytes()) for k in ("positions", "normals", "thickness_written")]
    index_buffer = ctx.buffer(b["indices"].tobytes())
    written = b["thickness_written"]
    formats = ("3f", "3f", f"{1 if written.ndim == 1 else written.shape[1]}f")
    layout = list(zip(buffers, formats, ("POSITION", "NORMAL", "_THICKNESS")))
    size = (SIZE, SIZE)
    depth = ctx.depth_renderbuffer(size)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.disable(moderngl.BLEND)

    inputs = program(ctx, "inputs")
    inputs["u_viewProjection"].write(matrix)
    normal_thickness, position_covered = ctx.texture(size, 4, dtype="f4"), ctx.texture(size, 4, dtype="f4")
    fbo = ctx.framebuffer([normal_thickness, position_covered], depth)
    fbo.use()
    fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.vertex_array(inputs, layout, index_buffer=index_buffer, index_element_size=4).render(moderngl.TRIANGLES)
    ctx.finish()
    out = {
        "normal_thickness": np.frombuffer(normal_thickness.read(), np.float32).reshape(SIZE, SIZE, 4),
        "position_covered": np.frombuffer(position_covered.read(), np.float32).reshape(SIZE, SIZE, 4),
    }

    shade = program(ctx, "shade")
    shade["u_viewProjection"].write(matrix)
    shade["u_eye"].value = tuple(EYE)
    shade["u_lightColor"].value = tuple(LIGHT_COLOR.tolist())
    p = b["params"]
    shade["u_bakerThickness.attenuationDistance"].value = p["attenuationDistance"]
    shade["u_bakerThickness.distortion"].value = p["distortion"]
    shade["u_bakerThickness.power"].value = p["power"]
    shade["u_bakerThickness.scale"].value = p["scale"]
    shade["u_bakerThickness.ambient"].value = p["ambient"]
    shade["u_bakerThickness.subsurfaceColor"].value = tuple(p["subsurfaceColor"])
    # RGBA8 UNORM, what a real framebuffer quantizes to; RGBA32F, to see the arithmetic differences 8 bits hide
    targets = {"u1": ctx.texture(size, 4), "f4": ctx.texture(size, 4, dtype="f4")}
    vao = ctx.vertex_array(shade, layout, index_buffer=index_buffer, index_element_size=4)
    for light_name, light in LIGHTS.items():
        for variant, code in VARIANTS.items():
            shade["u_lightPosition"].value = tuple(light)
            shade["u_variant"].value = code
            for dtype, color in targets.items():
                fbo = ctx.framebuffer([color], depth)
                fbo.use()
                fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
                vao.render(moderngl.TRIANGLES)
                ctx.finish()
                out[light_name, variant, dtype] = np.frombuffer(color.read(), np.dtype(dtype)).reshape(SIZE, SIZE, 4)
            out[light_name, variant] = out[light_name, variant, "u1"]
    return out


def twin_image(renders, params, light, variant) -> np.ndarray:
    """The twin's RGB for every pixel, from pass 1's inputs (same float32 math as SHADE_FS)."""
    nt, pc = renders["normal_thickness"], renders["position_covered"]
    position, thickness = pc[..., :3], nt[..., 3]
    with np.errstate(invalid="ignore", divide="ignore"):  # uncovered pixels have zero normals
        N = twins.normalize(nt[..., :3])
        V = twins.normalize(EYE.astype(np.float32) - position)
        L = twins.normalize(light.astype(np.float32) - position)
        if variant == "rtr":
            tss = twins.baker_thickness_transmittance(thickness, params["attenuationDistance"])
            rgb = twins.baker_translucency_rtr(V, L, tss, params["subsurfaceColor"], params["power"])
        else:
            rgb = twins.baker_translucency(params, N, V, L, thickness)
    return np.clip(rgb * LIGHT_COLOR, 0.0, 1.0)


def test_pass1_inputs(renders, baked_sphere):
    covered = renders["position_covered"][..., 3] > 0.5
    assert 0.2 < covered.mean() < 0.8  # the sphere fills a good part of the frame, not all of it
    thickness = renders["normal_thickness"][..., 3][covered]
    low, high = baked_sphere["thickness_range"]
    assert thickness.min() >= low - 1e-5 and thickness.max() <= high + 1e-5
    # cosine-weighted mean chord of a unit sphere is 4/3 (see baker.techniques.thickness.kernel)
    assert abs(np.median(thickness) - 4.0 / 3.0) < 0.05


@pytest.mark.parametrize("variant", sorted(VARIANTS))
@pytest.mark.parametrize("light", sorted(LIGHTS))
def test_render_matches_twin(renders, baked_sphere, light, variant):
    covered = renders["position_covered"][..., 3] > 0.5
    image = renders[light, variant]
    # the same rasterization in both passes: exactly the same pixels are covered
    np.testing.assert_array_equal(image[..., 3] == 255, covered)
    gpu = image[..., :3][covered].astype(np.float32) / 255.0
    twin = twin_image(renders, baked_sphere["params"], LIGHTS[light], variant)[covered]
    difference = np.abs(gpu - twin).max()
    # the same image unquantized: only float32 arithmetic differences (llvmpipe's pow/exp/inversesqrt) remain
    unquantized = np.abs(renders[light, variant, "f4"][..., :3][covered] - twin).max()
    print(f"\n{light}-lit {variant}: max |GPU - twin| = {difference * 255:.3f}/255 (RGBA8), "
          f"{unquantized:.2e} (RGBA32F) over {covered.sum()} pixels")
    assert difference <= TOLERANCE
    assert unquantized <= 1e-5


@pytest.mark.parametrize("variant", sorted(VARIANTS))
def test_render_is_not_trivial(renders, variant):
    covered = renders["position_covered"][..., 3] > 0.5
    back = renders["back", variant][..., :3].astype(np.float32) / 255.0
    front = renders["front", variant][..., :3].astype(np.float32) / 255.0
    assert back.max() > 0.1
    # back light shines through; a front light does not (only the GDC ambient term is left)
    assert back[covered].mean() > 3.0 * front[covered].mean()
    if variant == "rtr":
        assert front.max() == 0.0
    # the spot sits where the light is, on the +x +y side (weighed without GDC's view-independent ambient term)
    weight = np.maximum(back - front, 0.0).sum(axis=-1)[covered]
    position = renders["position_covered"][..., :3][covered]
    centroid = (position * weight[:, None]).sum(axis=0) / weight.sum()
    assert centroid[0] > 0.02
    # in the plane through the eye, the light and the centre: y / x as for the light, 0.5 / 0.8
    assert abs(centroid[1] / centroid[0] - 0.625) < 0.05
    # c_ss = (1, 0.45, 0.3) tints it: red > green > blue wherever it is lit
    lit = back.max(axis=-1) > 0.05
    assert np.all(back[lit][:, 0] > back[lit][:, 1]) and np.all(back[lit][:, 1] > back[lit][:, 2])


def test_distortion_changes_the_image(renders):
    """The GDC variant is not eq. 14.30 under another name: the normal bends the light."""
    rtr = renders["back", "rtr"][..., :3].astype(np.int32)
    gdc = renders["back", "gdc"][..., :3].astype(np.int32)
    assert np.abs(rtr - gdc).max() > 10


# ---------------------------------------------------------------------------------------------------------- texture path
@pytest.fixture(scope="module")
def baked_texture(tmp_path_factory):
    """A small thickness texture baked, written into the .glb, and decoded back from the written file."""
    folder = tmp_path_factory.mktemp("sphere_texture")
    source = folder / "sphere.glb"
    trimesh.creation.icosphere(subdivisions=3, radius=1.0).export(str(source))
    asset = baker.bake(str(source), bakes=["thickness"],
                       options={"thickness": {"rays": 32, "per_vertex": False, "texture_size": 32,
                                                  "texture_bits": 16}})  # the 16-bit PNG path (8 is the default)
    out = folder / "sphere_baked.glb"
    save(asset, out)

    doc = GltfDocument.load(out)
    material = doc.json["materials"][doc.json["meshes"][0]["primitives"][0]["material"]]
    volume = material["extensions"]["KHR_materials_volume"]
    image = doc.json["images"][doc.json["textures"][volume["thicknessTexture"]["index"]]["source"]]
    view = doc.json["bufferViews"][image["bufferView"]]
    png = bytes(doc.bin[view["byteOffset"]: view["byteOffset"] + view["byteLength"]])
    return {
        "pixels": decode_image(png, ".png"),
        "factor": volume["thicknessFactor"],
        "params": material["extensions"]["BAKER_thickness"],
    }


def test_texture_path_matches_twin(gl_context, baked_texture):
    import moderngl

    ctx = gl_context
    gray = baked_texture["pixels"]
    assert gray.dtype == np.uint16 and gray.ndim == 3 and gray.shape[2] == 1
    h, w = gray.shape[:2]
    # only GREEN carries thickness (KHR_materials_volume); red and blue hold decoys a wrong channel would pick up
    rgba = np.empty((h, w, 4), np.uint16)
    rgba[..., 0] = 65535 - gray[..., 0]
    rgba[..., 1] = gray[..., 0]
    rgba[..., 2] = 12345
    rgba[..., 3] = 65535
    texture = ctx.texture((w, h), 4, rgba.tobytes(), dtype="nu2")  # RGBA16 UNORM, as a 16-bit PNG is uploaded
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    target = ctx.texture((w, h), 4, dtype="f4")
    fbo = ctx.framebuffer([target])

    prog = program(ctx, "texture")
    prog["u_thicknessTexture"].value = 0
    prog["u_thicknessFactor"].value = baked_texture["factor"]
    prog["u_attenuationDistance"].value = baked_texture["params"]["attenuationDistance"]
    texture.use(0)
    fbo.use()
    fbo.clear()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
    ctx.finish()
    gpu = np.frombuffer(target.read(), np.float32).reshape(h, w, 4)

    texel = rgba.astype(np.float32) / np.float32(65535.0)
    thickness = twins.baker_thickness_from_texture(texel, baked_texture["factor"])
    tss = twins.baker_thickness_transmittance(thickness, baked_texture["params"]["attenuationDistance"])
    np.testing.assert_allclose(gpu[..., 0], thickness, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(gpu[..., 1], tss, rtol=1e-5, atol=1e-6)
    # and it is the baked thickness: about 4/3 of the radius on a unit sphere
    assert abs(np.median(thickness) - 4.0 / 3.0) < 0.1


# ---------------------------------------------------------------------------------------------------------- functions
def test_functions_match_twins_on_edge_cases(gl_context):
    """Each function on random and degenerate inputs (grazing, opposite, L + N * distortion = 0, zero thickness)."""
    import moderngl

    ctx = gl_context
    rng = np.random.default_rng(7)
    n = 32

    def unit(shape):
        v = rng.normal(size=shape + (3,))
        return (v / np.linalg.norm(v, axis=-1, keepdims=True)).astype(np.float32)

    N, V, L = unit((n, n)), unit((n, n)), unit((n, n))
    scalars = np.stack([rng.uniform(0.0, 3.0, (n, n)), rng.uniform(0.2, 2.0, (n, n)),
                        rng.uniform(0.5, 8.0, (n, n)), rng.uniform(0.0, 1.0, (n, n))], axis=-1).astype(np.float32)
    # row 0: degenerate cases
    L[0, 0], N[0, 0], scalars[0, 0, 3] = (0, 0, 1), (0, 0, -1), 1.0        # L + N * distortion = 0
    V[0, 1], L[0, 1] = (0, 0, 1), (0, 0, -1)                               # light straight behind: dot = 1
    V[0, 2], L[0, 2] = (0, 0, 1), (0, 0, 1)                                # light in front: dot = -1
    V[0, 3], L[0, 3] = (1, 0, 0), (0, 0, 1)                                # grazing: dot = 0
    scalars[0, 4, 0] = 0.0                                                 # zero thickness: tss = 1
    scalars[0, 5, 0] = -0.5                                                # negative (never baked): clamped to 0
    color, scale, ambient = (0.9, 0.6, 0.3), 1.7, 0.08

    def upload(a):
        rgba = np.zeros((n, n, 4), np.float32)
        rgba[..., : a.shape[-1]] = a
        t = ctx.texture((n, n), 4, rgba.tobytes(), dtype="f4")
        t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return t

    prog = program(ctx, "functions")
    for unit_index, (name, data) in enumerate((("u_n", N), ("u_v", V), ("u_l", L), ("u_scalars", scalars))):
        upload(data).use(unit_index)
        prog[name].value = unit_index
    prog["u_subsurfaceColor"].value = color
    prog["u_scale"].value = scale
    prog["u_ambient"].value = ambient
    rtr_target, gdc_target = ctx.texture((n, n), 4, dtype="f4"), ctx.texture((n, n), 4, dtype="f4")
    fbo = ctx.framebuffer([rtr_target, gdc_target])
    fbo.use()
    fbo.clear()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
    ctx.finish()
    rtr_gpu = np.frombuffer(rtr_target.read(), np.float32).reshape(n, n, 4)
    gdc_gpu = np.frombuffer(gdc_target.read(), np.float32).reshape(n, n, 4)

    tss = twins.baker_thickness_transmittance(scalars[..., 0], scalars[..., 1])
    rtr = twins.baker_translucency_rtr(V, L, tss, color, scalars[..., 2])
    gdc = twins.baker_translucency_gdc(N, V, L, tss, color, scalars[..., 3], scalars[..., 2], scale, ambient)
    assert np.all(np.isfinite(rtr_gpu)) and np.all(np.isfinite(gdc_gpu))
    np.testing.assert_allclose(rtr_gpu[..., 3], tss, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(rtr_gpu[..., :3], rtr, rtol=2e-5, atol=1e-6)
    np.testing.assert_allclose(gdc_gpu[..., :3], gdc, rtol=2e-5, atol=1e-6)
    # the degenerate rows say what they should
    np.testing.assert_allclose(gdc[0, 0], np.float32(ambient) * tss[0, 0] * np.float32(color), rtol=1e-6)
    np.testing.assert_allclose(rtr[0, 1], tss[0, 1] * np.float32(color), rtol=1e-6)
    assert np.all(rtr[0, 2] == 0) and np.all(rtr[0, 3] == 0)
    assert tss[0, 4] == 1.0 and tss[0, 5] == 1.0
