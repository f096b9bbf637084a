// baker_skin.glsl: pre-integrated skin shading with baker's LUTs, and wrap lighting with a color shift.
//
// Penner & Borshukov, "Pre-Integrated Skin Shading" (GPU Pro 2, 2011), RTR4 (Real-Time Rendering, 4th ed.) 14.6.3:
// the diffuse light of skin is read from a 2D LUT indexed by N.L and the curvature 1/r, pre-integrated over a
// diffusion profile (baker skin-lut / --bakes skin). Shadow edges get the same treatment from a penumbra LUT indexed
// by the filtered shadow value and 1 / penumbra width. Small-scale detail uses Penner's normal blending: one smooth
// normal mixed per channel with the detail (normal-mapped) normal, red smoothest; or, where BAKER_normal_blur baked
// them, one diffuse normal per channel (baker_skin_diffuse_normals).
// Wrap lighting with a color shift (RTR4 14.6.1; Green, GPU Gems ch. 16) is the cheap alternative.
//
// Data written by baker (schemas/BAKER_skin_lut/README.md):
//   texture   BAKER_skin_lut.lutTexture        RGB; u = N.L * 0.5 + 0.5, v = curvature over curvatureRange
//   texture   BAKER_skin_lut.penumbraTexture   RGB; u = shadow (0 shadowed), v = 1/width over penumbraWidthRange
//   attribute BAKER_skin_lut.curvatureAttribute (_CURVATURE), mean curvature in 1 / mesh units (convex > 0)
//   attribute BAKER_curvature.principalCurvaturesAttribute (_PRINCIPAL_CURVATURES) and principalDirectionAttribute
//             (_PRINCIPAL_DIRECTION), when baked: the curvature along the light (baker_skin_curvature_along_light)
//   params    curvatureRange, curvatureScale, penumbraWidthRange, normalBlend, wrap, scatterWidth, scatterColor
//             -> the fields of struct BakerSkin below, same names
// LUT texels are endpoint-aligned (column 0 is exactly N.L = -1): baker_skin_lut_coord maps t in [0, 1] to the
// texture coordinate of the matching texel centre. Sample the LUTs with LINEAR filtering, CLAMP_TO_EDGE, no mipmaps.
// If BAKER_skin_lut.encoding is "srgb", upload the LUTs as sRGB textures (or decode after sampling).
//
// How to include: no #version line, no precision statement, no uniforms/inputs/outputs; prepend your header:
//     #version 300 es  +  precision highp float; precision highp sampler2D;   |   #version 330 core
// Derivatives (fwidth) are only available in fragment shaders, so the per-pixel curvature estimate takes
// fwidth(N) and fwidth(P) as arguments: baker_skin_curvature_from_derivatives(fwidth(N), fwidth(P)).
//
// Compiles as GLSL ES 3.00 (WebGL2) and GLSL 3.30 core. Every function has a numpy twin in tests/gl/twins_skin.py,
// and tests/gl/test_skin.py renders it headlessly and checks the pixels against the twin.

#ifndef BAKER_SKIN_GLSL
#define BAKER_SKIN_GLSL

// The runtime half of BAKER_skin_lut, field for field.
struct BakerSkin {
    vec2 curvatureRange;      // curvature at the LUT's first and last row, 1/unit (unit: mm by default)
    float curvatureScale;     // 1 / mesh units -> 1/unit (a model in metres with a mm profile: 0.001)
    vec2 penumbraWidthRange;  // 1 / penumbra width at the penumbra LUT's first and last row, 1/unit
    vec3 normalBlend;         // per channel weight of the smooth normal in Penner's normal blending
    float wrap;               // wrap lighting: light wraps this far past the terminator
    float scatterWidth;       // wrap lighting: width of the color-shifted band
    vec3 scatterColor;        // wrap lighting: its color, linear RGB
};

// Texture coordinate of an endpoint-aligned LUT axis: t = 0 -> centre of the first texel, t = 1 -> the last.
float baker_skin_lut_coord(float t, float size) {
    return (clamp(t, 0.0, 1.0) * (size - 1.0) + 0.5) / size;
}

// Mesh curvature (1 / mesh units) -> the LUT's curvature. Concave regions (< 0) shade as flat.
float baker_skin_curvature(float meshCurvature, float curvatureScale) {
    return max(meshCurvature, 0.0) * curvatureScale;
}

// Per-pixel curvature estimate 1/r = |dN| / |dP| from screen-space derivatives (RTR4 14.6.3); pass fwidth(N) and
// fwidth(P) of the interpolated normal and position (mesh units). Returns 1 / mesh units.
float baker_skin_curvature_from_derivatives(vec3 fwidthN, vec3 fwidthP) {
    return length(fwidthN) / max(length(fwidthP), 1e-20);
}

// The normal curvature along the light (1 / mesh units): Penner's LUT wants the curvature across the terminator,
// which the mean curvature halves on cylinder-like parts (a finger, an ear's rim). Euler's formula
// k(L) = k1 cos^2(a) + k2 sin^2(a) = (k1 + k2) / 2 + (k1 - k2) / 2 cos(2a), a the angle in the tangent plane between
// L's projection and the k1 direction (Penner 2011 reads the curvature in the light's plane; do Carmo 3.2).
// principal = (k1, k2) of _PRINCIPAL_CURVATURES, direction = _PRINCIPAL_DIRECTION in the space of N and L (see
// baker_skin_direction_to). The direction is a line field whose sign may differ between vertices, so interpolated it
// can shorten: the cos(2a) term shrinks with its squared length, down to the mean curvature where it vanishes, and
// the same where L is along N (a undefined, the terminator far).
float baker_skin_curvature_along_light(vec2 principal, vec3 direction, vec3 N, vec3 L) {
    vec3 t = L - N * dot(N, L);                   // L in the tangent plane, length sin(L, N)
    vec3 d1 = direction - N * dot(N, direction);  // interpolated directions leave the tangent plane
    vec3 d2 = cross(N, d1);
    float c = dot(t, d1);
    float s = dot(t, d2);
    // c^2 - s^2 = |t|^2 |d1|^2 cos(2a): the ratio stays in [-1, 1]. float32 leaves |t|^2 ~ 1e-16 for L = N, so
    // below 1e-6 (L within 0.06 degrees of N, where the LUT is flat anyway) the term fades to the mean
    float cos2a = (c * c - s * s) / max(dot(t, t), 1e-6);
    return 0.5 * (principal.x + principal.y) + 0.5 * (principal.x - principal.y) * cos2a;
}

// Vertex stage: a principal direction (mesh space) into shading space by the linear part of the model(-view)
// matrix, its length kept (a shortened or zero direction stays so, see baker_skin_curvature_along_light).
vec3 baker_skin_direction_to(mat3 linear, vec3 direction) {
    vec3 d = linear * direction;
    return d * (length(direction) / max(length(d), 1e-20));
}

// LUT texture coordinates for N.L and a curvature in the LUT's unit.
vec2 baker_skin_lut_uv(float NdotL, float curvature, vec2 curvatureRange, vec2 lutSize) {
    float u = NdotL * 0.5 + 0.5;
    float v = (curvature - curvatureRange.x) / (curvatureRange.y - curvatureRange.x);
    return vec2(baker_skin_lut_coord(u, lutSize.x), baker_skin_lut_coord(v, lutSize.y));
}

// Pre-integrated diffuse (replaces saturate(N.L)) for one N.L, all three channels.
vec3 baker_skin_lut(sampler2D lut, float NdotL, float curvature, vec2 curvatureRange) {
    vec2 size = vec2(textureSize(lut, 0));
    return texture(lut, baker_skin_lut_uv(NdotL, curvature, curvatureRange, size)).rgb;
}

// Penner's normal blending: per channel, N.L with the detail normal mixed towards the smooth normal by normalBlend.
vec3 baker_skin_blended_ndotl(vec3 Nsmooth, vec3 Ndetail, vec3 L, vec3 normalBlend) {
    vec3 nr = normalize(mix(Ndetail, Nsmooth, normalBlend.r));
    vec3 ng = normalize(mix(Ndetail, Nsmooth, normalBlend.g));
    vec3 nb = normalize(mix(Ndetail, Nsmooth, normalBlend.b));
    return vec3(dot(nr, L), dot(ng, L), dot(nb, L));
}

// Pre-integrated diffuse with a separate N.L per channel (from baker_skin_blended_ndotl): each channel's own lookup.
vec3 baker_skin_lut_rgb(sampler2D lut, vec3 NdotL, float curvature, vec2 curvatureRange) {
    return vec3(baker_skin_lut(lut, NdotL.r, curvature, curvatureRange).r,
                baker_skin_lut(lut, NdotL.g, curvature, curvatureRange).g,
                baker_skin_lut(lut, NdotL.b, curvature, curvatureRange).b);
}

// Penner's penumbra LUT: the diffused shadow for a filtered shadow value (0 shadowed .. 1 lit) and the penumbra's
// width in the LUT's unit. Multiply the LUT diffuse by it instead of by the shadow value.
vec3 baker_skin_penumbra(sampler2D penumbraLut, float shadow, float penumbraWidth, vec2 penumbraWidthRange) {
    vec2 size = vec2(textureSize(penumbraLut, 0));
    float v = (1.0 / max(penumbraWidth, 1e-20) - penumbraWidthRange.x) / (penumbraWidthRange.y - penumbraWidthRange.x);
    return texture(penumbraLut, vec2(baker_skin_lut_coord(shadow, size.x), baker_skin_lut_coord(v, size.y))).rgb;
}

// Wrap lighting with a color shift (RTR4 14.6.1; Green 2004): diffuse wraps past the terminator, and a band of
// scatterColor is added where it fades out.
vec3 baker_skin_wrap(float NdotL, float wrap, float scatterWidth, vec3 scatterColor) {
    float diffuse = max((NdotL + wrap) / (1.0 + wrap), 0.0);
    // smoothstep(2w, w, d) of the original is undefined in GLSL for reversed edges: 1 - smoothstep(w, 2w, d) is it
    float scatter = smoothstep(0.0, scatterWidth, diffuse) * (1.0 - smoothstep(scatterWidth, 2.0 * scatterWidth, diffuse));
    return vec3(diffuse) + scatter * scatterColor;
}

// Convenience: Penner's skin diffuse for one light from the struct, the smooth and detail normals, L, and the mesh
// curvature (1 / mesh units, e.g. the interpolated _CURVATURE). Multiply by albedo, light color and shadow/penumbra.
vec3 baker_skin_diffuse(BakerSkin params, sampler2D lut, vec3 Nsmooth, vec3 Ndetail, vec3 L, float meshCurvature) {
    vec3 NdotL = baker_skin_blended_ndotl(Nsmooth, Ndetail, L, params.normalBlend);
    float curvature = baker_skin_curvature(meshCurvature, params.curvatureScale);
    return baker_skin_lut_rgb(lut, NdotL, curvature, params.curvatureRange);
}

// Pre-integrated diffuse with BAKER_normal_blur's per-channel diffuse normals (RTR4 14.6.2; Penner 2011 bakes them by
// blurring the normal map with the profile): NdotL = baker_normal_blur_ndotl(nRed, nGreen, nBlue, L) replaces
// Penner's normal blending; the specular term keeps the original normal map.
vec3 baker_skin_diffuse_normals(BakerSkin params, sampler2D lut, vec3 NdotL, float meshCurvature) {
    float curvature = baker_skin_curvature(meshCurvature, params.curvatureScale);
    return baker_skin_lut_rgb(lut, NdotL, curvature, params.curvatureRange);
}

#endif // BAKER_SKIN_GLSL
