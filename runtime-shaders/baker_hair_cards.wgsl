// baker_hair_cards.wgsl: alpha-tested hair cards from BAKER_hair_cards (RTR4 14.7.1); the WGSL twin of
// baker_hair_cards.glsl (same functions, same arguments, same meaning; see there for the textures' encoding and
// schemas/BAKER_hair_cards/README.md). Shading: Kajiya & Kay 1989 along the flow direction, the highlight shifted
// per strand (Scheuermann 2004). No entry point, no bindings: paste it once (names are unique across the runtime
// modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against tests/gl/twins_hair_cards.py.

// true where the alpha test cuts the fragment (glTF MASK: alpha < cutoff is discarded).
fn baker_hair_cards_cut(alpha: f32, alphaCutoff: f32) -> bool {
    return alpha < alphaCutoff;
}

// The strand direction in world space from a flow texel (rgb in 0..1) and the interpolated frame.
fn baker_hair_cards_flow(flowTexel: vec3f, normal: vec3f, tangent: vec4f) -> vec3f {
    let f = flowTexel * 2.0 - 1.0;
    let n = normalize(normal);
    let t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    let b = cross(n, t) * tangent.w;
    let w = f.x * t + f.y * b + f.z * n;
    let len = length(w);
    return select(b, w / len, len > 1e-6);
}

// The card's tangent frame where a host has no TANGENT attribute, from screen-space derivatives of the position and
// the texture coordinates (Schueler's cotangent frame, 2013): xyz across the card (+u), w = +-1 so that
// cross(N, xyz) x w runs along +v (root to tip). The position's derivatives are named dPdx/dPdy, not after the
// builtins: Babylon.js's WGSL processor rewrites every `dpdy` in a fragment shader (its y flip).
fn baker_hair_cards_frame(N: vec3f, dPdx: vec3f, dPdy: vec3f, duvdx: vec2f, duvdy: vec2f) -> vec4f {
    let dp2perp = cross(dPdy, N);
    let dp1perp = cross(N, dPdx);
    // the solve carries the sign of the screen's orientation against N (N facing away on a back face)
    let facing = select(1.0, -1.0, dot(cross(dPdx, dPdy), N) < 0.0);
    let across = (dp2perp * duvdx.x + dp1perp * duvdy.x) * facing;
    let along = (dp2perp * duvdx.y + dp1perp * duvdy.y) * facing;
    let len = length(across);
    let t = select(vec3f(1.0, 0.0, 0.0), across / len, len > 0.0);
    return vec4f(t, select(1.0, -1.0, dot(cross(N, across), along) < 0.0));
}

// The strands' offset from the card plane along its normal (mesh units) from the data texture's red channel.
fn baker_hair_cards_depth(depthTexel: f32, depthRange: f32) -> f32 {
    return (depthTexel * 2.0 - 1.0) * depthRange;
}

// The card fragment pushed to the strand it shows (for depth output or parallax): position + normal x depth.
fn baker_hair_cards_displace(position: vec3f, normal: vec3f, depthTexel: f32, depthRange: f32) -> vec3f {
    return position + normalize(normal) * baker_hair_cards_depth(depthTexel, depthRange);
}

// Kajiya-Kay along the flow direction T: diffuse sin(T, L) on the base colour, darkened towards the root by
// rootShade and varied per strand; specular sin(T, H)^p on the tangent shifted along the card normal by
// shift + (random - 0.5) x 0.2. L, V unit, away from the surface.
fn baker_hair_cards_shade(baseColor: vec3f, T: vec3f, N: vec3f, L: vec3f, V: vec3f, lightColor: vec3f,
                          rootToTip: f32, strandRandom: f32, exponent: f32, shift: f32, rootShade: f32) -> vec3f {
    let t = normalize(T + (shift + (strandRandom - 0.5) * 0.2) * normalize(N));
    let tl = dot(T, L);
    let sinTL = sqrt(max(0.0, 1.0 - tl * tl));
    let H = normalize(L + V);
    let th = dot(t, H);
    let sinTH = sqrt(max(0.0, 1.0 - th * th));
    let spec = smoothstep(-1.0, 0.0, th) * pow(sinTH, exponent);
    let occlusion = mix(rootShade, 1.0, clamp(rootToTip, 0.0, 1.0));
    return lightColor * occlusion * (baseColor * sinTL + vec3f(0.25) * spec * (0.5 + strandRandom));
}
