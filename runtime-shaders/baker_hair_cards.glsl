// baker_hair_cards.glsl: alpha-tested hair cards from BAKER_hair_cards (RTR4 14.7.1).
// No #version, no precision, no uniforms: the includer owns the header and the bindings.
//
// The material's baseColorTexture holds the strands' colour and coverage (alpha-tested at alphaCutoff); the data
// texture holds r = depth offset from the card (0.5 + 0.5 x depth / depthRange), g = root-to-tip parameter,
// b = per-strand random value; the flow texture the strands' direction in the card's tangent frame (TANGENT
// across the card, bitangent = cross(N, T) x TANGENT.w from root to tip, NORMAL), encoded 0.5 + 0.5 x f.
// Shading: Kajiya & Kay 1989 along the flow direction, the highlight shifted per strand (Scheuermann 2004).
#ifndef BAKER_HAIR_CARDS_GLSL
#define BAKER_HAIR_CARDS_GLSL

// true where the alpha test cuts the fragment (glTF MASK: alpha < cutoff is discarded).
bool baker_hair_cards_cut(float alpha, float alphaCutoff) {
    return alpha < alphaCutoff;
}

// The strand direction in world space from a flow texel (rgb in 0..1) and the interpolated frame.
vec3 baker_hair_cards_flow(vec3 flowTexel, vec3 normal, vec4 tangent) {
    vec3 f = flowTexel * 2.0 - 1.0;
    vec3 n = normalize(normal);
    vec3 t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    vec3 b = cross(n, t) * tangent.w;
    vec3 w = f.x * t + f.y * b + f.z * n;
    float len = length(w);
    return len > 1e-6 ? w / len : b;
}

// The card's tangent frame where a host has no TANGENT attribute: from screen-space derivatives of the position
// and the texture coordinates (the cotangent frame of Schueler, "Followup: Normal Mapping Without Precomputed
// Tangents", 2013): xyz across the card (+u), w = +-1 so that cross(N, xyz) x w runs along +v (root to tip).
vec4 baker_hair_cards_frame(vec3 N, vec3 dpdx, vec3 dpdy, vec2 duvdx, vec2 duvdy) {
    vec3 dp2perp = cross(dpdy, N);
    vec3 dp1perp = cross(N, dpdx);
    // the solve carries the sign of the screen's orientation against N (N facing away on a back face)
    float facing = dot(cross(dpdx, dpdy), N) < 0.0 ? -1.0 : 1.0;
    vec3 across = (dp2perp * duvdx.x + dp1perp * duvdy.x) * facing;
    vec3 along = (dp2perp * duvdx.y + dp1perp * duvdy.y) * facing;
    float len = length(across);
    vec3 t = len > 0.0 ? across / len : vec3(1.0, 0.0, 0.0);
    return vec4(t, dot(cross(N, across), along) < 0.0 ? -1.0 : 1.0);
}

// The strands' offset from the card plane along its normal (mesh units) from the data texture's red channel.
float baker_hair_cards_depth(float depthTexel, float depthRange) {
    return (depthTexel * 2.0 - 1.0) * depthRange;
}

// The card fragment pushed to the strand it shows (for depth output or parallax): position + normal x depth.
vec3 baker_hair_cards_displace(vec3 position, vec3 normal, float depthTexel, float depthRange) {
    return position + normalize(normal) * baker_hair_cards_depth(depthTexel, depthRange);
}

// Kajiya-Kay along the flow direction T: diffuse sin(T, L) on the base colour, darkened towards the root by
// rootShade (0..1) and varied per strand; specular sin(T, H)^p on the tangent shifted along the card normal by
// shift + (random - 0.5) x 0.2, so neighbouring strands' highlights do not line up. L, V unit, away from the
// surface.
vec3 baker_hair_cards_shade(vec3 baseColor, vec3 T, vec3 N, vec3 L, vec3 V, vec3 lightColor, float rootToTip,
                            float strandRandom, float exponent, float shift, float rootShade) {
    vec3 t = normalize(T + (shift + (strandRandom - 0.5) * 0.2) * normalize(N));
    float tl = dot(T, L);
    float sinTL = sqrt(max(0.0, 1.0 - tl * tl));
    vec3 H = normalize(L + V);
    float th = dot(t, H);
    float sinTH = sqrt(max(0.0, 1.0 - th * th));
    float spec = smoothstep(-1.0, 0.0, th) * pow(sinTH, exponent);
    float occlusion = mix(rootShade, 1.0, clamp(rootToTip, 0.0, 1.0));
    return lightColor * occlusion * (baseColor * sinTL + vec3(0.25) * spec * (0.5 + strandRandom));
}

#endif  // BAKER_HAIR_CARDS_GLSL
