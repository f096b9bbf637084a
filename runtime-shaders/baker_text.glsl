// baker_text.glsl: text from distance-field glyph atlases (BAKER_glyph_atlas / BAKER_text), any scale, antialiased.
//
// RTR4 (Real-Time Rendering, 4th ed.) section 15.5: a texel of the atlas holds the signed distance to the glyph's
// outline; bilinear filtering interpolates it and a threshold at 0.5 recovers the edge at any magnification
// (Green, "Improved Alpha-Tested Magnification for Vector Textures and Special Effects", SIGGRAPH 2007). One channel
// rounds corners; three channels whose MEDIAN is the distance keep them sharp (Chlumsky, "Shape Decomposition for
// Multi-channel Distance Fields", 2015). MTSDF adds the true distance in alpha for soft effects.
//
// Encoding (all baker field types, same as msdfgen / msdf-atlas-gen): a texel value v in [0, 1] is the signed
// distance (v - 0.5) * distanceRange in ATLAS pixels, positive inside.
//
//   field type (BAKER_glyph_atlas.fonts[i].type)   edge distance            true distance (soft effects)
//   0 sdf, 1 psdf                                   r                        r
//   2 msdf                                          median(r, g, b)          median(r, g, b)
//   3 mtsdf                                         median(r, g, b)          a
//
// Antialiasing: the distance is converted to SCREEN pixels with the screen-pixel range (Chlumsky's screenPxRange):
//   screenPxRange = max(0.5 * dot(distanceRange / atlasSize, 1 / fwidth(uv)), 1)
// which the caller computes in the fragment shader with fwidth (this module takes fwidth(uv) as an input, so it
// contains no derivative and compiles in any stage).
//
// Green's effects (all distances in atlas pixels, convert em with * BAKER_glyph_atlas size):
//   soft edge  - the 1-screen-pixel antialiasing ramp widened by `softness` screen pixels
//   outline    - the fill grown by `outlineWidth` (BAKER_text.outline.width * size), drawn under the fill
//   glow       - outside the glyph, fades from glowColor at the edge to nothing at `glowWidth` (true distance)
//   shadow     - a second sample at uv - shadowOffset (the caller's sample), blurred by `shadowSoftness`
// Layers composite back to front (shadow, glow, outline, fill) with premultiplied "over"; the result is
// PREMULTIPLIED RGBA: blend with (ONE, ONE_MINUS_SRC_ALPHA).
//
// How to include: no #version, no precision, no uniforms/inputs/outputs; prepend your header:
//     #version 300 es / precision highp float;     or     #version 330 core
// Compiles as GLSL ES 3.00 and GLSL 3.30 core. Numpy twins: tests/gl/twins_text.py; tests/gl/test_text.py renders a
// baked label headlessly and compares it with the twins.

#ifndef BAKER_TEXT_GLSL
#define BAKER_TEXT_GLSL

const int BAKER_TEXT_SDF = 0;
const int BAKER_TEXT_PSDF = 1;
const int BAKER_TEXT_MSDF = 2;
const int BAKER_TEXT_MTSDF = 3;

// Styling of BAKER_text in atlas-pixel units (em * size) and screen pixels; colors are straight (not premultiplied).
struct BakerTextStyle {
    vec4 color;            // fill (BAKER_text.color)
    float softness;        // extra edge blur, screen pixels (0 = crisp antialiasing)
    vec4 outlineColor;     // BAKER_text.outline.color
    float outlineWidth;    // atlas pixels (BAKER_text.outline.width * size); <= 0: no outline
    vec4 glowColor;
    float glowWidth;       // atlas pixels; <= 0: no glow
    vec4 shadowColor;      // alpha 0: no shadow
    float shadowSoftness;  // atlas pixels
};

float baker_text_median(vec3 v) {
    return max(min(v.r, v.g), min(max(v.r, v.g), v.b));
}

// Screen pixels spanned by the whole distance range at this fragment; uvFwidth = fwidth(uv) of the atlas UVs.
float baker_text_screen_px_range(float distanceRange, vec2 atlasSize, vec2 uvFwidth) {
    vec2 unitRange = vec2(distanceRange) / atlasSize;
    vec2 screenTexSize = vec2(1.0) / max(uvFwidth, vec2(1e-12));
    return max(0.5 * dot(unitRange, screenTexSize), 1.0);
}

// Signed distance of the edge, in units of the distance range (-0.5 .. 0.5), + inside.
float baker_text_edge_distance(vec4 texel, int fieldType) {
    float v = fieldType >= BAKER_TEXT_MSDF ? baker_text_median(texel.rgb) : texel.r;
    return v - 0.5;
}

// The true distance for soft effects (MTSDF alpha; otherwise the edge distance), range units.
float baker_text_true_distance(vec4 texel, int fieldType) {
    if (fieldType == BAKER_TEXT_MTSDF) {
        return texel.a - 0.5;
    }
    return baker_text_edge_distance(texel, fieldType);
}

// Antialiased coverage of a signed distance (range units) at a screen-pixel range: Chlumsky's opacity.
float baker_text_coverage(float signedDistance, float screenPxRange) {
    return clamp(signedDistance * screenPxRange + 0.5, 0.0, 1.0);
}

// The common case: MSDF texel -> opacity.
float baker_text_msdf_opacity(vec3 msd, float screenPxRange) {
    return baker_text_coverage(baker_text_median(msd) - 0.5, screenPxRange);
}

vec4 baker_text_over(vec4 src, vec4 dst) {
    return src + dst * (1.0 - src.a);
}

// Fill + outline + glow + drop shadow, premultiplied RGBA. `texel` at uv, `shadowTexel` at uv - shadowOffset.
vec4 baker_text_shade(BakerTextStyle style, vec4 texel, vec4 shadowTexel, int fieldType, float distanceRange,
                      float screenPxRange) {
    float pxPerTexel = screenPxRange / distanceRange;      // screen pixels per atlas pixel
    float ramp = 1.0 + max(style.softness, 0.0);           // width of the edge ramp, screen pixels
    float d = baker_text_edge_distance(texel, fieldType) * distanceRange;    // atlas pixels, + inside
    float dt = baker_text_true_distance(texel, fieldType) * distanceRange;
    float ds = baker_text_true_distance(shadowTexel, fieldType) * distanceRange;

    float fill = clamp(d * pxPerTexel / ramp + 0.5, 0.0, 1.0);
    float outline = style.outlineWidth > 0.0
        ? clamp((d + style.outlineWidth) * pxPerTexel / ramp + 0.5, 0.0, 1.0) : 0.0;
    float glow = style.glowWidth > 0.0 ? 1.0 - smoothstep(0.0, style.glowWidth, -dt) : 0.0;
    float blur = max(style.shadowSoftness, 0.0) + 0.5 / pxPerTexel;  // at least half a screen pixel
    float shadow = smoothstep(-blur, blur, ds);

    vec4 result = vec4(style.shadowColor.rgb, 1.0) * (style.shadowColor.a * shadow);
    result = baker_text_over(vec4(style.glowColor.rgb, 1.0) * (style.glowColor.a * glow), result);
    result = baker_text_over(vec4(style.outlineColor.rgb, 1.0) * (style.outlineColor.a * outline), result);
    result = baker_text_over(vec4(style.color.rgb, 1.0) * (style.color.a * fill), result);
    return result;
}

#endif // BAKER_TEXT_GLSL
