// BAKER_hair ribbons shaded as hair fibres (BAKER_hair_shading; runtime-shaders/baker_hair_shading.glsl): per
// directional light, Chiang et al. 2016's single scattering from the baked tables plus Zinke et al. 2008's dual
// scattering with the number of fibres toward the light read from the strand's baked ambient cube; the ambient light
// times the material's multiply scattered colour and the rest-pose occlusion; coverage as opacity. Needs
// hair_ribbon.vert with BAKER_HAIR_SHADING defined.
uniform vec3 u_color;
uniform sampler2D u_hairLongitudinal;
uniform sampler2D u_hairAzimuthal;
uniform sampler2D u_hairDual;
uniform vec4 u_hairVariances;
uniform vec4 u_hairParams;  // tilt (radians), azimuthal slices, dual alphaF, dual betaF
varying float vOpacity;
varying vec3 vTangent;
varying vec3 vView;
varying vec3 vSigmaA;
varying float vOcclusion;
varying vec3 vFibresPos;
varying vec3 vFibresNeg;
varying vec3 vAxisX;
varying vec3 vAxisY;
varying vec3 vAxisZ;
// the ambient cube of fibre counts toward the unit direction L (lights' space; McTaggart 2004's basis in mesh space)
float baker_hair_fibres_toward(vec3 L) {
	vec3 l = normalize(vec3(dot(L, vAxisX), dot(L, vAxisY), dot(L, vAxisZ)));
	vec3 c = mix(vFibresNeg, vFibresPos, step(0.0, l));
	return dot(l * l, c);
}
void main() {
	vec3 T = normalize(vTangent);
	vec3 V = normalize(vView);
	BakerHairShading h = BakerHairShading(u_hairVariances, u_hairParams.x, u_hairParams.y, u_hairParams.z,
		u_hairParams.w, 1.0, 1.0);
	vec3 color = baker_ambient_light() * u_color * vOcclusion;
	for (int i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) break;
		vec3 L = baker_light_direction(i);
		color += baker_light_color(i) * baker_hair_shading(u_hairLongitudinal, u_hairAzimuthal, u_hairDual, h, T, L, V,
			baker_hair_fibres_toward(L), vSigmaA);
	}
	gl_FragColor = vec4(color, vOpacity);
}
