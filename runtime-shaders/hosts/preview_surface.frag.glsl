// baker preview: the fragment stage of a surface panel. The body computes `color` (and may set `alpha`) from
// N, V, P (unit normal facing the eye, normal-mapped; Ng before the map, unit direction to the eye, world
// position), `scalar` and `albedo` (the material's base colour: factor x sRGB texture, linear; the preview's
// grey 0.8 without one). The normal map is read in the glTF tangent frame: TANGENT when the primitive has it, else the frame of the
// screen-space derivatives of position and texture coordinates (as the Khronos glTF sample viewer does). Placeholders:
// "@baker:modules", "@baker:line" (u_ink / u_width when the body draws lines), "@baker:declarations",
// "@baker:inputs" (extra varyings) and "@baker:body". u_alphaMode (0 OPAQUE, the default; 1 MASK: cut where the base
// colour's alpha, factor x texture, is below u_alphaCutoff; 2 BLEND: that alpha is the output's) is the glTF
// material's alphaMode, as every glTF viewer honours it; the reference panel sets it.
// @baker:modules
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec4 u_baseColorFactor;
uniform int u_hasBaseColorTexture;
uniform sampler2D u_baseColorTexture;
uniform int u_hasNormalTexture;
uniform sampler2D u_normalTexture;
uniform float u_normalScale;
uniform int u_hasTangent;
uniform int u_alphaMode;
uniform float u_alphaCutoff;
// @baker:line
// @baker:declarations
in vec3 v_position;
in vec3 v_normal;
in float v_scalar;
in vec2 v_baseUV;
in vec2 v_normalUV;
in vec4 v_tangent;
// @baker:inputs
out vec4 fragColor;
void main() {
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_position);
    if (dot(N, V) < 0.0) N = -N;  // double-sided preview
    vec3 P = v_position;
    vec3 Ng = N;  // the interpolated normal, before the normal map (the frame of other normal maps)
    // derivatives before any branch: they are undefined in non-uniform control flow
    vec3 dPdx = dFdx(P), dPdy = dFdy(P);
    vec2 dUVdx = dFdx(v_normalUV), dUVdy = dFdy(v_normalUV);
    if (u_hasNormalTexture != 0) {
        vec3 t;
        float handedness = 1.0;
        if (u_hasTangent != 0) {
            t = v_tangent.xyz;
            handedness = v_tangent.w < 0.0 ? -1.0 : 1.0;
        } else {
            t = (dUVdy.y * dPdx - dUVdx.y * dPdy) / (dUVdx.x * dUVdy.y - dUVdy.x * dUVdx.y);
        }
        t = t - N * dot(N, t);
        if (dot(t, t) > 1e-24) {
            t = normalize(t);
            vec3 b = cross(N, t) * handedness;
            vec3 m = texture(u_normalTexture, v_normalUV).rgb * 2.0 - 1.0;
            m.xy *= u_normalScale;
            vec3 mapped = mat3(t, b, N) * m;
            if (dot(mapped, mapped) > 1e-24) N = normalize(mapped);
        }
    }
    vec3 albedo = u_baseColorFactor.rgb;
    float baseAlpha = u_baseColorFactor.a;
    if (u_hasBaseColorTexture != 0) {
        vec4 texel = texture(u_baseColorTexture, v_baseUV);
        albedo *= texel.rgb;
        baseAlpha *= texel.a;
    }
    if (u_alphaMode == 1 && baseAlpha < u_alphaCutoff) discard;
    float scalar = v_scalar;
    vec3 color;
    float alpha = u_alphaMode == 2 ? baseAlpha : 1.0;
    // @baker:body
    fragColor = vec4(clamp(color, 0.0, 1.0), alpha);
}
