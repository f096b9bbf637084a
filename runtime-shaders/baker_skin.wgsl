// baker_skin.wgsl: pre-integrated skin shading with baker's LUTs, and wrap lighting with a color shift; the WGSL twin
// of baker_skin.glsl (same functions, same arguments, same meaning; see there and schemas/BAKER_skin_lut/README.md).
//
// Penner & Borshukov, "Pre-Integrated Skin Shading" (GPU Pro 2, 2011), RTR4 14.6.3: the diffuse light of skin read
// from a 2D LUT by N.L and the curvature 1/r, a penumbra LUT for shadow edges, Penner's per-channel normal blending
// (or BAKER_normal_blur's per-channel diffuse normals). Wrap lighting with a color shift (RTR4 14.6.1; Green, GPU
// Gems ch. 16) is the cheap alternative.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D argument is a texture_2d<f32> and its sampler;
// GLSL texture() is textureSample (fragment stage, implicit derivatives), textureSize is textureDimensions. Sample
// the LUTs with a LINEAR, CLAMP_TO_EDGE sampler; they have no mip levels. Derivatives (fwidth) stay the caller's:
// baker_skin_curvature_from_derivatives(fwidth(N), fwidth(P)). No entry point, no bindings: paste it once (names
// are unique across the runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it
// against tests/gl/twins_skin.py.

// The runtime half of BAKER_skin_lut, field for field.
struct BakerSkin {
    curvatureRange: vec2f,      // curvature at the LUT's first and last row, 1/unit (unit: mm by default)
    curvatureScale: f32,        // 1 / mesh units -> 1/unit (a model in metres with a mm profile: 0.001)
    penumbraWidthRange: vec2f,  // 1 / penumbra width at the penumbra LUT's first and last row, 1/unit
    normalBlend: vec3f,         // per channel weight of the smooth normal in Penner's normal blending
    wrap: f32,                  // wrap lighting: light wraps this far past the terminator
    scatterWidth: f32,          // wrap lighting: width of the color-shifted band
    scatterColor: vec3f,        // wrap lighting: its color, linear RGB
}

// Texture coordinate of an endpoint-aligned LUT axis: t = 0 -> centre of the first texel, t = 1 -> the last.
fn baker_skin_lut_coord(t: f32, size: f32) -> f32 {
    return (clamp(t, 0.0, 1.0) * (size - 1.0) + 0.5) / size;
}

// Mesh curvature (1 / mesh units) -> the LUT's curvature. Concave regions (< 0) shade as flat.
fn baker_skin_curvature(meshCurvature: f32, curvatureScale: f32) -> f32 {
    return max(meshCurvature, 0.0) * curvatureScale;
}

// Per-pixel curvature estimate 1/r = |dN| / |dP| from screen-space derivatives (RTR4 14.6.3); pass fwidth(N) and
// fwidth(P) of the interpolated normal and position (mesh units). Returns 1 / mesh units.
fn baker_skin_curvature_from_derivatives(fwidthN: vec3f, fwidthP: vec3f) -> f32 {
    return length(fwidthN) / max(length(fwidthP), 1e-20);
}

// The normal curvature along the light (1 / mesh units), Euler's formula k(L) = (k1 + k2) / 2 + (k1 - k2) / 2 cos(2a)
// (Penner 2011 reads the curvature in the light's plane; do Carmo 3.2). principal = (k1, k2) of
// _PRINCIPAL_CURVATURES, direction = _PRINCIPAL_DIRECTION in the space of N and L. A shortened (interpolated)
// direction shrinks the cos(2a) term towards the mean curvature, and so does L along N.
fn baker_skin_curvature_along_light(principal: vec2f, direction: vec3f, N: vec3f, L: vec3f) -> f32 {
    let t = L - N * dot(N, L);                   // L in the tangent plane, length sin(L, N)
    let d1 = direction - N * dot(N, direction);  // interpolated directions leave the tangent plane
    let d2 = cross(N, d1);
    let c = dot(t, d1);
    let s = dot(t, d2);
    // c^2 - s^2 = |t|^2 |d1|^2 cos(2a); below |t|^2 = 1e-6 (L within 0.06 degrees of N) the term fades to the mean
    let cos2a = (c * c - s * s) / max(dot(t, t), 1e-6);
    return 0.5 * (principal.x + principal.y) + 0.5 * (principal.x - principal.y) * cos2a;
}

// Vertex stage: a principal direction (mesh space) into shading space by the linear part of the model(-view)
// matrix, its length kept.
fn baker_skin_direction_to(linear: mat3x3f, direction: vec3f) -> vec3f {
    let d = linear * direction;
    return d * (length(direction) / max(length(d), 1e-20));
}

// LUT texture coordinates for N.L and a curvature in the LUT's unit.
fn baker_skin_lut_uv(NdotL: f32, curvature: f32, curvatureRange: vec2f, lutSize: vec2f) -> vec2f {
    let u = NdotL * 0.5 + 0.5;
    let v = (curvature - curvatureRange.x) / (curvatureRange.y - curvatureRange.x);
    return vec2f(baker_skin_lut_coord(u, lutSize.x), baker_skin_lut_coord(v, lutSize.y));
}

// Pre-integrated diffuse (replaces saturate(N.L)) for one N.L, all three channels.
fn baker_skin_lut(lut: texture_2d<f32>, lutSampler: sampler, NdotL: f32, curvature: f32,
                  curvatureRange: vec2f) -> vec3f {
    let size = vec2f(textureDimensions(lut, 0));
    return textureSample(lut, lutSampler, baker_skin_lut_uv(NdotL, curvature, curvatureRange, size)).rgb;
}

// Penner's normal blending: per channel, N.L with the detail normal mixed towards the smooth normal by normalBlend.
fn baker_skin_blended_ndotl(Nsmooth: vec3f, Ndetail: vec3f, L: vec3f, normalBlend: vec3f) -> vec3f {
    let nr = normalize(mix(Ndetail, Nsmooth, normalBlend.r));
    let ng = normalize(mix(Ndetail, Nsmooth, normalBlend.g));
    let nb = normalize(mix(Ndetail, Nsmooth, normalBlend.b));
    return vec3f(dot(nr, L), dot(ng, L), dot(nb, L));
}

// Pre-integrated diffuse with a separate N.L per channel (from baker_skin_blended_ndotl): each channel's own lookup.
fn baker_skin_lut_rgb(lut: texture_2d<f32>, lutSampler: sampler, NdotL: vec3f, curvature: f32,
                      curvatureRange: vec2f) -> vec3f {
    return vec3f(baker_skin_lut(lut, lutSampler, NdotL.r, curvature, curvatureRange).r,
                 baker_skin_lut(lut, lutSampler, NdotL.g, curvature, curvatureRange).g,
                 baker_skin_lut(lut, lutSampler, NdotL.b, curvature, curvatureRange).b);
}

// Penner's penumbra LUT: the diffused shadow for a filtered shadow value (0 shadowed .. 1 lit) and the penumbra's
// width in the LUT's unit. Multiply the LUT diffuse by it instead of by the shadow value.
fn baker_skin_penumbra(penumbraLut: texture_2d<f32>, penumbraSampler: sampler, shadow: f32, penumbraWidth: f32,
                       penumbraWidthRange: vec2f) -> vec3f {
    let size = vec2f(textureDimensions(penumbraLut, 0));
    let v = (1.0 / max(penumbraWidth, 1e-20) - penumbraWidthRange.x) / (penumbraWidthRange.y - penumbraWidthRange.x);
    return textureSample(penumbraLut, penumbraSampler,
                         vec2f(baker_skin_lut_coord(shadow, size.x), baker_skin_lut_coord(v, size.y))).rgb;
}

// Wrap lighting with a color shift (RTR4 14.6.1; Green 2004): diffuse wraps past the terminator, and a band of
// scatterColor is added where it fades out.
fn baker_skin_wrap(NdotL: f32, wrap: f32, scatterWidth: f32, scatterColor: vec3f) -> vec3f {
    let diffuse = max((NdotL + wrap) / (1.0 + wrap), 0.0);
    // the original's smoothstep(2w, w, d) has reversed edges: 1 - smoothstep(w, 2w, d) is it
    let scatter = smoothstep(0.0, scatterWidth, diffuse)
                * (1.0 - smoothstep(scatterWidth, 2.0 * scatterWidth, diffuse));
    return vec3f(diffuse) + scatter * scatterColor;
}

// Penner's skin diffuse for one light from the struct, the smooth and detail normals, L, and the mesh curvature
// (1 / mesh units, e.g. the interpolated _CURVATURE). Multiply by albedo, light color and shadow/penumbra.
fn baker_skin_diffuse(params: BakerSkin, lut: texture_2d<f32>, lutSampler: sampler, Nsmooth: vec3f, Ndetail: vec3f,
                      L: vec3f, meshCurvature: f32) -> vec3f {
    let NdotL = baker_skin_blended_ndotl(Nsmooth, Ndetail, L, params.normalBlend);
    let curvature = baker_skin_curvature(meshCurvature, params.curvatureScale);
    return baker_skin_lut_rgb(lut, lutSampler, NdotL, curvature, params.curvatureRange);
}

// Pre-integrated diffuse with BAKER_normal_blur's per-channel diffuse normals (RTR4 14.6.2): NdotL =
// baker_normal_blur_ndotl(nRed, nGreen, nBlue, L) replaces Penner's normal blending.
fn baker_skin_diffuse_normals(params: BakerSkin, lut: texture_2d<f32>, lutSampler: sampler, NdotL: vec3f,
                              meshCurvature: f32) -> vec3f {
    let curvature = baker_skin_curvature(meshCurvature, params.curvatureScale);
    return baker_skin_lut_rgb(lut, lutSampler, NdotL, curvature, params.curvatureRange);
}
