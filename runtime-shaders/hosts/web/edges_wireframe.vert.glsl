// BAKER_edges single-pass wireframe (Baerentzen et al. 2006): a non-indexed copy with per-corner barycentrics and
// the triangle's edge mask.
attribute vec3 baker_bary;
attribute float baker_mask;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vBary = baker_bary;
	vMask = int(baker_mask + 0.5);
	gl_Position = baker_clip(position);
}
