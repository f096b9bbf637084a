// baker_toon.glsl: toon shading with a baked ramp, X-Toon, and hue-preserving posterization.
//
// RTR4 section 15.1. A toon shader replaces the diffuse term by a lookup in a small ramp texture that turns
// u = 0.5 + 0.5 N.L into a few flat bands (hard, or joined by short smooth transitions). Barla, Thollot & Markosian,
// "X-Toon: An Extended Toon Shader", NPAR 2006, use a 2D map instead: its second coordinate is a detail value D,
// from depth (D = 1 - log(z / zMin) / log(zMax / zMin)) or orientation (D = |N.V|^r), and rows of lower D have less
// contrast, so far or grazing surfaces soften. Posterization quantizes a colour to a few levels; RTR4 recommends a
// hue-preserving space (HSV, Y'CbCr) over quantizing R, G and B separately, which shifts hues.
//
// Data written by baker (schemas/BAKER_toon_ramp/README.md):
//   rampTexture        width x 1 (xtoon "none") or width x height (X-Toon) gray texture; LINEAR, CLAMP_TO_EDGE
//   bands, softness, shadow       the parameters of the ramp (baker_toon_bands evaluates it analytically)
//   depthRange / orientationPower the parameters of the detail function of an X-Toon map
//
// How to include: no #version line, no precision statement, no uniforms, inputs or outputs; prepend your header
// and paste the file after it. Compiles as GLSL ES 3.00 and GLSL 3.30 core. Every function has a numpy twin in
// tests/gl/twins_hatching.py; tests/gl/test_hatching.py checks them on the GPU.

#ifndef BAKER_TOON_GLSL
#define BAKER_TOON_GLSL

// The ramp coordinate of a diffuse term: u = 0.5 + 0.5 N.L, covering the shadowed side too.
float baker_toon_u(float NdotL) {
    return 0.5 + 0.5 * clamp(NdotL, -1.0, 1.0);
}

// The shade of a 1D ramp texture (sampled along its middle row).
float baker_toon_ramp(sampler2D ramp, float NdotL) {
    return texture(ramp, vec2(baker_toon_u(NdotL), 0.5)).r;
}

// The same ramp evaluated analytically: band k covers u in [k / bands, (k + 1) / bands), value
// shadow + (1 - shadow) k / (bands - 1); softness > 0 turns each step into a smoothstep of that many bands' width.
float baker_toon_bands(float u, float bands, float softness, float shadow) {
    float x = clamp(u, 0.0, 1.0) * bands;
    float level;
    if (softness <= 0.0) {
        level = min(floor(x), bands - 1.0);
    } else {
        level = 0.0;
        for (int k = 1; k < 64; ++k) {
            if (float(k) >= bands) {
                break;
            }
            float t = clamp((x - float(k) + 0.5 * softness) / softness, 0.0, 1.0);
            level += t * t * (3.0 - 2.0 * t);
        }
    }
    return shadow + (1.0 - shadow) * level / (bands - 1.0);
}

// X-Toon detail from view-space depth z (> 0): 1 at zMin, 0 at zMax (Barla et al. 2006, eq. 1).
float baker_xtoon_detail_depth(float z, float zMin, float zMax) {
    return clamp(1.0 - log(z / zMin) / log(zMax / zMin), 0.0, 1.0);
}

// X-Toon detail from orientation: |N.V|^r (1 facing the eye, 0 at the silhouette).
float baker_xtoon_detail_orientation(vec3 N, vec3 V, float r) {
    return pow(abs(dot(N, V)), r);
}

// The shade of an X-Toon map: u from N.L, v = 1 - detail (the map's top row is full detail).
float baker_xtoon(sampler2D xtoonMap, float NdotL, float detail) {
    return texture(xtoonMap, vec2(baker_toon_u(NdotL), 1.0 - clamp(detail, 0.0, 1.0))).r;
}

vec3 baker_rgb_to_hsv(vec3 c) {
    float mx = max(max(c.r, c.g), c.b);
    float mn = min(min(c.r, c.g), c.b);
    float delta = mx - mn;
    float safe = delta > 0.0 ? delta : 1.0;
    float h = mx == c.r ? (c.g - c.b) / safe : (mx == c.g ? 2.0 + (c.b - c.r) / safe : 4.0 + (c.r - c.g) / safe);
    h = delta > 0.0 ? h / 6.0 : 0.0;
    h = h - floor(h);
    float s = mx > 0.0 ? delta / mx : 0.0;
    return vec3(h, s, mx);
}

vec3 baker_hsv_to_rgb(vec3 c) {
    vec3 k = mod(vec3(5.0, 3.0, 1.0) + c.x * 6.0, 6.0);
    return c.z - c.z * c.y * clamp(min(k, 4.0 - k), 0.0, 1.0);
}

// x in [0, 1] to one of `levels` values 0, 1 / (levels - 1), ..., 1.
float baker_quantize(float x, float levels) {
    return min(floor(x * levels), levels - 1.0) / (levels - 1.0);
}

// Posterize the value (V of HSV) only: hue and saturation are kept.
vec3 baker_posterize_hsv(vec3 rgb, float levels) {
    vec3 hsv = baker_rgb_to_hsv(rgb);
    hsv.z = baker_quantize(hsv.z, levels);
    return baker_hsv_to_rgb(hsv);
}

// Posterize the luma Y' of Y'CbCr (BT.601, full range): chroma is kept.
vec3 baker_posterize_ycbcr(vec3 rgb, float levels) {
    float y = dot(rgb, vec3(0.299, 0.587, 0.114));
    float cb = dot(rgb, vec3(-0.168736, -0.331264, 0.5));
    float cr = dot(rgb, vec3(0.5, -0.418688, -0.081312));
    y = baker_quantize(y, levels);
    return clamp(vec3(y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb), 0.0, 1.0);
}

#endif
