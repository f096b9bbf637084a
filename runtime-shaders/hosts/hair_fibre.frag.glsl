// BAKER_hair ribbons shaded as hair fibres (BAKER_hair_shading; baker_hair_shading.glsl at "@baker:modules", with
// hair_ribbon.vert.glsl and BAKER_HAIR_SHADING defined): one light, Chiang et al. 2016 from the baked tables plus
// Zinke et al. 2008's dual scattering with the fibres toward the light from the strand's ambient cube; the ambient
// term is the Kajiya-Kay panel's (0.15 x base colour) times the rest-pose occlusion; coverage alpha.
// @baker:modules
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec3 u_lightMesh;  // u_light in the strands' mesh space (the fibre counts' basis)
uniform vec3 u_baseColor;
uniform sampler2D u_hairLongitudinal;
uniform sampler2D u_hairAzimuthal;
uniform sampler2D u_hairDual;
uniform vec4 u_hairVariances;
uniform vec4 u_hairParams;  // tilt (radians), azimuthal slices, dual alphaF, dual betaF
in vec3 v_position;
in vec3 v_tangent;
in float v_alpha;
in vec3 v_sigmaA;
in float v_occlusion;
in vec3 v_fibresPos;
in vec3 v_fibresNeg;
out vec4 fragColor;
void main() {
    vec3 T = normalize(v_tangent);
    vec3 V = normalize(u_eye - v_position);
    BakerHairShading h = BakerHairShading(u_hairVariances, u_hairParams.x, u_hairParams.y, u_hairParams.z,
                                          u_hairParams.w, 1.0, 1.0);
    vec3 l = u_lightMesh;
    float fibres = dot(l * l, mix(v_fibresNeg, v_fibresPos, step(0.0, l)));
    vec3 c = 0.15 * u_baseColor * v_occlusion
           + baker_hair_shading(u_hairLongitudinal, u_hairAzimuthal, u_hairDual, h, T, u_light, V, fibres, v_sigmaA);
    fragColor = vec4(clamp(c, 0.0, 1.0), v_alpha);
}
