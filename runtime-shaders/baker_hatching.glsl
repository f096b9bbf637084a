// baker_hatching.glsl: real-time hatching with a tonal art map (TAM).
//
// Implements the shading of Praun, Hoppe, Webb & Finkelstein, "Real-Time Hatching", SIGGRAPH 2001 (RTR4 section
// 15.3, figures 15.21-15.22): a tone value (e.g. from N.L) picks a blend of the TAM's stroke textures. The six tones
// are packed into the RGB channels of two textures, tones 0-2 and 3-5 (lightest to darkest); each of them has its
// own, hand-drawn mip levels (the TAM's levels, uploaded as the texture's custom mip chain), so strokes keep their
// width on screen. Because the TAM is nested (every stroke of a light tone is in all darker tones and all finer
// levels), blending neighbouring tones and levels never makes strokes pop.
//
// Praun's weights are hat functions over the tone targets: with darkness targets t0 < ... < t5 (the extension's
// `tones`), white paper at darkness 0 and black ink at 1, a darkness d between two neighbouring knots is their
// linear blend. The blend of the images then has, on average, exactly the darkness d asked for:
//
//     brightness = wPaper * 1 + dot(wA, tones012.rgb) + dot(wB, tones345.rgb) + wBlack * 0
//
// Webb, Praun, Finkelstein & Hoppe, "Fine Tone Control in Hardware Hatching", NPAR 2002: the *volume TAM* stores
// many tones as the layers of an array texture whose mips are spatial only; baker_hatching_volume blends the two
// layers around d (tone targets evenly spaced: darkest * (i + 1) / n).
//
// Data written by baker (schemas/BAKER_tonal_art_map/README.md):
//   levels[i].textures[0|1]  packed layout: level i of the two textures (RGB8; upload as UNORM, not sRGB)
//   levels[i].texture        volume layout: level i of the array texture (the tone slices stacked vertically)
//   tones                    darkness targets -> vec3 tonesA = tones[0..2], tonesB = tones[3..5]
//   scale, levels[0].size    tile coordinates = uv * scale / levels[0].size (baker_tam_coord)
//   levels.length            the LOD is clamped to [0, levels.length - 1]
// Upload level i of the TAM as mip level i (glTexImage2D(..., i, ...)), set TEXTURE_MAX_LEVEL = levels.length - 1,
// minFilter LINEAR_MIPMAP_LINEAR, wrap REPEAT.
//
// How to include: no #version line, no precision statement, no uniforms, inputs or outputs; prepend your header
// (GLSL ES 3.00 needs `precision highp sampler2DArray;` before the volume function, WebGL2 having no default) and
// paste the file after it. Compiles as GLSL ES 3.00 and GLSL 3.30 core. Every function has a numpy twin in
// tests/gl/twins_hatching.py; tests/gl/test_hatching.py renders a lit sphere and compares.

#ifndef BAKER_HATCHING_GLSL
#define BAKER_HATCHING_GLSL

// TAM tile coordinates from a mesh UV: `scale` finest-level texels per UV unit, `finestSize` = levels[0].size.
vec2 baker_tam_coord(vec2 uv, float scale, float finestSize) {
    return uv * (scale / finestSize);
}

// The mip level of the TAM chain, from the screen-space derivatives of the tile coordinates (pass dFdx(tile) and
// dFdy(tile) from a fragment shader): log2 of the larger footprint in finest-level texels, as GL computes it
// (isotropic), clamped to the levels that exist.
float baker_tam_lod(vec2 dTileDx, vec2 dTileDy, float finestSize, float levelCount) {
    vec2 dx = dTileDx * finestSize;
    vec2 dy = dTileDy * finestSize;
    float rho2 = max(dot(dx, dx), dot(dy, dy));
    return clamp(0.5 * log2(max(rho2, 1e-20)), 0.0, levelCount - 1.0);
}

// Praun's blend weights of the six tones for a darkness d in [0, 1]: wA for tones 0-2, wB for tones 3-5, and the
// white-paper weight. The black-ink weight (1 - the sum of the others) adds nothing to the brightness.
void baker_hatching_weights(float darkness, vec3 tonesA, vec3 tonesB, out vec3 wA, out vec3 wB, out float wPaper) {
    float d = clamp(darkness, 0.0, 1.0);
    vec3 prevA = vec3(0.0, tonesA.x, tonesA.y);
    vec3 nextA = vec3(tonesA.y, tonesA.z, tonesB.x);
    vec3 prevB = vec3(tonesA.z, tonesB.x, tonesB.y);
    vec3 nextB = vec3(tonesB.y, tonesB.z, 1.0);
    wA = max(min((vec3(d) - prevA) / (tonesA - prevA), (nextA - vec3(d)) / (nextA - tonesA)), vec3(0.0));
    wB = max(min((vec3(d) - prevB) / (tonesB - prevB), (nextB - vec3(d)) / (nextB - tonesB)), vec3(0.0));
    wPaper = max(1.0 - d / tonesA.x, 0.0);
}

// Brightness (1 = paper) of the hatching for darkness d at tile coordinates `tile` and mip level `lod`.
float baker_hatching(sampler2D tones012, sampler2D tones345, vec2 tile, float lod, float darkness, vec3 tonesA,
                     vec3 tonesB) {
    vec3 wA;
    vec3 wB;
    float wPaper;
    baker_hatching_weights(darkness, tonesA, tonesB, wA, wB, wPaper);
    vec3 a = textureLod(tones012, tile, lod).rgb;
    vec3 b = textureLod(tones345, tile, lod).rgb;
    return wPaper + dot(wA, a) + dot(wB, b);
}

// Webb's volume TAM: brightness from an array texture with one layer per tone (layer i at darkness
// darkest * (i + 1) / toneCount, lightest first), spatial mips only. Blends paper / the two layers around d / black.
// The sampler parameter carries its own precision: GLSL ES 3.00 has no default precision for sampler2DArray.
float baker_hatching_volume(highp sampler2DArray tam, vec2 tile, float lod, float darkness, float toneCount,
                            float darkest) {
    float d = clamp(darkness, 0.0, 1.0);
    float x = d / darkest * toneCount - 1.0;  // -1 = paper, toneCount - 1 = the darkest layer
    if (x >= toneCount - 1.0) {
        float last = textureLod(tam, vec3(tile, toneCount - 1.0), lod).r;
        return last * (1.0 - (d - darkest) / (1.0 - darkest));  // towards black ink at d = 1
    }
    float i0 = floor(x);
    float f = x - i0;
    float lower = i0 < 0.0 ? 1.0 : textureLod(tam, vec3(tile, i0), lod).r;
    float upper = textureLod(tam, vec3(tile, i0 + 1.0), lod).r;
    return mix(lower, upper, f);
}

// A tone value from diffuse lighting: darkness = 1 - (0.5 + 0.5 N.L) (a "half-Lambert" that keeps strokes
// on the shadowed side instead of solid black), times the light's intensity.
float baker_hatching_darkness(vec3 N, vec3 L, float intensity) {
    return clamp(1.0 - (0.5 + 0.5 * dot(N, L)) * intensity, 0.0, 1.0);
}

#endif
