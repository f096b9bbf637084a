// BAKER_text label quads in world space; TEXCOORD_0 addresses the glyph atlas.
uniform mat4 u_viewProjection;
in vec3 POSITION;
in vec2 TEXCOORD_0;
out vec2 v_uv;
void main() {
    v_uv = TEXCOORD_0;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
