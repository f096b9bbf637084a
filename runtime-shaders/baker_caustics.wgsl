// baker_caustics.wgsl: offline-baked, looping, tileable water caustics applied as an animated light map (RTR4
// 14.5.3); the WGSL twin of baker_caustics.glsl (same functions, same arguments, same meaning; see there and
// schemas/BAKER_caustics/README.md). A point is projected along the refracted sun onto the baked depth; its
// distance from that depth fades the caustic out.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D argument is a texture_2d<f32> and its sampler
// (REPEAT, LINEAR for the frames; the same sampler may be passed twice); GLSL texture() is textureSample
// (fragment stage, implicit derivatives, so a mip chain is used as GLSL would). No entry point, no bindings: paste it once (names are
// unique across the runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against
// tests/gl/twins_caustics.py.

// The frames to blend at `time` seconds: (index of the first frame, weight of the next one, index of the next).
// The loop wraps: after the last frame comes the first.
fn baker_caustics_frame(time: f32, period: f32, frameCount: f32) -> vec3f {
    let f = fract(time / period) * frameCount;
    let first = min(floor(f), frameCount - 1.0);
    let next = select(first + 1.0, 0.0, first + 1.0 >= frameCount);
    return vec3f(first, f - first, next);
}

// Depth of a world point below the water surface (metres; negative above the water).
fn baker_caustics_depth(worldPosition: vec3f, waterLevel: f32) -> f32 {
    return waterLevel - worldPosition.y;
}

// Texture coordinates of a world point: moved along the refracted sun direction to the baked depth, then the
// tile's axes (x -> +X, y -> -Z) divided by the tile size.
fn baker_caustics_uv(worldPosition: vec3f, projectionDirection: vec3f, waterLevel: f32, depth: f32,
                     tileSize: f32) -> vec2f {
    let below = depth - baker_caustics_depth(worldPosition, waterLevel);
    let onFloor = worldPosition - projectionDirection * (below / projectionDirection.y);
    return vec2f(onFloor.x, -onFloor.z) / tileSize;
}

// 1 at the baked depth, falling linearly to 0 at fadeDistance from it; 0 above the water.
fn baker_caustics_fade(pointDepth: f32, depth: f32, fadeDistance: f32) -> f32 {
    if (pointDepth <= 0.0) {
        return 0.0;
    }
    return clamp(1.0 - abs(pointDepth - depth) / max(fadeDistance, 1e-6), 0.0, 1.0);
}

// Irradiance relative to flat water, blended between two frames; `rgb` 0 reads a gray frame's red channel.
fn baker_caustics_irradiance(first: texture_2d<f32>, firstSampler: sampler, next: texture_2d<f32>,
                             nextSampler: sampler, uv: vec2f, blend: f32, intensityScale: f32, rgb: f32) -> vec3f {
    let a = textureSample(first, firstSampler, uv).rgb;
    let b = textureSample(next, nextSampler, uv).rgb;
    let e = mix(a, b, blend) * intensityScale;
    return select(e.rrr, e, rgb > 0.5);
}

// The lit colour with the caustic added: the sunlit part redistributed by the irradiance ratio,
// litColor + sunLit (E - 1) strength fade, never below zero.
fn baker_caustics_apply(litColor: vec3f, sunLit: vec3f, irradiance: vec3f, strength: f32, fade: f32) -> vec3f {
    return max(litColor + sunLit * (irradiance - 1.0) * (strength * fade), vec3f(0.0));
}

// The diffuse light to draw once the caustic is applied, for a display without tone mapping: where the caustic adds
// light, the added light compressed into the headroom left above the pixel, before + h a / (h + a) per channel
// (a = after - before, h = 1 - before - other, at least 0: Reinhard's x / (1 + x) on the excess, slope 1 where the
// caustic starts), so a bright caustic line shows as a highlight instead of clipping to flat white; where it takes
// light away, `after` as computed. `before`, `after`: the diffuse light without and with the caustic; `other`: the
// rest of the pixel's light (indirect, specular), which the caustic leaves as it is.
fn baker_caustics_headroom(before: vec3f, after: vec3f, other: vec3f) -> vec3f {
    let room = max(vec3f(1.0) - before - other, vec3f(0.0));
    let added = max(after - before, vec3f(0.0));
    return min(after, before) + room * added / max(room + added, vec3f(1e-6));
}
