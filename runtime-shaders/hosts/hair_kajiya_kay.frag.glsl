// BAKER_hair ribbons shaded with Kajiya-Kay (baker_hair.glsl at "@baker:modules"), one light, coverage alpha.
// @baker:modules
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec3 u_baseColor;
in vec3 v_position;
in vec3 v_tangent;
in float v_alpha;
out vec4 fragColor;
void main() {
    vec3 T = normalize(v_tangent);
    vec3 V = normalize(u_eye - v_position);
    vec3 c = 0.15 * u_baseColor + baker_hair_kajiya_kay(T, u_light, V, u_baseColor, vec3(0.35), 40.0);
    fragColor = vec4(clamp(c, 0.0, 1.0), v_alpha);
}
