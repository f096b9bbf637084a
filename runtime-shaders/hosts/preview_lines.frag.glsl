// baker preview: the fragment stage of plain line primitives: the material's base colour with the diffuse term of
// Kajiya & Kay (1989) for a thin fibre, sin(T, L) = sqrt(1 - (T.L)^2), over an ambient floor.
uniform vec3 u_light;
uniform vec3 u_baseColor;
in vec3 v_tangent;
out vec4 fragColor;
void main() {
    vec3 T = normalize(v_tangent);
    float TdotL = dot(T, u_light);
    float diffuse = sqrt(max(1.0 - TdotL * TdotL, 0.0));
    fragColor = vec4(clamp(u_baseColor * (0.25 + 0.75 * diffuse), 0.0, 1.0), 1.0);
}
