// baker_toon.wgsl: toon shading with a baked ramp, X-Toon, and hue-preserving posterization (RTR4 15.1); the WGSL
// twin of baker_toon.glsl (same functions, same arguments, same meaning; see there and
// schemas/BAKER_toon_ramp/README.md). Barla, Thollot & Markosian, "X-Toon: An Extended Toon Shader", NPAR 2006:
// a 2D map whose second coordinate is a detail value from depth or orientation.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D argument is a texture_2d<f32> and its sampler
// (LINEAR, CLAMP_TO_EDGE for the ramp and the X-Toon map); GLSL texture() is textureSample (fragment stage); GLSL's
// mod(x, y) = x - y floor(x / y) is written out (WGSL's % truncates). No entry point, no bindings: paste it once
// (names are unique across the runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks
// it against tests/gl/twins_toon.py.

// The ramp coordinate of a diffuse term: u = 0.5 + 0.5 N.L, covering the shadowed side too.
fn baker_toon_u(NdotL: f32) -> f32 {
    return 0.5 + 0.5 * clamp(NdotL, -1.0, 1.0);
}

// The shade of a 1D ramp texture (sampled along its middle row).
fn baker_toon_ramp(ramp: texture_2d<f32>, rampSampler: sampler, NdotL: f32) -> f32 {
    return textureSample(ramp, rampSampler, vec2f(baker_toon_u(NdotL), 0.5)).r;
}

// The same ramp evaluated analytically: band k covers u in [k / bands, (k + 1) / bands), value
// shadow + (1 - shadow) k / (bands - 1); softness > 0 turns each step into a smoothstep of that many bands' width.
fn baker_toon_bands(u: f32, bands: f32, softness: f32, shadow: f32) -> f32 {
    let x = clamp(u, 0.0, 1.0) * bands;
    var level: f32;
    if (softness <= 0.0) {
        level = min(floor(x), bands - 1.0);
    } else {
        level = 0.0;
        for (var k = 1; k < 64; k++) {
            if (f32(k) >= bands) {
                break;
            }
            let t = clamp((x - f32(k) + 0.5 * softness) / softness, 0.0, 1.0);
            level += t * t * (3.0 - 2.0 * t);
        }
    }
    return shadow + (1.0 - shadow) * level / (bands - 1.0);
}

// X-Toon detail from view-space depth z (> 0): 1 at zMin, 0 at zMax (Barla et al. 2006, eq. 1).
fn baker_xtoon_detail_depth(z: f32, zMin: f32, zMax: f32) -> f32 {
    return clamp(1.0 - log(z / zMin) / log(zMax / zMin), 0.0, 1.0);
}

// X-Toon detail from orientation: |N.V|^r (1 facing the eye, 0 at the silhouette).
fn baker_xtoon_detail_orientation(N: vec3f, V: vec3f, r: f32) -> f32 {
    return pow(abs(dot(N, V)), r);
}

// The shade of an X-Toon map: u from N.L, v = 1 - detail (the map's top row is full detail).
fn baker_xtoon(xtoonMap: texture_2d<f32>, xtoonSampler: sampler, NdotL: f32, detail: f32) -> f32 {
    return textureSample(xtoonMap, xtoonSampler, vec2f(baker_toon_u(NdotL), 1.0 - clamp(detail, 0.0, 1.0))).r;
}

fn baker_rgb_to_hsv(c: vec3f) -> vec3f {
    let mx = max(max(c.r, c.g), c.b);
    let mn = min(min(c.r, c.g), c.b);
    let delta = mx - mn;
    let safe = select(1.0, delta, delta > 0.0);
    var h = select(select(4.0 + (c.r - c.g) / safe, 2.0 + (c.b - c.r) / safe, mx == c.g), (c.g - c.b) / safe,
                   mx == c.r);
    h = select(0.0, h / 6.0, delta > 0.0);
    h = h - floor(h);
    let s = select(0.0, delta / mx, mx > 0.0);
    return vec3f(h, s, mx);
}

fn baker_hsv_to_rgb(c: vec3f) -> vec3f {
    let x = vec3f(5.0, 3.0, 1.0) + c.x * 6.0;
    let k = x - 6.0 * floor(x / 6.0);  // GLSL mod(x, 6)
    return c.z - c.z * c.y * clamp(min(k, 4.0 - k), vec3f(0.0), vec3f(1.0));
}

// x in [0, 1] to one of `levels` values 0, 1 / (levels - 1), ..., 1.
fn baker_quantize(x: f32, levels: f32) -> f32 {
    return min(floor(x * levels), levels - 1.0) / (levels - 1.0);
}

// Posterize the value (V of HSV) only: hue and saturation are kept.
fn baker_posterize_hsv(rgb: vec3f, levels: f32) -> vec3f {
    var hsv = baker_rgb_to_hsv(rgb);
    hsv.z = baker_quantize(hsv.z, levels);
    return baker_hsv_to_rgb(hsv);
}

// Posterize the luma Y' of Y'CbCr (BT.601, full range): chroma is kept.
fn baker_posterize_ycbcr(rgb: vec3f, levels: f32) -> vec3f {
    var y = dot(rgb, vec3f(0.299, 0.587, 0.114));
    let cb = dot(rgb, vec3f(-0.168736, -0.331264, 0.5));
    let cr = dot(rgb, vec3f(0.5, -0.418688, -0.081312));
    y = baker_quantize(y, levels);
    return clamp(vec3f(y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb), vec3f(0.0), vec3f(1.0));
}
