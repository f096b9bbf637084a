// BAKER_hair: each line vertex twice (baker_side 0 / 1), opened into a view-facing ribbon at least a pixel wide, with
// the pixel coverage as opacity; widths x u_lodWidthScale for a level of `lods`. With BAKER_HAIR_SHADING defined (the
// fibre model, hair_fibre.frag) it also passes the strand's absorption, rest-pose occlusion and fibre counts.
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
#ifdef BAKER_HAIR_SHADING
// per-strand eumelanin, pheomelanin (melaninAttribute; else unused) and the rest-pose ambient visibility
// (occlusion.attribute; 1 without one), one attribute: WebGPU allows 8 vertex buffers
attribute vec3 baker_fibre;
attribute vec3 baker_fibresPos;    // ambient-cube fibre counts c(+x), c(+y), c(+z) (fibreCount), 0 without one
attribute vec3 baker_fibresNeg;    // c(-x), c(-y), c(-z)
uniform vec3 u_hairSigmaA;         // the material's sigmaA
uniform float u_hairMelaninPerVertex;
varying vec3 vSigmaA;
varying float vOcclusion;
varying vec3 vFibresPos;
varying vec3 vFibresNeg;
varying vec3 vAxisX;               // the mesh axes in the lights' space: a light direction -> the counts' mesh space
varying vec3 vAxisY;
varying vec3 vAxisZ;
#endif
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
#ifdef BAKER_HAIR_SHADING
	vSigmaA = u_hairMelaninPerVertex > 0.5 ? baker_hair_shading_melanin(baker_fibre.x, baker_fibre.y) : u_hairSigmaA;
	vOcclusion = baker_fibre.z;
	vFibresPos = baker_fibresPos;
	vFibresNeg = baker_fibresNeg;
	vAxisX = normalize(baker_light_vector(vec3(1.0, 0.0, 0.0)));
	vAxisY = normalize(baker_light_vector(vec3(0.0, 1.0, 0.0)));
	vAxisZ = normalize(baker_light_vector(vec3(0.0, 0.0, 1.0)));
#endif
}
