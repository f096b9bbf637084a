// BAKER_edges fins (McGuire & Hughes 2004): the fin primitive's degenerate quads opened into u_width-pixel lines
// where the edge is of a class in u_classes, drawn just over the surface it outlines. Object-space fin vertices.
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute float _fin_flags;
uniform vec2 u_viewport;
uniform float u_width;
uniform float u_creaseCos;
uniform int u_classes;
void main() {
	vec3 eye = baker_object_eye();
	int c = baker_fin_classify(_fin_v0, _fin_v1, _fin_v2, _fin_v3, _fin_flags, eye, u_creaseCos);
	vec4 clip0 = baker_clip(_fin_v0);
	vec4 clip1 = baker_clip(_fin_v1);
	if ((c & u_classes) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		gl_Position = baker_fin_culled();
		return;
	}
	gl_Position = baker_fin_position(clip0, clip1, _fin_corner, u_width, u_viewport);
	gl_Position.z -= 1e-4 * gl_Position.w;
}
