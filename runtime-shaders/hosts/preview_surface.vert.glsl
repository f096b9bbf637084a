// baker preview: the vertex stage of a surface panel. The includer puts the version header first and fills
// "@baker:modules" (runtime modules), "@baker:declarations" (the panel's uniforms) and "@baker:body" (may
// move `position`, set v_bary / v_mask); positions and normals arrive in world space.
// @baker:modules
uniform mat4 u_viewProjection;
uniform vec3 u_eye;
uniform float u_viewportHeight;
uniform float u_projectionScaleY;
uniform float u_width;
// @baker:declarations
in vec3 POSITION;
in vec3 NORMAL;
in float a_scalar;
in vec2 TEXCOORD_0;
in vec3 a_outline;
in vec2 a_baseUV;
in vec2 a_normalUV;
in vec4 a_tangent;
in float a_mask;
out vec3 v_position;
out vec3 v_normal;
out float v_scalar;
out vec2 v_uv;
out vec2 v_baseUV;
out vec2 v_normalUV;
out vec4 v_tangent;
out vec3 v_bary;
flat out int v_mask;
void main() {
    vec3 position = POSITION;
    v_normal = NORMAL;
    v_scalar = a_scalar;
    v_uv = TEXCOORD_0;
    v_baseUV = a_baseUV;
    v_normalUV = a_normalUV;
    v_tangent = a_tangent;
    v_bary = vec3(0.0);
    v_mask = 0;
    // @baker:body
    v_position = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
