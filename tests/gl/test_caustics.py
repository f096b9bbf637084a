"""``runtime-shaders/baker_caustics.glsl``: compiles as GLSL ES 3.00 and 3.30 core, and a headless render of baked
frames on a floor matches its numpy twins (``tests/gl/twins_caustics.py``)."""
from __future__ import annotations

import numpy as np
import pytest

from . import twins_caustics as twins
from .glsl import HEADERS, REPO, assert_compiles

MODULE = (REPO / "runtime-shaders" / "baker_caustics.glsl").read_text()

FULLSCREEN_VS = """
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
"""

# every function on world positions and times read from a float texture; the two frames are bound by the host
FLOOR_FS = """
uniform sampler2D u_inputs;   // world position xyz, time
uniform sampler2D u_first;
uniform sampler2D u_next;
uniform vec3 u_projection;
uniform float u_waterLevel;
uniform float u_depth;
uniform float u_tileSize;
uniform float u_period;
uniform float u_frames;
uniform float u_scale;
uniform float u_fadeDistance;
layout(location = 0) out vec4 o_uv;      // uv, fade, depth
layout(location = 1) out vec4 o_frame;   // first, blend, next
layout(location = 2) out vec4 o_color;
layout(location = 3) out vec4 o_headroom;  // the colour's added light compressed above a pixel of 0.6 other light
void main() {
    vec4 s = texelFetch(u_inputs, ivec2(gl_FragCoord.xy), 0);
    vec2 uv = baker_caustics_uv(s.xyz, u_projection, u_waterLevel, u_depth, u_tileSize);
    float d = baker_caustics_depth(s.xyz, u_waterLevel);
    float fade = baker_caustics_fade(d, u_depth, u_fadeDistance);
    vec3 frame = baker_caustics_frame(s.w, u_period, u_frames);
    o_uv = vec4(uv, fade, d);
    o_frame = vec4(frame, 1.0);
    vec3 e = baker_caustics_irradiance(u_first, u_next, uv, frame.y, u_scale, 0.0);
    o_color = vec4(baker_caustics_apply(vec3(0.3, 0.25, 0.2), vec3(0.2), e, 1.0, fade), 1.0);
    o_headroom = vec4(baker_caustics_headroom(vec3(0.3, 0.25, 0.2), o_color.rgb, vec3(0.6)), 1.0);
}
"""


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, stage):
    text = HEADERS[version] + MODULE + (FULLSCREEN_VS if stage == "vert" else FLOOR_FS)
    assert_compiles(glslang_validator, tmp_path, version, "caustics", stage, text)


def test_floor_render_matches_twins(gl_context):
    import moderngl

    from baker.techniques.caustics.extension import frame_pixels, to_gltf_axes
    from baker.techniques.caustics.kernel import caustic_frames
    from baker.techniques.caustics.options import CausticsOptions, at_scale

    ctx = gl_context
    options = at_scale(CausticsOptions(size=32, frames=4, waves=16, samples=2))[0]  # the lengths at scale 1
    baked = caustic_frames(options, seed=3)
    pixels, scale = frame_pixels(baked)
    frames = [(p.astype(np.float32) / 65535.0)[..., None] for p in pixels]
    projection = np.array(to_gltf_axes(baked.projection), np.float32)
    n = 48
    rng = np.random.default_rng(7)
    inputs = np.stack([rng.uniform(-3, 3, (n, n)), rng.uniform(-3.0, 0.5, (n, n)), rng.uniform(-3, 3, (n, n)),
                       rng.uniform(0, 9, (n, n))], -1).astype(np.float32)
    uniforms = {"u_projection": tuple(projection), "u_waterLevel": 0.0, "u_depth": options.depth,
                "u_tileSize": options.tile_size, "u_period": options.period, "u_frames": float(options.frames),
                "u_scale": scale, "u_fadeDistance": options.fade_distance}
    # every texel's frame pair is the same only if time is uniform; bind the pair of a fixed time for the colour
    time = 5.3
    first, blend, following = twins.baker_caustics_frame(time, options.period, options.frames)
    inputs[..., 3] = np.where(np.arange(n)[None, :] % 2 == 0, time, inputs[..., 3])

    def float_texture(a, linear=False):
        t = ctx.texture((a.shape[1], a.shape[0]), a.shape[2], np.ascontiguousarray(a).tobytes(), dtype="f4")
        t.filter = (moderngl.LINEAR, moderngl.LINEAR) if linear else (moderngl.NEAREST, moderngl.NEAREST)
        t.repeat_x = t.repeat_y = True
        return t

    prog = ctx.program(vertex_shader=HEADERS["330 core"] + MODULE + FULLSCREEN_VS,
                       fragment_shader=HEADERS["330 core"] + MODULE + FLOOR_FS)
    bound = (("u_inputs", float_texture(inputs)), ("u_first", float_texture(frames[int(first)], True)),
             ("u_next", float_texture(frames[int(following)], True)))
    for unit, (name, tex) in enumerate(bound):
        tex.use(unit)
        prog[name].value = unit
    for name, value in uniforms.items():
        prog[name].value = value
    targets = [ctx.texture((n, n), 4, dtype="f4") for _ in range(4)]
    fbo = ctx.framebuffer(targets)
    fbo.use()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, []).render(moderngl.TRIANGLES, vertices=3)
    ctx.finish()
    uv, frame, color, headroom = (np.frombuffer(t.read(), np.float32).reshape(n, n, 4) for t in targets)

    world = inputs[..., :3]
    np.testing.assert_allclose(uv[..., :2], twins.baker_caustics_uv(world, projection, 0.0, options.depth,
                                                                    options.tile_size), atol=2e-5)
    depth = twins.baker_caustics_depth(world, 0.0)
    np.testing.assert_allclose(uv[..., 3], depth, atol=1e-6)
    fade = twins.baker_caustics_fade(depth, options.depth, options.fade_distance)
    np.testing.assert_allclose(uv[..., 2], fade, atol=1e-5)
    np.testing.assert_allclose(frame[..., :3], twins.baker_caustics_frame(inputs[..., 3], options.period,
                                                                         options.frames), atol=1e-4)
    e = twins.baker_caustics_irradiance(frames[int(first)], frames[int(following)], uv[..., :2],
                                        np.full((n, n), blend, np.float32), scale, 0.0)
    expected = twins.baker_caustics_apply(np.array([0.3, 0.25, 0.2], np.float32), np.float32(0.2), e, 1.0, fade)
    same_time = np.arange(n)[None, :].repeat(n, 0) % 2 == 0
    # GL LINEAR filtering may keep only 8 bits of the sub-texel weight: allow 1/256 of a texel step
    step = max(np.abs(np.diff(f, axis=a)).max() for f in frames for a in (0, 1))
    assert np.abs(color[..., :3] - expected)[same_time].max() <= step * scale * 0.2 / 256 + 1e-5
    # the caustic does show: the lit colour varies across the floor where the fade is on
    lit = same_time & (fade > 0.5)
    assert lit.sum() > 50 and color[..., 0][lit].std() > 0.02
    # the headroom: the twin's, and the pixel (0.6 other light on the colour) never reaches 1 however bright the
    # caustic, while darkening is kept as computed and a caustic line stays brighter than the colour without it
    before = np.array([0.3, 0.25, 0.2], np.float32)
    np.testing.assert_allclose(headroom[..., :3], twins.baker_caustics_headroom(before, color[..., :3], 0.6),
                               atol=1e-5)
    assert (headroom[..., :3] + 0.6 < 1.0).all()
    darker, brighter = color[..., :3] <= before, color[..., :3] > before + 1e-3
    np.testing.assert_allclose(headroom[..., :3][darker], color[..., :3][darker], atol=1e-6)
    above = np.broadcast_to(before, brighter.shape)[brighter]
    assert brighter.sum() > 20 and (headroom[..., :3][brighter] > above).all()
    assert (color[..., :3] + 0.6 >= 1.0).any()  # the caustic would clip without the headroom
