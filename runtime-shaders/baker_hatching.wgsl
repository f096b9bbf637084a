// baker_hatching.wgsl: real-time hatching with a tonal art map (TAM); the WGSL twin of baker_hatching.glsl (same
// functions, same arguments, same meaning; see there and schemas/BAKER_tonal_art_map/README.md).
//
// Praun, Hoppe, Webb & Finkelstein, "Real-Time Hatching", SIGGRAPH 2001 (RTR4 15.3): a darkness picks a blend of
// the TAM's six tones (two RGB textures, tones 0-2 and 3-5, each with its own hand-drawn mip levels) by hat
// functions over the tone targets, white paper at 0 and black ink at 1:
//     brightness = wPaper + dot(wA, tones012.rgb) + dot(wB, tones345.rgb)
// Webb, Praun, Finkelstein & Hoppe, "Fine Tone Control in Hardware Hatching", NPAR 2002: the volume TAM, one array
// layer per tone, mips spatial only.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D / sampler2DArray argument is a texture_2d<f32> /
// texture_2d_array<f32> and its sampler (LINEAR, mipmapFilter LINEAR, REPEAT; upload level i of the TAM as mip
// level i); textureLod is textureSampleLevel (any stage), an array layer an i32 (the GLSL layers are whole
// numbers); GLSL's `out` parameters are pointers. No entry point, no bindings: paste it once (names are unique
// across the runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against
// tests/gl/twins_hatching.py.

// TAM tile coordinates from a mesh UV: `scale` finest-level texels per UV unit, `finestSize` = levels[0].size.
fn baker_tam_coord(uv: vec2f, scale: f32, finestSize: f32) -> vec2f {
    return uv * (scale / finestSize);
}

// The mip level of the TAM chain from the screen-space derivatives of the tile coordinates (pass dpdx(tile) and
// dpdy(tile)): log2 of the larger footprint in finest-level texels (isotropic), clamped to the levels that exist.
fn baker_tam_lod(dTileDx: vec2f, dTileDy: vec2f, finestSize: f32, levelCount: f32) -> f32 {
    let dx = dTileDx * finestSize;
    let dy = dTileDy * finestSize;
    let rho2 = max(dot(dx, dx), dot(dy, dy));
    return clamp(0.5 * log2(max(rho2, 1e-20)), 0.0, levelCount - 1.0);
}

// Praun's blend weights of the six tones for a darkness d in [0, 1]: wA for tones 0-2, wB for tones 3-5, and the
// white-paper weight (black ink takes the rest and adds nothing).
fn baker_hatching_weights(darkness: f32, tonesA: vec3f, tonesB: vec3f, wA: ptr<function, vec3f>,
                          wB: ptr<function, vec3f>, wPaper: ptr<function, f32>) {
    let d = clamp(darkness, 0.0, 1.0);
    let prevA = vec3f(0.0, tonesA.x, tonesA.y);
    let nextA = vec3f(tonesA.y, tonesA.z, tonesB.x);
    let prevB = vec3f(tonesA.z, tonesB.x, tonesB.y);
    let nextB = vec3f(tonesB.y, tonesB.z, 1.0);
    *wA = max(min((vec3f(d) - prevA) / (tonesA - prevA), (nextA - vec3f(d)) / (nextA - tonesA)), vec3f(0.0));
    *wB = max(min((vec3f(d) - prevB) / (tonesB - prevB), (nextB - vec3f(d)) / (nextB - tonesB)), vec3f(0.0));
    *wPaper = max(1.0 - d / tonesA.x, 0.0);
}

// Brightness (1 = paper) of the hatching for darkness d at tile coordinates `tile` and mip level `lod`.
fn baker_hatching(tones012: texture_2d<f32>, tones012Sampler: sampler, tones345: texture_2d<f32>,
                  tones345Sampler: sampler, tile: vec2f, lod: f32, darkness: f32, tonesA: vec3f, tonesB: vec3f) -> f32 {
    var wA: vec3f;
    var wB: vec3f;
    var wPaper: f32;
    baker_hatching_weights(darkness, tonesA, tonesB, &wA, &wB, &wPaper);
    let a = textureSampleLevel(tones012, tones012Sampler, tile, lod).rgb;
    let b = textureSampleLevel(tones345, tones345Sampler, tile, lod).rgb;
    return wPaper + dot(wA, a) + dot(wB, b);
}

// Webb's volume TAM: brightness from an array texture with one layer per tone (layer i at darkness
// darkest * (i + 1) / toneCount, lightest first), spatial mips only: paper / the two layers around d / black.
fn baker_hatching_volume(tam: texture_2d_array<f32>, tamSampler: sampler, tile: vec2f, lod: f32, darkness: f32,
                         toneCount: f32, darkest: f32) -> f32 {
    let d = clamp(darkness, 0.0, 1.0);
    let x = d / darkest * toneCount - 1.0;  // -1 = paper, toneCount - 1 = the darkest layer
    if (x >= toneCount - 1.0) {
        let last = textureSampleLevel(tam, tamSampler, tile, i32(floor(toneCount - 0.5)), lod).r;
        return last * (1.0 - (d - darkest) / (1.0 - darkest));  // towards black ink at d = 1
    }
    let i0 = floor(x);
    let f = x - i0;
    var lower = 1.0;
    if (i0 >= 0.0) {
        lower = textureSampleLevel(tam, tamSampler, tile, i32(i0), lod).r;
    }
    let upper = textureSampleLevel(tam, tamSampler, tile, i32(i0) + 1, lod).r;
    return mix(lower, upper, f);
}

// A tone value from diffuse lighting: darkness = 1 - (0.5 + 0.5 N.L) (a half-Lambert that keeps strokes on the
// shadowed side), times the light's intensity.
fn baker_hatching_darkness(N: vec3f, L: vec3f, intensity: f32) -> f32 {
    return clamp(1.0 - (0.5 + 0.5 * dot(N, L)) * intensity, 0.0, 1.0);
}
