// BAKER_edges shell outline (RTR4 15.2.2): the back faces pushed out along _OUTLINE_NORMAL by a constant pixel width
// (zero on open rims; with u_width = 0, colour writes off: an open primitive's depth-only back-face pass).
attribute vec3 _outline_normal;
uniform vec2 u_viewport;
uniform float u_width;
void main() {
	vec4 clip = baker_clip(position);
	vec3 p = baker_shell_position(position, _outline_normal, clip.w, u_width, u_viewport.y, baker_projection_y());
	gl_Position = baker_clip(p);
}
