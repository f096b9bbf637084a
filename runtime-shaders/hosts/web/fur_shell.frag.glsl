// A fur shell's texel, alpha-tested at u_alphaCutoff (u_alphaTest 1: opaque, coverage kept by the mip chain) or
// blended, darker towards the root, lit by the ambient and half the directional diffuse light.
uniform sampler2D u_texture;
uniform float u_shell;
uniform float u_shellCount;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFur;
varying vec3 vNormalLight;
void main() {
	vec4 texel = texture(u_texture, vUvFur);
	if (texel.a < u_alphaCutoff) discard;
	vec4 shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(u_shell, u_shellCount), 0.35);
	vec3 light = baker_ambient_light() + baker_directional_diffuse(normalize(vNormalLight)) * 0.5;
	gl_FragColor = vec4(shaded.rgb * light, mix(shaded.a, 1.0, u_alphaTest));
}
