// baker_fur.glsl: shell-and-fin fur from BAKER_fur (Lengyel et al., I3D 2001; RTR4 14.7.3).
// No #version, no precision, no uniforms: the includer owns the header and the bindings.
//
// Shells: draw the surface shellCount times; pass shell i moves each vertex out by (i + 1) x shellSpacing and
// samples shellTextures[i] at TEXCOORD_0 x tiling (RGB colour, A coverage), alpha-blended inner to outer.
// Fins: draw the fin primitive (degenerate quads on every edge, attributes _FIN_V0.._FIN_V3, _FIN_CORNER,
// _FUR_FIN_NORMAL, _FUR_FIN_UV); the vertex shader raises corners 2 and 3 by `length` along _FUR_FIN_NORMAL,
// and the fin fades in near the silhouette.
#ifndef BAKER_FUR_GLSL
#define BAKER_FUR_GLSL

// Height (0..1 of the fur length) of shell i's slice, as baked: (i + 0.5) / shellCount.
float baker_fur_shell_height(float shell, float shellCount) {
    return (shell + 0.5) / shellCount;
}

// Shell vertex: out along the normal by (shell + 1) x spacing, plus a displacement (gravity, wind; mesh units at
// the outermost shell) that grows with the square of the height, so hairs bend rather than slant.
vec3 baker_fur_shell_position(vec3 position, vec3 normal, float shell, float shellSpacing, float shellCount,
                              vec3 displacement) {
    float h = (shell + 1.0) / shellCount;
    return position + normal * ((shell + 1.0) * shellSpacing) + displacement * (h * h);
}

vec2 baker_fur_shell_uv(vec2 uv, float tiling) {
    return uv * tiling;
}

// Shell fragment: the texel's colour darkened towards the root (a cheap self-shadowing term, occlusionAtRoot in
// 0..1) and its coverage as alpha.
vec4 baker_fur_shell_shade(vec4 texel, float height, float occlusionAtRoot) {
    return vec4(texel.rgb * mix(occlusionAtRoot, 1.0, height), texel.a);
}

// The two face normals of a fin's edge from its four corners (v0, v1 the edge, v2 opposite in the first face,
// v3 opposite in the second face, which runs v1 -> v0).
void baker_fur_fin_face_normals(vec3 v0, vec3 v1, vec3 v2, vec3 v3, out vec3 n0, out vec3 n1) {
    n0 = normalize(cross(v1 - v0, v2 - v0));
    n1 = normalize(cross(v0 - v1, v3 - v1));
}

// Fin vertex: corner 0 at v0, 1 at v1 on the surface; 2 above v1 and 3 above v0 by `finLength` along `normal`.
vec3 baker_fur_fin_position(vec3 v0, vec3 v1, vec3 normal, float corner, float finLength) {
    vec3 base = (corner < 0.5 || corner > 2.5) ? v0 : v1;
    float up = corner > 1.5 ? 1.0 : 0.0;
    return base + normal * (finLength * up);
}

// How much of a fin to show: 1 on the silhouette (the edge's mean normal perpendicular to the view), falling to 0
// when |N . V| reaches `threshold` (Lengyel et al. fade fins in near the silhouette). V: unit, towards the eye.
float baker_fur_fin_weight(vec3 n0, vec3 n1, vec3 V, float threshold) {
    vec3 n = normalize(n0 + n1);
    return 1.0 - smoothstep(0.0, threshold, abs(dot(n, V)));
}

#endif  // BAKER_FUR_GLSL
