"""``runtime-shaders/baker_normal_blur.glsl``: compiles as GLSL ES 3.00 and 3.30 core, and renders what its twin says.

The data is a real bake: a bumped sphere (tests/techniques/test_normal_blur.py) baked with ``normal-blur``, the .glb
written and read back, its three diffuse maps, smoothed map, stretch map and parameters fed to the GPU (moderngl,
EGL, llvmpipe). A full-screen quad puts one fragment on each texel centre; each variant shades with the module into
RGBA8 and the numpy twin (tests/gl/twins_normal_blur.py) must agree within 2/255 on every pixel.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import baker
from baker.gltf.document import GltfDocument
from baker.gltf.images import decode_image
from baker.pipeline import save
from tests.techniques.test_normal_blur import bump_sphere

from . import twins_normal_blur as twins
from .glsl import HEADERS, assert_compiles

REPO = Path(__file__).parents[2]
MODULE = (REPO / "runtime-shaders" / "baker_normal_blur.glsl").read_text()
SIZE = 128
TOLERANCE = 2.0 / 255.0
LIGHT = np.array([0.5, 0.3, 0.8]) / np.linalg.norm([0.5, 0.3, 0.8])
ANGLE = 0.4  # the test's TBN: a turn about (1, 1, 0) / sqrt 2
AXIS = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
TBN = (np.cos(ANGLE) * np.eye(3) + np.sin(ANGLE) * np.array([[0, -AXIS[2], AXIS[1]], [AXIS[2], 0, -AXIS[0]],
                                                              [-AXIS[1], AXIS[0], 0]])
       + (1 - np.cos(ANGLE)) * np.outer(AXIS, AXIS))
SIGMA = 0.0015  # m, one of the TSD passes

# the quad is drawn as a TSD pass draws a mesh: its corners' UVs through baker_normal_blur_uv_position (a wrong
# mapping moves every pixel and fails every variant)
VS = """
in vec2 a_position;
out vec2 v_uv;
void main() {
    v_uv = a_position * 0.5 + 0.5;
    gl_Position = baker_normal_blur_uv_position(v_uv);
}
"""

# u_variant: 0 per-channel Lambert from the three maps, 1 Penner's blend (N.L remapped to 0..1), 2 TSD step along u,
# 3 TSD step along v, 4 the two steps' results accumulated with RGB weights
FS = """
in vec2 v_uv;
uniform sampler2D u_red;
uniform sampler2D u_green;
uniform sampler2D u_blue;
uniform sampler2D u_smoothed;
uniform sampler2D u_stretch;
uniform sampler2D u_irradiance;
uniform mat3 u_tbn;
uniform vec3 u_light;
uniform vec3 u_channelBlend;
uniform float u_stretchScale;
uniform float u_sigma;
uniform float u_flipY;
uniform int u_variant;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 rgb;
    if (u_variant == 0) {
        rgb = baker_normal_blur_lambert(u_tbn, texture(u_red, v_uv).rgb, texture(u_green, v_uv).rgb,
                                        texture(u_blue, v_uv).rgb, u_light, u_flipY);
    } else if (u_variant == 1) {
        rgb = baker_normal_blur_blend_ndotl(u_tbn, texture(u_smoothed, v_uv).rgb, u_channelBlend, u_light, u_flipY)
            * 0.5 + 0.5;
    } else if (u_variant == 4) {
        vec3 along_u = baker_normal_blur_tsd_step(u_irradiance, u_stretch, v_uv, vec2(1.0, 0.0), u_sigma, u_stretchScale);
        vec3 along_v = baker_normal_blur_tsd_step(u_irradiance, u_stretch, v_uv, vec2(0.0, 1.0), u_sigma, u_stretchScale);
        rgb = baker_normal_blur_tsd_accumulate(baker_normal_blur_tsd_accumulate(vec3(0.0), along_u, vec3(0.6, 0.3, 0.1)),
                                               along_v, vec3(0.4, 0.7, 0.9));
    } else {
        vec2 direction = u_variant == 2 ? vec2(1.0, 0.0) : vec2(0.0, 1.0);
        rgb = baker_normal_blur_tsd_step(u_irradiance, u_stretch, v_uv, direction, u_sigma, u_stretchScale);
    }
    o_color = vec4(rgb, 1.0);
}
"""
VARIANTS = {"lambert": 0, "blend": 1, "tsd_u": 2, "tsd_v": 3, "tsd_sum": 4}


def source(version: str, body: str) -> str:
    return HEADERS[version] + MODULE + body


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, stage):
    assert_compiles(glslang_validator, tmp_path, version, "normal_blur", stage,
                    source(version, VS if stage == "vert" else FS))


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    folder = tmp_path_factory.mktemp("normal_blur_gl")
    source_path = bump_sphere(folder / "sphere.glb", "v", segments=64, rings=64, size=SIZE)
    out = folder / "blurred.glb"
    save(baker.bake(source_path, bakes=["normal-blur"]), out)
    doc = GltfDocument.load(out)
    ext = doc.json["materials"][0]["extensions"]["BAKER_normal_blur"]

    def image(info):
        return decode_image(doc.image_bytes(doc.json["textures"][info["index"]]["source"]), ".png")

    u, v = np.meshgrid((np.arange(SIZE) + 0.5) / SIZE, (np.arange(SIZE) + 0.5) / SIZE)
    irradiance = np.stack([0.5 + 0.5 * np.sin(40 * u), 0.5 + 0.5 * np.sin(25 * v), (u * v)], -1)
    return {"ext": ext, "maps": [image(i) for i in ext["diffuseNormalTextures"]],
            "smoothed": image(ext["smoothedNormalTexture"]), "stretch": image(ext["stretchTexture"]),
            "irradiance": np.rint(irradiance * 255).astype(np.uint8)}


def upload(ctx, pixels):
    import moderngl

    pixels = np.ascontiguousarray(pixels)
    dtype = "nu2" if pixels.dtype == np.uint16 else "f1"
    texture = ctx.texture((pixels.shape[1], pixels.shape[0]), pixels.shape[2], pixels.tobytes(), dtype=dtype,
                          alignment=1 if dtype == "f1" else 2)
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = False
    return texture


@pytest.fixture(scope="module")
def renders(gl_context, baked):
    import moderngl

    ctx = gl_context
    program = ctx.program(vertex_shader=source("330 core", VS), fragment_shader=source("330 core", FS))
    # row 0 of an image is t = 0: the quad's bottom row of pixels (y = -1) reads v ~ 0, as the read-back's row 0
    quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32).tobytes())
    vao = ctx.vertex_array(program, [(quad, "2f", "a_position")])
    names = ["u_red", "u_green", "u_blue", "u_smoothed", "u_stretch", "u_irradiance"]
    images = [*baked["maps"], baked["smoothed"], baked["stretch"], baked["irradiance"]]
    for unit, (name, pixels) in enumerate(zip(names, images)):
        upload(ctx, pixels).use(unit)
        program[name].value = unit
    ext = baked["ext"]
    program["u_tbn"].write(TBN.T.astype(np.float32).tobytes())  # column-major: columns T, B, N
    program["u_light"].value = tuple(LIGHT)
    program["u_channelBlend"].value = tuple(ext["channelBlend"])
    program["u_stretchScale"].value = ext["stretchScale"]
    program["u_sigma"].value = SIGMA
    program["u_flipY"].value = 1.0
    color = ctx.texture((SIZE, SIZE), 4)
    fbo = ctx.framebuffer([color])
    out = {}
    for name, code in VARIANTS.items():
        program["u_variant"].value = code
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        vao.render(moderngl.TRIANGLE_STRIP)
        ctx.finish()
        out[name] = np.frombuffer(color.read(), np.uint8).reshape(SIZE, SIZE, 4)
    return out


def twin_image(baked, variant):
    u, v = np.meshgrid((np.arange(SIZE) + 0.5) / SIZE, (np.arange(SIZE) + 0.5) / SIZE)
    uv = np.stack([u, v], -1).astype(np.float32)
    f = lambda a: a.astype(np.float32) / np.float32(np.iinfo(a.dtype).max)  # noqa: E731
    ext = baked["ext"]
    if variant == "lambert":
        return twins.baker_normal_blur_lambert(TBN, *(f(m)[..., :3] for m in baked["maps"]), LIGHT, 1.0)
    if variant == "blend":
        return twins.baker_normal_blur_blend_ndotl(TBN, f(baked["smoothed"])[..., :3], ext["channelBlend"], LIGHT,
                                                   1.0) * np.float32(0.5) + np.float32(0.5)
    if variant == "tsd_sum":
        steps = [twins.baker_normal_blur_tsd_step(f(baked["irradiance"]), f(baked["stretch"]), uv, d, SIGMA,
                                                  ext["stretchScale"]) for d in ((1.0, 0.0), (0.0, 1.0))]
        total = twins.baker_normal_blur_tsd_accumulate(np.zeros_like(steps[0]), steps[0], (0.6, 0.3, 0.1))
        return twins.baker_normal_blur_tsd_accumulate(total, steps[1], (0.4, 0.7, 0.9))
    direction = (1.0, 0.0) if variant == "tsd_u" else (0.0, 1.0)
    return twins.baker_normal_blur_tsd_step(f(baked["irradiance"]), f(baked["stretch"]), uv, direction, SIGMA,
                                            ext["stretchScale"])


@pytest.mark.parametrize("variant", sorted(VARIANTS))
def test_render_matches_twin(renders, baked, variant):
    gpu = renders[variant][..., :3].astype(np.float32) / 255.0
    twin = np.clip(twin_image(baked, variant), 0.0, 1.0)
    difference = np.abs(gpu - twin).max()
    print(f"\n{variant}: max |GPU - twin| = {difference * 255:.3f}/255")
    assert difference <= TOLERANCE


def test_render_shows_the_technique(renders, baked):
    """Red is the softest channel: its Lambert image varies least; the TSD step along u blurs the u-stripes."""
    lambert = renders["lambert"][..., :3].astype(np.float32)
    detail = [np.abs(np.diff(lambert[..., c], axis=0)).mean() for c in range(3)]
    assert detail[0] < detail[1] <= detail[2] * 1.05, detail
    stripes = baked["irradiance"][..., 0].astype(np.float32)
    blurred = renders["tsd_u"][..., 0].astype(np.float32)
    assert np.abs(np.diff(blurred, axis=1)).mean() < np.abs(np.diff(stripes, axis=1)).mean()
