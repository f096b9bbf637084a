// baker_hair_shading.glsl: hair shaded like hair (RTR4 14.7.2). Chiang et al. 2016's fibre model (pbrt's HairBxDF:
// d'Eon's M_p, the trimmed logistic N_p, A_p with Fresnel and melanin absorption, p = R, TT, TRT + residual) read
// from its baked tables (`baker hair-lut`, BAKER_hair_shading), and Zinke et al. 2008's dual scattering (global
// transmittance Psi_G from the number of fibres between the fibre and the light, local backscatter Psi_G Psi_L from
// the per-fibre averages). No #version, no precision, no uniforms: the includer owns the header and the bindings.
//
// Tables (hair_lut.json; half float, LINEAR filtering, CLAMP_TO_EDGE, no mips; endpoint-aligned: texel i is at
// t = i / (size - 1)):
//   mTable    (hair_longitudinal): RGB = M_R, M_TT, M_TRT; u = theta_i / pi + 0.5, v = theta_o' / pi + 0.5
//   nTable    (hair_azimuthal): RGBA = A_R N_R, A_TT N_TT, A_TRT N_TRT, A_residual / (2 pi); u = |phi| / pi;
//             `slices` blocks of thetaSize rows stacked along the absorption x = 1 - exp(-sigma_a / 2), row
//             slice * thetaSize + |theta_o| / (pi / 2) * (thetaSize - 1)
//   dualTable (hair_dual_scattering): RGBA = a_f, a_b, alpha_b, beta_b; u = |theta| / (pi / 2), v = x
// Angles: theta = asin(dot(w, T)) with T the fibre tangent, phi the angle between L and V about T; L and V point
// away from the fibre. The result is the radiance toward V per unit irradiance from L (multiply by the light's
// colour and intensity; no cosine: it is in the model). The numpy twin is baker.api.hair_shade / hair_bsdf.
#ifndef BAKER_HAIR_SHADING_GLSL
#define BAKER_HAIR_SHADING_GLSL

const float BAKER_HAIR_SHADING_PI = 3.14159265358979;

// The runtime half of BAKER_hair_shading (hair_lut.json), field for field.
struct BakerHairShading {
    vec4 variances;        // parameters.longitudinalVariance: d'Eon's v for R, TT, TRT, residual
    float tilt;            // cuticle tilt alpha, radians (R turns by -2 alpha, TT by alpha, TRT by 4 alpha)
    float slices;          // azimuthal.slices: absorption slices of nTable
    float alphaF;          // dualScattering.alphaF: shift of one forward scattering, radians
    float betaF;           // dualScattering.betaF: its width, radians
    float densityForward;  // Zinke's d_f (1 for a count of the fibres crossed; Zinke used 0.7 with opacity maps)
    float densityBack;     // Zinke's d_b (likewise)
};

// d'Eon et al. 2011's absorption per fibre radius of eumelanin and pheomelanin concentrations (pbrt's).
vec3 baker_hair_shading_melanin(float eumelanin, float pheomelanin) {
    return eumelanin * vec3(0.419, 0.697, 1.37) + pheomelanin * vec3(0.187, 0.4, 1.05);
}

// The tables' absorption axis: x = 1 - exp(-sigma_a / 2) per channel (transmittance through one diameter).
vec3 baker_hair_shading_absorption(vec3 sigmaA) {
    return 1.0 - exp(-0.5 * sigmaA);
}

// (theta_i, theta_o, phi) of light L and view V about tangent T (phi in [0, pi]; 0 when a projection vanishes).
vec3 baker_hair_shading_angles(vec3 T, vec3 L, vec3 V) {
    vec3 t = normalize(T);
    float sinI = clamp(dot(L, t), -1.0, 1.0);
    float sinO = clamp(dot(V, t), -1.0, 1.0);
    vec3 pl = L - sinI * t;
    vec3 pv = V - sinO * t;
    float norm = length(pl) * length(pv);
    float cosPhi = norm > 1e-12 ? dot(pl, pv) / norm : 1.0;
    return vec3(asin(sinI), asin(sinO), acos(clamp(cosPhi, -1.0, 1.0)));
}

// M_R, M_TT, M_TRT at theta_o tilted per lobe, and the residual's M (the TRT variance, untilted): four fetches.
vec4 baker_hair_shading_longitudinal(sampler2D mTable, float thetaI, float thetaO, float tilt) {
    vec2 size = vec2(textureSize(mTable, 0));
    float u = (clamp(thetaI / BAKER_HAIR_SHADING_PI + 0.5, 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    vec4 shift = vec4(-2.0 * tilt, tilt, 4.0 * tilt, 0.0);
    vec4 m;
    for (int p = 0; p < 4; ++p) {
        // asin(sin(theta_o + shift)): the tilted angle, reflected about +-pi/2 (exact, where asin(sin) is not)
        float thetaP = thetaO + shift[p];
        thetaP = thetaP > 0.5 * BAKER_HAIR_SHADING_PI ? BAKER_HAIR_SHADING_PI - thetaP
               : (thetaP < -0.5 * BAKER_HAIR_SHADING_PI ? -BAKER_HAIR_SHADING_PI - thetaP : thetaP);
        float v = (clamp(thetaP / BAKER_HAIR_SHADING_PI + 0.5, 0.0, 1.0) * (size.y - 1.0) + 0.5) / size.y;
        m[p] = textureLod(mTable, vec2(u, v), 0.0)[min(p, 2)];
    }
    return m;
}

// The h-averaged A_p N_p (R, TT, TRT, residual / 2 pi) at |phi|, |theta_o| and one channel's absorption x: two
// fetches, linear between the two nearest absorption slices.
vec4 baker_hair_shading_azimuthal(sampler2D nTable, float slices, float phi, float thetaO, float x) {
    vec2 size = vec2(textureSize(nTable, 0));
    float thetaSize = size.y / slices;
    float s = clamp(x, 0.0, 1.0) * (slices - 1.0);
    float k = min(floor(s), slices - 2.0);
    float u = (clamp(abs(phi) / BAKER_HAIR_SHADING_PI, 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    float row = clamp(abs(thetaO) / (0.5 * BAKER_HAIR_SHADING_PI), 0.0, 1.0) * (thetaSize - 1.0);
    vec4 lo = textureLod(nTable, vec2(u, (k * thetaSize + row + 0.5) / size.y), 0.0);
    vec4 hi = textureLod(nTable, vec2(u, ((k + 1.0) * thetaSize + row + 0.5) / size.y), 0.0);
    return mix(lo, hi, s - k);
}

// Single scattering, sum_p M_p A_p N_p per channel (baker.api.hair_bsdf).
vec3 baker_hair_shading_single(sampler2D mTable, sampler2D nTable, BakerHairShading h, vec3 T, vec3 L, vec3 V,
                               vec3 sigmaA) {
    vec3 angles = baker_hair_shading_angles(T, L, V);
    vec4 m = baker_hair_shading_longitudinal(mTable, angles.x, angles.y, h.tilt);
    vec3 x = baker_hair_shading_absorption(sigmaA);
    vec3 result;
    for (int c = 0; c < 3; ++c) {
        result[c] = dot(m, baker_hair_shading_azimuthal(nTable, h.slices, angles.z, angles.y, x[c]));
    }
    return result;
}

// log I0(x), x >= 0 (Abramowitz & Stegun 9.8.1-2, relative error < 2e-7).
float baker_hair_shading_log_i0(float x) {
    if (x <= 3.75) {
        float t2 = x * x / 14.0625;
        return log(1.0 + t2 * (3.5156229 + t2 * (3.0899424 + t2 * (1.2067492 + t2 * (0.2659732 + t2 * (0.0360768
               + t2 * 0.0045813))))));
    }
    float r = 3.75 / x;
    return x - 0.5 * log(x) + log(0.39894228 + r * (0.01328592 + r * (0.00225319 + r * (-0.00157565 + r * (
               0.00916281 + r * (-0.02057706 + r * (0.02635537 + r * (-0.01647633 + r * 0.00392377))))))));
}

// d'Eon et al. 2011's longitudinal lobe of variance v (unit integral of M cos theta_i over theta_i), log domain.
float baker_hair_shading_lobe(float thetaI, float thetaO, float v) {
    float a = abs(cos(thetaI) * cos(thetaO)) / v;
    float b = sin(thetaI) * sin(thetaO) / v;
    float logSinh = 1.0 / v + log((1.0 - exp(-2.0 / v)) * 0.5);
    return exp(baker_hair_shading_log_i0(a) - b - log(2.0 * v) - logSinh);
}

// Zinke's per-fibre averages (a_f, a_b, alpha_b, beta_b) at |theta| and one channel's absorption x: one fetch.
vec4 baker_hair_shading_dual(sampler2D dualTable, float theta, float x) {
    vec2 size = vec2(textureSize(dualTable, 0));
    float u = (clamp(abs(theta) / (0.5 * BAKER_HAIR_SHADING_PI), 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    float v = (clamp(x, 0.0, 1.0) * (size.y - 1.0) + 0.5) / size.y;
    return textureLod(dualTable, vec2(u, v), 0.0);
}

// The fibre behind `fibresCrossed` fibres parallel to T (from a baked count or a deep opacity map; fractions fade
// the direct light): direct single scattering and the neighbours' backscatter where light arrives unscattered,
// plus the forward-scattered light T_f = a_f^n spread by n beta_f^2 about theta_i + n alpha_f over the forward half
// of azimuths, and its backscatter (baker.api.hair_shade, Zinke et al. 2008).
vec3 baker_hair_shading(sampler2D mTable, sampler2D nTable, sampler2D dualTable, BakerHairShading h, vec3 T,
                        vec3 L, vec3 V, float fibresCrossed, vec3 sigmaA) {
    const float PI = BAKER_HAIR_SHADING_PI;
    vec3 single = baker_hair_shading_single(mTable, nTable, h, T, L, V, sigmaA);
    vec3 angles = baker_hair_shading_angles(T, L, V);
    float thetaI = angles.x;
    float thetaO = angles.y;
    float phi = angles.z;
    float n = max(fibresCrossed, 0.0);
    float direct = clamp(1.0 - n, 0.0, 1.0);
    float crossed = max(n, 1.0);
    float spread = crossed * h.betaF * h.betaF;
    float thetaG = clamp(thetaI + crossed * h.alphaF, -0.5 * PI, 0.5 * PI);
    vec4 shift = vec4(-2.0 * h.tilt, h.tilt, 4.0 * h.tilt, 0.0);
    vec4 mG;
    for (int p = 0; p < 4; ++p) {
        mG[p] = baker_hair_shading_lobe(thetaG, clamp(thetaO + shift[p], -0.5 * PI, 0.5 * PI), h.variances[p] + spread);
    }
    float thetaD = 0.5 * (thetaO - thetaI);
    float backDirect = phi < 0.5 * PI ? 1.0 / PI : 0.0;
    float backSpread = (PI - phi) / (PI * PI);
    vec3 x = baker_hair_shading_absorption(sigmaA);
    vec3 result;
    for (int c = 0; c < 3; ++c) {
        float aF = baker_hair_shading_dual(dualTable, thetaI, x[c]).x;
        float scattered = (1.0 - direct) * pow(max(aF, 0.0), crossed);
        vec4 d = baker_hair_shading_dual(dualTable, thetaD, x[c]);
        float aF2 = min(d.x * d.x, 0.999);
        float one = 1.0 - aF2;
        float aB = d.y;
        float a1 = aB * aF2 / one;
        float a3 = aB * aB * aB * aF2 / (one * one * one);
        float aBack = a1 + a3;
        float shiftB = d.z * (1.0 - 2.0 * aB * aB / (one * one))
                     + h.alphaF * (2.0 * one * one + 4.0 * aF2 * aB * aB) / (one * one * one);
        float width1 = sqrt(2.0 * h.betaF * h.betaF + d.w * d.w);
        float width3 = sqrt(2.0 * h.betaF * h.betaF + 3.0 * d.w * d.w);
        float sigmaB = (1.0 + h.densityBack * aF2) * (a1 * width1 + a3 * width3) / max(aBack, 1e-12);
        float varB = max(sigmaB * sigmaB, 1e-4);  // no zero-width lobe where a fibre backscatters nothing
        float thetaBack = clamp(thetaO + shiftB, -0.5 * PI, 0.5 * PI);
        float sBack = aBack * baker_hair_shading_lobe(thetaI, thetaBack, varB) * backDirect;
        float sBackG = aBack * baker_hair_shading_lobe(thetaG, thetaBack, varB + spread) * backSpread;
        // N over the forward half of incoming azimuths: four taps at phi + (-3, -1, 1, 3) pi / 8
        vec4 nG = vec4(0.0);
        for (int k = 0; k < 4; ++k) {
            float tap = phi + (float(k) - 1.5) * (0.25 * PI) + PI;
            tap = abs(tap - 2.0 * PI * floor(tap / (2.0 * PI)) - PI);
            nG += baker_hair_shading_azimuthal(nTable, h.slices, tap, thetaO, x[c]);
        }
        float sG = dot(mG, 0.25 * nG);
        result[c] = direct * (single[c] + h.densityBack * sBack)
                  + scattered * h.densityForward * (sG + h.densityBack * sBackG);
    }
    return result;
}

#endif
