// baker_normal_blur.wgsl: per-channel diffuse normals and a texture-space diffusion reference pass; the WGSL twin of
// baker_normal_blur.glsl (same functions, same arguments, same meaning; see there and
// schemas/BAKER_normal_blur/README.md).
//
// RTR4 14.6.2: under subsurface scattering the diffuse term behaves as if shaded with blurred normals, more blurred
// in red (Ma et al. 2007); Penner (GPU Pro 2, 2011) bakes them by blurring the normal map with the diffusion
// profile. 14.6.4: texture-space diffusion (Borshukov & Lewis 2003; d'Eon & Luebke, GPU Gems 3 ch. 14) blurs
// irradiance in UV space with kernels scaled per texel by the UV stretch.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D argument is a texture_2d<f32> and its sampler (the
// stretch map and the irradiance target: LINEAR, CLAMP_TO_EDGE); GLSL texture() is textureSample (fragment stage);
// derivatives (dpdx, dpdy) stay the caller's. No entry point, no bindings: paste it once (names are unique across
// the runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against
// tests/gl/twins_normal_blur.py.

// A tangent-space normal from an RGB texel (n = 2c - 1), normalized; flipY = -1 where the host's frame has its
// bitangent the other way, else 1.
fn baker_normal_blur_decode(texel: vec3f, flipY: f32) -> vec3f {
    var n = texel * 2.0 - 1.0;
    n.y *= flipY;
    return normalize(n);
}

// A tangent frame from screen-space derivatives where the host has no TANGENT (Schueler 2013, "Normal mapping without
// precomputed tangents"): columns dP/du, -dP/dv (glTF's +Y is up in the image, v grows down) and N, the two scaled
// alike. Pass dpdx/dpdy of the position and of the normal map's UV; N unit.
fn baker_normal_blur_derivative_frame(N: vec3f, dPdx: vec3f, dPdy: vec3f, dUVdx: vec2f, dUVdy: vec2f) -> mat3x3f {
    let dp2perp = cross(dPdy, N);
    let dp1perp = cross(N, dPdx);
    let T = dp2perp * dUVdx.x + dp1perp * dUVdy.x;
    let B = dp2perp * dUVdx.y + dp1perp * dUVdy.y;
    let scale = inverseSqrt(max(max(dot(T, T), dot(B, B)), 1e-30));
    return mat3x3f(T * scale, -B * scale, N);
}

// Per-channel N.L from the three diffuse normals (view or world space, like L).
fn baker_normal_blur_ndotl(nRed: vec3f, nGreen: vec3f, nBlue: vec3f, L: vec3f) -> vec3f {
    return vec3f(dot(nRed, L), dot(nGreen, L), dot(nBlue, L));
}

// Per-channel Lambert with the diffuse maps: tbn takes tangent space to the space of L (columns T, B, N).
fn baker_normal_blur_lambert(tbn: mat3x3f, texelRed: vec3f, texelGreen: vec3f, texelBlue: vec3f, L: vec3f,
                             flipY: f32) -> vec3f {
    let ndotl = baker_normal_blur_ndotl(normalize(tbn * baker_normal_blur_decode(texelRed, flipY)),
                                        normalize(tbn * baker_normal_blur_decode(texelGreen, flipY)),
                                        normalize(tbn * baker_normal_blur_decode(texelBlue, flipY)), L);
    return clamp(ndotl, vec3f(0.0), vec3f(1.0));
}

// Penner's cheaper variant: per channel the smoothed normal mixed towards the vertex normal (0, 0, 1) by
// channelBlend, taken through tbn; returns per-channel N.L.
fn baker_normal_blur_blend_ndotl(tbn: mat3x3f, texelSmoothed: vec3f, channelBlend: vec3f, L: vec3f,
                                 flipY: f32) -> vec3f {
    let s = baker_normal_blur_decode(texelSmoothed, flipY);
    let up = vec3f(0.0, 0.0, 1.0);
    let nr = normalize(tbn * normalize(mix(s, up, channelBlend.r)));
    let ng = normalize(tbn * normalize(mix(s, up, channelBlend.g)));
    let nb = normalize(tbn * normalize(mix(s, up, channelBlend.b)));
    return vec3f(dot(nr, L), dot(ng, L), dot(nb, L));
}

// The UV stretch at uv: (|dP/du|, |dP/dv|) in mesh units per UV unit.
fn baker_normal_blur_stretch(stretchTexture: texture_2d<f32>, stretchSampler: sampler, uv: vec2f,
                             stretchScale: f32) -> vec2f {
    return textureSample(stretchTexture, stretchSampler, uv).rg * stretchScale;
}

// One pass of a separable texture-space Gaussian blur (d'Eon & Luebke's 7 taps over +-3 sigma): sigma in mesh units,
// turned into UV units by the stretch at uv along direction (1, 0) = u or (0, 1) = v.
fn baker_normal_blur_tsd_step(irradiance: texture_2d<f32>, irradianceSampler: sampler, stretchTexture: texture_2d<f32>,
                              stretchSampler: sampler, uv: vec2f, direction: vec2f, sigma: f32,
                              stretchScale: f32) -> vec3f {
    const weights = array<f32, 7>(0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006);
    let stretch = max(baker_normal_blur_stretch(stretchTexture, stretchSampler, uv, stretchScale), vec2f(1e-12));
    let step = direction * sigma / stretch;  // UV offset of one sigma on the surface
    var sum = vec3f(0.0);
    for (var i = 0; i < 7; i++) {
        sum += weights[i] * textureSample(irradiance, irradianceSampler, uv + f32(i - 3) * step).rgb;
    }
    return sum;
}

// Texture-space diffusion, pass 1: rasterize the mesh into its UV layout (Borshukov & Lewis 2003): the clip-space
// position of a vertex at uv, so texel (u, v) of the render target is the texel (u, v) of the textures. The one
// formula that differs from the GLSL: WebGPU's framebuffer row 0 is at NDC y = +1 and a texture's row 0 at v = 0,
// so y is flipped (GL's row 0 is at NDC y = -1 and t = 0, hence uv * 2 - 1 there).
fn baker_normal_blur_uv_position(uv: vec2f) -> vec4f {
    return vec4f(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
}

// Texture-space diffusion, last pass: add one Gaussian's blurred irradiance with its RGB weights to the sum.
fn baker_normal_blur_tsd_accumulate(total: vec3f, blurred: vec3f, weights: vec3f) -> vec3f {
    return total + weights * blurred;
}
