// A fur fin's texel times its silhouette weight, lit like the shells.
uniform sampler2D u_texture;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalLight;
void main() {
	vec4 texel = texture(u_texture, vUvFin);
	if (texel.a < u_alphaCutoff) discard;
	float a = mix(texel.a, 1.0, u_alphaTest) * vWeight;
	if (a < 0.01) discard;
	vec3 light = baker_ambient_light() + baker_directional_diffuse(normalize(vNormalLight)) * 0.5;
	gl_FragColor = vec4(texel.rgb * light, a);
}
