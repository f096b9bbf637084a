// BAKER_hair ribbons shaded with BAKER_hair_shading (baker_hair_shading.glsl at "@baker:modules"): Chiang et al.
// 2016's fibre tables and Zinke et al. 2008's dual scattering, the fibres crossed toward the light read from the
// ambient cube n(l) = sum_i l_i^2 c(sign l_i, i) (l: the light direction in the strands' mesh space); one light of irradiance pi (a white Lambert surface facing it is
// 1), a little ambient of the fibres' colour, coverage alpha.
// @baker:modules
uniform vec3 u_eye;
uniform vec3 u_light;
uniform vec3 u_lightMesh;  // u_light in the strands' mesh space, where the fibre counts' ambient cube is
uniform vec3 u_baseColor;
uniform sampler2D u_m;
uniform sampler2D u_n;
uniform sampler2D u_dual;
uniform vec4 u_variances;
uniform vec4 u_params;   // tilt (rad), slices, alphaF, betaF
in vec3 v_position;
in vec3 v_tangent;
in float v_alpha;
in vec3 v_sigma;
in vec3 v_fibresPos;
in vec3 v_fibresNeg;
out vec4 fragColor;
void main() {
    vec3 T = normalize(v_tangent);
    vec3 V = normalize(u_eye - v_position);
    vec3 l2 = u_lightMesh * u_lightMesh;
    float crossed = dot(l2, mix(v_fibresNeg, v_fibresPos, step(0.0, u_lightMesh)));
    BakerHairShading h = BakerHairShading(u_variances, u_params.x, u_params.y, u_params.z, u_params.w, 1.0, 1.0);
    vec3 c = 0.15 * u_baseColor + 3.14159265 * baker_hair_shading(u_m, u_n, u_dual, h, T, u_light, V, crossed,
                                                                   v_sigma);
    fragColor = vec4(clamp(c, 0.0, 1.0), v_alpha);
}
