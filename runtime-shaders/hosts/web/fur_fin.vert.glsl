// BAKER_fur fins (Lengyel et al. 2001): each edge's quad opened to the fur length, faded away from the silhouette.
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute vec3 _fur_fin_normal;
attribute vec2 _fur_fin_uv;
uniform float u_length;
uniform float u_threshold;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalLight;
void main() {
	vec3 p = baker_fur_fin_position(_fin_v0, _fin_v1, _fur_fin_normal, _fin_corner, u_length);
	vec3 n0;
	vec3 n1;
	baker_fur_fin_face_normals(_fin_v0, _fin_v1, _fin_v2, _fin_v3, n0, n1);
	vWeight = baker_fur_fin_weight(n0, n1, normalize(baker_object_eye() - p), u_threshold);
	vUvFin = _fur_fin_uv;
	vNormalLight = baker_light_normal(_fur_fin_normal);
	gl_Position = baker_clip(p);
}
