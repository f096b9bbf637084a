// BAKER_hair with BAKER_hair_shading: hair_ribbon.vert.glsl's view-facing ribbons, passing on what the fibre model
// needs per strand vertex: the absorption sigma_a (from _HAIR_MELANIN or the material) and the ambient-cube fibre
// counts (_HAIR_FIBRES_POS / _NEG). baker_hair.glsl at "@baker:modules".
// @baker:modules
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_rootWidth;
uniform float u_tipWidth;
uniform float u_tanHalfFovY;
uniform float u_viewportHeight;
in vec3 POSITION;
in vec3 a_tangent;
in float a_param;
in float a_widthScale;
in float a_side;
in vec3 a_sigma;
in vec3 a_fibresPos;
in vec3 a_fibresNeg;
out vec3 v_position;
out vec3 v_tangent;
out float v_alpha;
out vec3 v_sigma;
out vec3 v_fibresPos;
out vec3 v_fibresNeg;
void main() {
    float width = baker_hair_width(u_rootWidth, u_tipWidth, a_param, a_widthScale);
    vec2 coverage = baker_hair_coverage(width, baker_hair_pixel_size(length(u_eye - POSITION), u_tanHalfFovY,
                                                                       u_viewportHeight));
    v_position = baker_hair_ribbon_position(POSITION, a_tangent, u_eye, coverage.x, a_side);
    v_tangent = a_tangent;
    v_alpha = coverage.y;
    v_sigma = a_sigma;
    v_fibresPos = a_fibresPos;
    v_fibresNeg = a_fibresNeg;
    gl_Position = u_viewProjection * vec4(v_position, 1.0);
}
