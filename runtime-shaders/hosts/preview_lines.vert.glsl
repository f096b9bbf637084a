// baker preview: the vertex stage of plain line primitives (a groom without BAKER_hair: LINES, LINE_STRIP,
// LINE_LOOP), drawn as lines in the reference panel. Positions and segment tangents arrive in world space.
uniform mat4 u_viewProjection;
in vec3 POSITION;
in vec3 a_tangent;
out vec3 v_tangent;
void main() {
    v_tangent = a_tangent;
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
