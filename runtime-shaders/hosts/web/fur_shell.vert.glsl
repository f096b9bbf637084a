// BAKER_fur shell u_shell of u_shellCount (Lengyel et al. 2001): the surface pushed out along its normal.
uniform float u_shell;
uniform float u_shellCount;
uniform float u_shellSpacing;
uniform float u_tiling;
varying vec2 vUvFur;
varying vec3 vNormalLight;
void main() {
	vec3 p = baker_fur_shell_position(position, normal, u_shell, u_shellSpacing, u_shellCount, vec3(0.0));
	vUvFur = baker_fur_shell_uv(uv, u_tiling);
	vNormalLight = baker_light_normal(normal);
	gl_Position = baker_clip(p);
}
