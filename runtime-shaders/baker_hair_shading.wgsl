// baker_hair_shading.wgsl: hair shaded like hair (RTR4 14.7.2); the WGSL twin of baker_hair_shading.glsl (same
// functions, same arguments, same meaning; see there for the tables' layout and hair_lut.json). Chiang et al.
// 2016's fibre model (pbrt's HairBxDF) from its baked tables and Zinke et al. 2008's dual scattering.
//
// WGSL conventions (runtime-shaders/README.md): a GLSL sampler2D argument is a texture_2d<f32> and its sampler
// (LINEAR, CLAMP_TO_EDGE, no mips; the tables are half float, so no float32-filterable feature is needed);
// textureLod is textureSampleLevel (any stage, any control flow), textureSize is textureDimensions. No entry
// point, no bindings: paste it once. tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against
// tests/gl/twins_hair_shading.py (baker.api.hair_shade / hair_bsdf).

const BAKER_HAIR_SHADING_PI: f32 = 3.14159265358979;

// The runtime half of BAKER_hair_shading (hair_lut.json), field for field.
struct BakerHairShading {
    variances: vec4f,      // parameters.longitudinalVariance: d'Eon's v for R, TT, TRT, residual
    tilt: f32,             // cuticle tilt alpha, radians (R turns by -2 alpha, TT by alpha, TRT by 4 alpha)
    slices: f32,           // azimuthal.slices: absorption slices of nTable
    alphaF: f32,           // dualScattering.alphaF: shift of one forward scattering, radians
    betaF: f32,            // dualScattering.betaF: its width, radians
    densityForward: f32,   // Zinke's d_f (1 for a count of the fibres crossed; Zinke used 0.7 with opacity maps)
    densityBack: f32,      // Zinke's d_b (likewise)
}

// d'Eon et al. 2011's absorption per fibre radius of eumelanin and pheomelanin concentrations (pbrt's).
fn baker_hair_shading_melanin(eumelanin: f32, pheomelanin: f32) -> vec3f {
    return eumelanin * vec3f(0.419, 0.697, 1.37) + pheomelanin * vec3f(0.187, 0.4, 1.05);
}

// The tables' absorption axis: x = 1 - exp(-sigma_a / 2) per channel (transmittance through one diameter).
fn baker_hair_shading_absorption(sigmaA: vec3f) -> vec3f {
    return 1.0 - exp(-0.5 * sigmaA);
}

// (theta_i, theta_o, phi) of light L and view V about tangent T (phi in [0, pi]; 0 when a projection vanishes).
fn baker_hair_shading_angles(T: vec3f, L: vec3f, V: vec3f) -> vec3f {
    let t = normalize(T);
    let sinI = clamp(dot(L, t), -1.0, 1.0);
    let sinO = clamp(dot(V, t), -1.0, 1.0);
    let pl = L - sinI * t;
    let pv = V - sinO * t;
    let norm = length(pl) * length(pv);
    var cosPhi = 1.0;
    if (norm > 1e-12) {
        cosPhi = dot(pl, pv) / norm;
    }
    return vec3f(asin(sinI), asin(sinO), acos(clamp(cosPhi, -1.0, 1.0)));
}

// M_R, M_TT, M_TRT at theta_o tilted per lobe, and the residual's M (the TRT variance, untilted): four fetches.
fn baker_hair_shading_longitudinal(mTable: texture_2d<f32>, mTableSampler: sampler, thetaI: f32, thetaO: f32,
                                   tilt: f32) -> vec4f {
    let size = vec2f(textureDimensions(mTable, 0));
    let u = (clamp(thetaI / BAKER_HAIR_SHADING_PI + 0.5, 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    let shift = vec4f(-2.0 * tilt, tilt, 4.0 * tilt, 0.0);
    var m = vec4f(0.0);
    for (var p = 0; p < 4; p++) {
        // asin(sin(theta_o + shift)): the tilted angle, reflected about +-pi/2 (exact, where asin(sin) is not)
        var thetaP = thetaO + shift[p];
        if (thetaP > 0.5 * BAKER_HAIR_SHADING_PI) {
            thetaP = BAKER_HAIR_SHADING_PI - thetaP;
        } else if (thetaP < -0.5 * BAKER_HAIR_SHADING_PI) {
            thetaP = -BAKER_HAIR_SHADING_PI - thetaP;
        }
        let v = (clamp(thetaP / BAKER_HAIR_SHADING_PI + 0.5, 0.0, 1.0) * (size.y - 1.0) + 0.5) / size.y;
        m[p] = textureSampleLevel(mTable, mTableSampler, vec2f(u, v), 0.0)[min(p, 2)];
    }
    return m;
}

// The h-averaged A_p N_p (R, TT, TRT, residual / 2 pi) at |phi|, |theta_o| and one channel's absorption x: two
// fetches, linear between the two nearest absorption slices.
fn baker_hair_shading_azimuthal(nTable: texture_2d<f32>, nTableSampler: sampler, slices: f32, phi: f32,
                                thetaO: f32, x: f32) -> vec4f {
    let size = vec2f(textureDimensions(nTable, 0));
    let thetaSize = size.y / slices;
    let s = clamp(x, 0.0, 1.0) * (slices - 1.0);
    let k = min(floor(s), slices - 2.0);
    let u = (clamp(abs(phi) / BAKER_HAIR_SHADING_PI, 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    let row = clamp(abs(thetaO) / (0.5 * BAKER_HAIR_SHADING_PI), 0.0, 1.0) * (thetaSize - 1.0);
    let lo = textureSampleLevel(nTable, nTableSampler, vec2f(u, (k * thetaSize + row + 0.5) / size.y), 0.0);
    let hi = textureSampleLevel(nTable, nTableSampler, vec2f(u, ((k + 1.0) * thetaSize + row + 0.5) / size.y), 0.0);
    return mix(lo, hi, s - k);
}

// Single scattering, sum_p M_p A_p N_p per channel (baker.api.hair_bsdf).
fn baker_hair_shading_single(mTable: texture_2d<f32>, mTableSampler: sampler, nTable: texture_2d<f32>,
                             nTableSampler: sampler, h: BakerHairShading, T: vec3f, L: vec3f, V: vec3f,
                             sigmaA: vec3f) -> vec3f {
    let angles = baker_hair_shading_angles(T, L, V);
    let m = baker_hair_shading_longitudinal(mTable, mTableSampler, angles.x, angles.y, h.tilt);
    let x = baker_hair_shading_absorption(sigmaA);
    var result = vec3f(0.0);
    for (var c = 0; c < 3; c++) {
        result[c] = dot(m, baker_hair_shading_azimuthal(nTable, nTableSampler, h.slices, angles.z, angles.y, x[c]));
    }
    return result;
}

// log I0(x), x >= 0 (Abramowitz & Stegun 9.8.1-2, relative error < 2e-7).
fn baker_hair_shading_log_i0(x: f32) -> f32 {
    if (x <= 3.75) {
        let t2 = x * x / 14.0625;
        return log(1.0 + t2 * (3.5156229 + t2 * (3.0899424 + t2 * (1.2067492 + t2 * (0.2659732 + t2 * (0.0360768
               + t2 * 0.0045813))))));
    }
    let r = 3.75 / x;
    return x - 0.5 * log(x) + log(0.39894228 + r * (0.01328592 + r * (0.00225319 + r * (-0.00157565 + r * (
               0.00916281 + r * (-0.02057706 + r * (0.02635537 + r * (-0.01647633 + r * 0.00392377))))))));
}

// d'Eon et al. 2011's longitudinal lobe of variance v (unit integral of M cos theta_i over theta_i), log domain.
fn baker_hair_shading_lobe(thetaI: f32, thetaO: f32, v: f32) -> f32 {
    let a = abs(cos(thetaI) * cos(thetaO)) / v;
    let b = sin(thetaI) * sin(thetaO) / v;
    let logSinh = 1.0 / v + log((1.0 - exp(-2.0 / v)) * 0.5);
    return exp(baker_hair_shading_log_i0(a) - b - log(2.0 * v) - logSinh);
}

// Zinke's per-fibre averages (a_f, a_b, alpha_b, beta_b) at |theta| and one channel's absorption x: one fetch.
fn baker_hair_shading_dual(dualTable: texture_2d<f32>, dualTableSampler: sampler, theta: f32, x: f32) -> vec4f {
    let size = vec2f(textureDimensions(dualTable, 0));
    let u = (clamp(abs(theta) / (0.5 * BAKER_HAIR_SHADING_PI), 0.0, 1.0) * (size.x - 1.0) + 0.5) / size.x;
    let v = (clamp(x, 0.0, 1.0) * (size.y - 1.0) + 0.5) / size.y;
    return textureSampleLevel(dualTable, dualTableSampler, vec2f(u, v), 0.0);
}

// The fibre behind `fibresCrossed` fibres parallel to T (from a baked count or a deep opacity map; fractions fade
// the direct light): direct single scattering and the neighbours' backscatter where light arrives unscattered,
// plus the forward-scattered light T_f = a_f^n spread by n beta_f^2 about theta_i + n alpha_f over the forward half
// of azimuths, and its backscatter (baker.api.hair_shade, Zinke et al. 2008).
fn baker_hair_shading(mTable: texture_2d<f32>, mTableSampler: sampler, nTable: texture_2d<f32>,
                      nTableSampler: sampler, dualTable: texture_2d<f32>, dualTableSampler: sampler,
                      h: BakerHairShading, T: vec3f, L: vec3f, V: vec3f, fibresCrossed: f32, sigmaA: vec3f) -> vec3f {
    let PI = BAKER_HAIR_SHADING_PI;
    let single = baker_hair_shading_single(mTable, mTableSampler, nTable, nTableSampler, h, T, L, V, sigmaA);
    let angles = baker_hair_shading_angles(T, L, V);
    let thetaI = angles.x;
    let thetaO = angles.y;
    let phi = angles.z;
    let n = max(fibresCrossed, 0.0);
    let direct = clamp(1.0 - n, 0.0, 1.0);
    let crossed = max(n, 1.0);
    let spread = crossed * h.betaF * h.betaF;
    let thetaG = clamp(thetaI + crossed * h.alphaF, -0.5 * PI, 0.5 * PI);
    let shift = vec4f(-2.0 * h.tilt, h.tilt, 4.0 * h.tilt, 0.0);
    var mG = vec4f(0.0);
    for (var p = 0; p < 4; p++) {
        mG[p] = baker_hair_shading_lobe(thetaG, clamp(thetaO + shift[p], -0.5 * PI, 0.5 * PI), h.variances[p] + spread);
    }
    let thetaD = 0.5 * (thetaO - thetaI);
    let backDirect = select(0.0, 1.0 / PI, phi < 0.5 * PI);
    let backSpread = (PI - phi) / (PI * PI);
    let x = baker_hair_shading_absorption(sigmaA);
    var result = vec3f(0.0);
    for (var c = 0; c < 3; c++) {
        let aF = baker_hair_shading_dual(dualTable, dualTableSampler, thetaI, x[c]).x;
        let scattered = (1.0 - direct) * pow(max(aF, 0.0), crossed);
        let d = baker_hair_shading_dual(dualTable, dualTableSampler, thetaD, x[c]);
        let aF2 = min(d.x * d.x, 0.999);
        let one = 1.0 - aF2;
        let aB = d.y;
        let a1 = aB * aF2 / one;
        let a3 = aB * aB * aB * aF2 / (one * one * one);
        let aBack = a1 + a3;
        let shiftB = d.z * (1.0 - 2.0 * aB * aB / (one * one))
                   + h.alphaF * (2.0 * one * one + 4.0 * aF2 * aB * aB) / (one * one * one);
        let width1 = sqrt(2.0 * h.betaF * h.betaF + d.w * d.w);
        let width3 = sqrt(2.0 * h.betaF * h.betaF + 3.0 * d.w * d.w);
        let sigmaB = (1.0 + h.densityBack * aF2) * (a1 * width1 + a3 * width3) / max(aBack, 1e-12);
        let varB = max(sigmaB * sigmaB, 1e-4);  // no zero-width lobe where a fibre backscatters nothing
        let thetaBack = clamp(thetaO + shiftB, -0.5 * PI, 0.5 * PI);
        let sBack = aBack * baker_hair_shading_lobe(thetaI, thetaBack, varB) * backDirect;
        let sBackG = aBack * baker_hair_shading_lobe(thetaG, thetaBack, varB + spread) * backSpread;
        // N over the forward half of incoming azimuths: four taps at phi + (-3, -1, 1, 3) pi / 8
        var nG = vec4f(0.0);
        for (var k = 0; k < 4; k++) {
            var tap = phi + (f32(k) - 1.5) * (0.25 * PI) + PI;
            tap = abs(tap - 2.0 * PI * floor(tap / (2.0 * PI)) - PI);
            nG += baker_hair_shading_azimuthal(nTable, nTableSampler, h.slices, tap, thetaO, x[c]);
        }
        let sG = dot(mG, 0.25 * nG);
        result[c] = direct * (single[c] + h.densityBack * sBack)
                  + scattered * h.densityForward * (sG + h.densityBack * sBackG);
    }
    return result;
}
