// The wireframe's coverage of the masked edges, premultiplied alpha out (blend ONE, ONE_MINUS_SRC_ALPHA).
uniform vec3 u_color;
uniform float u_width;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vec2 cov = baker_wireframe(vBary, fwidth(vBary), vMask, u_width, 0.0);
	if (cov.x <= 0.0) discard;
	gl_FragColor = vec4(u_color * cov.x, cov.x);
}
