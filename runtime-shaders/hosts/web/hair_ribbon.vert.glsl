// BAKER_hair: each line vertex twice (baker_side 0 / 1), opened into a view-facing ribbon at least a pixel wide, with
// the pixel coverage as opacity; widths x u_lodWidthScale for a level of `lods`.
attribute vec3 baker_tangent;
attribute float baker_param;
attribute float baker_side;
attribute float baker_widthScale;
uniform float u_rootWidth;
uniform float u_tipWidth;
uniform float u_lodWidthScale;
uniform vec2 u_viewport;
varying float vOpacity;
varying vec3 vTangent;
varying vec3 vView;
void main() {
	vec3 eye = baker_object_eye();
	float w = baker_hair_lod_width(baker_hair_width(u_rootWidth, u_tipWidth, baker_param, baker_widthScale), u_lodWidthScale);
	float tanHalfFovY = 1.0 / baker_projection_y();
	vec2 cov = baker_hair_coverage(w, baker_hair_pixel_size(distance(eye, position), tanHalfFovY, u_viewport.y));
	vec3 p = baker_hair_ribbon_position(position, baker_tangent, eye, cov.x, baker_side);
	vOpacity = cov.y;
	vTangent = normalize(baker_light_vector(baker_tangent));
	vView = baker_to_eye(p);
	gl_Position = baker_clip(p);
}
