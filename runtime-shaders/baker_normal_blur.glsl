// baker_normal_blur.glsl: per-channel diffuse normals and a texture-space diffusion reference pass.
//
// RTR4 (Real-Time Rendering, 4th ed.) 14.6.2: under subsurface scattering the diffuse term behaves as if shaded
// with blurred normals, more blurred in red (Ma et al. 2007); Penner (GPU Pro 2, 2011) bakes them by blurring the
// normal map with the diffusion profile. The specular term keeps the original normalTexture. 14.6.4: texture-space
// diffusion (Borshukov & Lewis 2003; d'Eon & Luebke, GPU Gems 3 ch. 14) blurs irradiance in UV space with kernels
// scaled per texel by the UV stretch, so a UV blur stands for a blur on the surface.
//
// Data written by baker (schemas/BAKER_normal_blur/README.md):
//   textures  BAKER_normal_blur.diffuseNormalTextures[0..2]  tangent-space normal maps (R, G, B), scale 1, the
//             normalTexture's UV set and tangent frame
//   texture   BAKER_normal_blur.smoothedNormalTexture + channelBlend   Penner's cheaper variant
//   texture   BAKER_normal_blur.stretchTexture (R = |dP/du|, G = |dP/dv|) x stretchScale, mesh units per UV unit
//   params    textureSpaceDiffusion.gaussians[i].variance / incrementalVariance / weights (mesh units^2)
// Sample the normal maps as the host samples normalTexture (same sampler); the stretch map LINEAR, CLAMP_TO_EDGE.
//
// How to include: no #version line, no precision statement, no uniforms/inputs/outputs; prepend your header:
//     #version 300 es  +  precision highp float; precision highp sampler2D;   |   #version 330 core
// Compiles as GLSL ES 3.00 (WebGL2) and GLSL 3.30 core. Every function has a numpy twin in
// tests/gl/twins_normal_blur.py, and tests/gl/test_normal_blur.py renders it headlessly against the twin.

#ifndef BAKER_NORMAL_BLUR_GLSL
#define BAKER_NORMAL_BLUR_GLSL

// A tangent-space normal from an RGB texel (n = 2c - 1), normalized; flipY = -1 where the host's frame has its
// bitangent the other way (three.js without vertex tangents), else 1.
vec3 baker_normal_blur_decode(vec3 texel, float flipY) {
    vec3 n = texel * 2.0 - 1.0;
    n.y *= flipY;
    return normalize(n);
}

// A tangent frame from screen-space derivatives where the host has no TANGENT (Schueler 2013, "Normal mapping without
// precomputed tangents"): columns dP/du, -dP/dv (glTF's +Y is up in the image, v grows down) and N, the two scaled
// alike. Pass dFdx/dFdy of the position and of the normal map's UV; N unit.
mat3 baker_normal_blur_derivative_frame(vec3 N, vec3 dPdx, vec3 dPdy, vec2 dUVdx, vec2 dUVdy) {
    vec3 dp2perp = cross(dPdy, N);
    vec3 dp1perp = cross(N, dPdx);
    vec3 T = dp2perp * dUVdx.x + dp1perp * dUVdy.x;
    vec3 B = dp2perp * dUVdx.y + dp1perp * dUVdy.y;
    float scale = inversesqrt(max(max(dot(T, T), dot(B, B)), 1e-30));
    return mat3(T * scale, -B * scale, N);
}

// Per-channel N.L from the three diffuse normals (view or world space, like L). Feed it to a LUT
// (baker_skin_lut_rgb) or saturate it for Lambert.
vec3 baker_normal_blur_ndotl(vec3 nRed, vec3 nGreen, vec3 nBlue, vec3 L) {
    return vec3(dot(nRed, L), dot(nGreen, L), dot(nBlue, L));
}

// Per-channel Lambert with the diffuse maps: tbn takes tangent space to the space of L (columns T, B, N).
vec3 baker_normal_blur_lambert(mat3 tbn, vec3 texelRed, vec3 texelGreen, vec3 texelBlue, vec3 L, float flipY) {
    vec3 ndotl = baker_normal_blur_ndotl(normalize(tbn * baker_normal_blur_decode(texelRed, flipY)),
                                         normalize(tbn * baker_normal_blur_decode(texelGreen, flipY)),
                                         normalize(tbn * baker_normal_blur_decode(texelBlue, flipY)), L);
    return clamp(ndotl, 0.0, 1.0);
}

// Penner's cheaper variant: per channel the smoothed normal mixed towards the vertex normal (0, 0, 1) by
// channelBlend, taken through tbn; returns per-channel N.L.
vec3 baker_normal_blur_blend_ndotl(mat3 tbn, vec3 texelSmoothed, vec3 channelBlend, vec3 L, float flipY) {
    vec3 s = baker_normal_blur_decode(texelSmoothed, flipY);
    vec3 up = vec3(0.0, 0.0, 1.0);
    vec3 nr = normalize(tbn * normalize(mix(s, up, channelBlend.r)));
    vec3 ng = normalize(tbn * normalize(mix(s, up, channelBlend.g)));
    vec3 nb = normalize(tbn * normalize(mix(s, up, channelBlend.b)));
    return vec3(dot(nr, L), dot(ng, L), dot(nb, L));
}

// The UV stretch at uv: (|dP/du|, |dP/dv|) in mesh units per UV unit.
vec2 baker_normal_blur_stretch(sampler2D stretchTexture, vec2 uv, float stretchScale) {
    return texture(stretchTexture, uv).rg * stretchScale;
}

// One pass of a separable texture-space Gaussian blur (d'Eon & Luebke's 7 taps over +-3 sigma, weights
// 0.006 0.061 0.242 0.382 0.242 0.061 0.006): sigma in mesh units, turned into UV units by the stretch at uv along
// direction (1, 0) = u or (0, 1) = v. Blur u then v, each Gaussian's incremental variance on the previous result,
// and sum the results with the Gaussians' RGB weights.
vec3 baker_normal_blur_tsd_step(sampler2D irradiance, sampler2D stretchTexture, vec2 uv, vec2 direction,
                                float sigma, float stretchScale) {
    const float weights[7] = float[7](0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006);
    vec2 stretch = max(baker_normal_blur_stretch(stretchTexture, uv, stretchScale), vec2(1e-12));
    vec2 step = direction * sigma / stretch;  // UV offset of one sigma on the surface
    vec3 sum = vec3(0.0);
    for (int i = 0; i < 7; i++) {
        sum += weights[i] * texture(irradiance, uv + float(i - 3) * step).rgb;
    }
    return sum;
}

// Texture-space diffusion, pass 1: rasterize the mesh into its UV layout (Borshukov & Lewis 2003): the clip-space
// position of a vertex at uv, so texel (u, v) of the render target is the texel (u, v) of the textures (row 0 at
// v = 0, as GL reads a render target back). Shade irradiance there with the real position and normal as varyings.
vec4 baker_normal_blur_uv_position(vec2 uv) {
    return vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Texture-space diffusion, last pass: add one Gaussian's blurred irradiance with its RGB weights
// (textureSpaceDiffusion.gaussians[i].weights) to the sum of the ones before (d'Eon & Luebke's recombination).
vec3 baker_normal_blur_tsd_accumulate(vec3 total, vec3 blurred, vec3 weights) {
    return total + weights * blurred;
}

#endif // BAKER_NORMAL_BLUR_GLSL
