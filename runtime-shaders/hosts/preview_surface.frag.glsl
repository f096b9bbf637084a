// baker preview: the fragment stage of a surface panel. The body computes `color` (and may set `alpha`) from
// N, V, P (unit normal facing the eye, unit direction to the eye, world position) and `scalar`. Placeholders:
// "@baker:modules", "@baker:line" (u_ink / u_width when the body draws lines), "@baker:declarations",
// "@baker:inputs" (extra varyings) and "@baker:body".
// @baker:modules
uniform vec3 u_eye;
uniform vec3 u_light;
// @baker:line
// @baker:declarations
in vec3 v_position;
in vec3 v_normal;
in float v_scalar;
// @baker:inputs
out vec4 fragColor;
void main() {
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_position);
    if (dot(N, V) < 0.0) N = -N;  // double-sided preview
    vec3 P = v_position;
    float scalar = v_scalar;
    vec3 color;
    float alpha = 1.0;
    // @baker:body
    fragColor = vec4(clamp(color, 0.0, 1.0), alpha);
}
