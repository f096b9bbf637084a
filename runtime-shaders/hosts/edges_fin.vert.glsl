// BAKER_edges fins (McGuire & Hughes 2004): a fin primitive's degenerate quads opened into u_width-pixel lines
// where the edge is of a class in u_show (1 contour, 2 ridge, 4 valley, 8 boundary); world-space fin vertices.
// Includer: version header, then baker_edges.glsl at "@baker:modules". v_clip / v_kind are the classification
// and clip position before the depth offset (tests read them back).
// @baker:modules
in vec3 _FIN_V0;
in vec3 _FIN_V1;
in vec3 _FIN_V2;
in vec3 _FIN_V3;
in float _FIN_CORNER;
in float _FIN_FLAGS;
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_creaseCos;
uniform float u_width;
uniform vec2 u_viewport;
uniform int u_show;
uniform float u_depthOffset;  // clip-space z pulled toward the eye (x w): drawn over the surface the edge lies on
out vec4 v_clip;
out float v_kind;
void main() {
    int kind = baker_fin_classify(_FIN_V0, _FIN_V1, _FIN_V2, _FIN_V3, _FIN_FLAGS, u_eye, u_creaseCos);
    vec4 c0 = u_viewProjection * vec4(_FIN_V0, 1.0);
    vec4 c1 = u_viewProjection * vec4(_FIN_V1, 1.0);
    v_kind = float(kind);
    v_clip = (kind & u_show) != 0 ? baker_fin_position(c0, c1, _FIN_CORNER, u_width, u_viewport) : baker_fin_culled();
    gl_Position = v_clip;
    gl_Position.z -= u_depthOffset * gl_Position.w;
}
