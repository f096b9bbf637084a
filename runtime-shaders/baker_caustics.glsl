// baker_caustics.glsl: offline-baked, looping, tileable water caustics applied as an animated light map.
//
// RTR4 section 14.5.3: "one may apply an animated texture of caustics generated offline as a light map applied on
// a surface" (CryEngine, Crysis 3). baker bakes the frames from a physical water surface (a wave spectrum refracted
// by Snell's law, gathered on a floor at `depth` metres); a frame holds the floor irradiance relative to flat
// water (1 = no caustic), texel value x intensityScale. A point is projected along the refracted sun direction onto
// the baked depth, so the pattern slides with the sun as it would; its distance from that depth fades it out.
//
// Data written by baker (schemas/BAKER_caustics/README.md):
//   frameTextures          the frames of one loop, in order; REPEAT, LINEAR (gray, or RGB with dispersion)
//   tileSize, period       metres per texture repeat, seconds per loop
//   intensityScale         irradiance of texel value 1
//   depth, waterLevel      the baked floor depth below the water surface, the surface's world height (+Y)
//   fadeDistance, strength fade-out distance from the baked depth (m), scale of the modulation
//   projectionDirection    the refracted sun direction under flat water (world space, unit, pointing down)
//
// How to include: no #version line, no precision statement, no uniforms, inputs or outputs; prepend your header
// and paste the file after it. Compiles as GLSL ES 3.00 and GLSL 3.30 core. Every function has a numpy twin in
// tests/gl/twins_caustics.py; tests/gl/test_caustics.py checks them on the GPU. GLSL ES 3.00 cannot index a
// sampler array with a variable, so the host binds the two frames of baker_caustics_frame to two samplers.

#ifndef BAKER_CAUSTICS_GLSL
#define BAKER_CAUSTICS_GLSL

// The frames to blend at `time` seconds: (index of the first frame, weight of the next one, index of the next).
// The loop wraps: after the last frame comes the first.
vec3 baker_caustics_frame(float time, float period, float frameCount) {
    float f = fract(time / period) * frameCount;
    float first = min(floor(f), frameCount - 1.0);
    float next = first + 1.0 >= frameCount ? 0.0 : first + 1.0;
    return vec3(first, f - first, next);
}

// Depth of a world point below the water surface (metres; negative above the water).
float baker_caustics_depth(vec3 worldPosition, float waterLevel) {
    return waterLevel - worldPosition.y;
}

// Texture coordinates of a world point: moved along the refracted sun direction to the baked depth, then the
// tile's axes (x -> +X, y -> -Z) divided by the tile size.
vec2 baker_caustics_uv(vec3 worldPosition, vec3 projectionDirection, float waterLevel, float depth,
                       float tileSize) {
    float below = depth - baker_caustics_depth(worldPosition, waterLevel);
    vec3 onFloor = worldPosition - projectionDirection * (below / projectionDirection.y);
    return vec2(onFloor.x, -onFloor.z) / tileSize;
}

// 1 at the baked depth, falling linearly to 0 at fadeDistance from it; 0 above the water.
float baker_caustics_fade(float pointDepth, float depth, float fadeDistance) {
    if (pointDepth <= 0.0) {
        return 0.0;
    }
    return clamp(1.0 - abs(pointDepth - depth) / max(fadeDistance, 1e-6), 0.0, 1.0);
}

// Irradiance relative to flat water, blended between two frames; `rgb` 0 reads a gray frame's red channel.
vec3 baker_caustics_irradiance(sampler2D first, sampler2D next, vec2 uv, float blend, float intensityScale,
                               float rgb) {
    vec3 a = texture(first, uv).rgb;
    vec3 b = texture(next, uv).rgb;
    vec3 e = mix(a, b, blend) * intensityScale;
    return rgb > 0.5 ? e : e.rrr;
}

// The lit colour with the caustic added: the sunlit part is redistributed by the irradiance ratio,
// litColor + sunLit (E - 1) strength fade, never below zero.
vec3 baker_caustics_apply(vec3 litColor, vec3 sunLit, vec3 irradiance, float strength, float fade) {
    return max(litColor + sunLit * (irradiance - 1.0) * (strength * fade), vec3(0.0));
}

// The diffuse light to draw once the caustic is applied, for a display without tone mapping: where the caustic adds
// light, the added light compressed into the headroom left above the pixel, before + h a / (h + a) per channel
// (a = after - before, h = 1 - before - other, at least 0: Reinhard's x / (1 + x) on the excess, slope 1 where the
// caustic starts), so a bright caustic line shows as a highlight instead of clipping to flat white; where it takes
// light away, `after` as computed. `before`, `after`: the diffuse light without and with the caustic; `other`: the
// rest of the pixel's light (indirect, specular), which the caustic leaves as it is.
vec3 baker_caustics_headroom(vec3 before, vec3 after, vec3 other) {
    vec3 room = max(vec3(1.0) - before - other, vec3(0.0));
    vec3 added = max(after - before, vec3(0.0));
    return min(after, before) + room * added / max(room + added, vec3(1e-6));
}

#endif
