// BAKER_hair ribbons shaded with Kajiya-Kay per directional light plus the ambient light, coverage as opacity.
uniform vec3 u_color;
uniform vec3 u_specular;
uniform float u_exponent;
varying float vOpacity;
varying vec3 vTangent;
varying vec3 vView;
void main() {
	vec3 T = normalize(vTangent);
	vec3 V = normalize(vView);
	vec3 color = baker_ambient_light() * u_color;
	for (int i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) break;
		color += baker_light_color(i) * baker_hair_kajiya_kay(T, baker_light_direction(i), V, u_color, u_specular, u_exponent);
	}
	gl_FragColor = vec4(color, vOpacity);
}
