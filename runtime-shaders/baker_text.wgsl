// baker_text.wgsl: text from distance-field glyph atlases (BAKER_glyph_atlas / BAKER_text), any scale, antialiased;
// the WGSL twin of baker_text.glsl (same functions, same arguments, same meaning; see there for the field types,
// the encoding and the effects, and schemas/BAKER_glyph_atlas/README.md).
//
// RTR4 15.5: bilinear filtering of a signed distance and a threshold at 0.5 recover the edge at any magnification
// (Green, SIGGRAPH 2007); the median of three channels keeps corners sharp (Chlumsky, "Shape Decomposition for
// Multi-channel Distance Fields", 2015); MTSDF adds the true distance in alpha. A texel v is the signed distance
// (v - 0.5) * distanceRange in atlas pixels, positive inside. Antialiasing by the screen-pixel range
//     screenPxRange = max(0.5 * dot(distanceRange / atlasSize, 1 / fwidth(uv)), 1)
// (the caller passes fwidth(uv): no derivative in here, any stage). The result is PREMULTIPLIED RGBA: blend with
// (one, one-minus-src-alpha).
//
// No entry point, no bindings: paste it once (names are unique across the runtime modules). tests/gl/test_wgsl.py
// compiles it in Chromium's WebGPU and checks it against tests/gl/twins_text.py.

const BAKER_TEXT_SDF: i32 = 0;
const BAKER_TEXT_PSDF: i32 = 1;
const BAKER_TEXT_MSDF: i32 = 2;
const BAKER_TEXT_MTSDF: i32 = 3;

// Styling of BAKER_text in atlas-pixel units (em * size) and screen pixels; colors are straight (not premultiplied).
struct BakerTextStyle {
    color: vec4f,           // fill (BAKER_text.color)
    softness: f32,          // extra edge blur, screen pixels (0 = crisp antialiasing)
    outlineColor: vec4f,    // BAKER_text.outline.color
    outlineWidth: f32,      // atlas pixels (BAKER_text.outline.width * size); <= 0: no outline
    glowColor: vec4f,
    glowWidth: f32,         // atlas pixels; <= 0: no glow
    shadowColor: vec4f,     // alpha 0: no shadow
    shadowSoftness: f32,    // atlas pixels
}

fn baker_text_median(v: vec3f) -> f32 {
    return max(min(v.r, v.g), min(max(v.r, v.g), v.b));
}

// Screen pixels spanned by the whole distance range at this fragment; uvFwidth = fwidth(uv) of the atlas UVs.
fn baker_text_screen_px_range(distanceRange: f32, atlasSize: vec2f, uvFwidth: vec2f) -> f32 {
    let unitRange = vec2f(distanceRange) / atlasSize;
    let screenTexSize = vec2f(1.0) / max(uvFwidth, vec2f(1e-12));
    return max(0.5 * dot(unitRange, screenTexSize), 1.0);
}

// Signed distance of the edge, in units of the distance range (-0.5 .. 0.5), + inside.
fn baker_text_edge_distance(texel: vec4f, fieldType: i32) -> f32 {
    let v = select(texel.r, baker_text_median(texel.rgb), fieldType >= BAKER_TEXT_MSDF);
    return v - 0.5;
}

// The true distance for soft effects (MTSDF alpha; otherwise the edge distance), range units.
fn baker_text_true_distance(texel: vec4f, fieldType: i32) -> f32 {
    if (fieldType == BAKER_TEXT_MTSDF) {
        return texel.a - 0.5;
    }
    return baker_text_edge_distance(texel, fieldType);
}

// Antialiased coverage of a signed distance (range units) at a screen-pixel range: Chlumsky's opacity.
fn baker_text_coverage(signedDistance: f32, screenPxRange: f32) -> f32 {
    return clamp(signedDistance * screenPxRange + 0.5, 0.0, 1.0);
}

// The common case: MSDF texel -> opacity.
fn baker_text_msdf_opacity(msd: vec3f, screenPxRange: f32) -> f32 {
    return baker_text_coverage(baker_text_median(msd) - 0.5, screenPxRange);
}

fn baker_text_over(src: vec4f, dst: vec4f) -> vec4f {
    return src + dst * (1.0 - src.a);
}

// Fill + outline + glow + drop shadow, premultiplied RGBA. `texel` at uv, `shadowTexel` at uv - shadowOffset.
fn baker_text_shade(style: BakerTextStyle, texel: vec4f, shadowTexel: vec4f, fieldType: i32, distanceRange: f32,
                    screenPxRange: f32) -> vec4f {
    let pxPerTexel = screenPxRange / distanceRange;      // screen pixels per atlas pixel
    let ramp = 1.0 + max(style.softness, 0.0);          // width of the edge ramp, screen pixels
    let d = baker_text_edge_distance(texel, fieldType) * distanceRange;    // atlas pixels, + inside
    let dt = baker_text_true_distance(texel, fieldType) * distanceRange;
    let ds = baker_text_true_distance(shadowTexel, fieldType) * distanceRange;

    let fill = clamp(d * pxPerTexel / ramp + 0.5, 0.0, 1.0);
    var outline = 0.0;
    if (style.outlineWidth > 0.0) {
        outline = clamp((d + style.outlineWidth) * pxPerTexel / ramp + 0.5, 0.0, 1.0);
    }
    var glow = 0.0;
    if (style.glowWidth > 0.0) {
        glow = 1.0 - smoothstep(0.0, style.glowWidth, -dt);
    }
    let blur = max(style.shadowSoftness, 0.0) + 0.5 / pxPerTexel;  // at least half a screen pixel
    let shadow = smoothstep(-blur, blur, ds);

    var result = vec4f(style.shadowColor.rgb, 1.0) * (style.shadowColor.a * shadow);
    result = baker_text_over(vec4f(style.glowColor.rgb, 1.0) * (style.glowColor.a * glow), result);
    result = baker_text_over(vec4f(style.outlineColor.rgb, 1.0) * (style.outlineColor.a * outline), result);
    result = baker_text_over(vec4f(style.color.rgb, 1.0) * (style.color.a * fill), result);
    return result;
}
