// baker_hair.wgsl: hair strands from BAKER_hair as view-facing ribbons, and three hair shading models (RTR4
// 14.7.1-14.7.2); the WGSL twin of baker_hair.glsl (same functions, same arguments, same meaning; see there for the
// data and schemas/BAKER_hair/README.md). No entry point, no bindings: paste it once (names are unique across the
// runtime modules). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against
// tests/gl/twins_hair.py.

const BAKER_HAIR_PI: f32 = 3.14159265358979;

// ------------------------------------------------------------------------------------------------ geometry
// Strand width at parameter t (0 root, 1 tip): linear taper, times the strand's width scale.
fn baker_hair_width(rootWidth: f32, tipWidth: f32, param: f32, widthScale: f32) -> f32 {
    return mix(rootWidth, tipWidth, param) * widthScale;
}

// World size of one pixel at distance viewDistance for a perspective camera (vertical fov, viewport height px).
fn baker_hair_pixel_size(viewDistance: f32, tanHalfFovY: f32, viewportHeight: f32) -> f32 {
    return 2.0 * viewDistance * tanHalfFovY / viewportHeight;
}

// Pixel coverage (TressFX): a strand thinner than a pixel is drawn one pixel wide, its opacity scaled by the
// fraction of the pixel it covers. Returns (drawn width, opacity scale).
fn baker_hair_coverage(width: f32, pixelSize: f32) -> vec2f {
    return vec2f(max(width, pixelSize), clamp(width / max(pixelSize, 1e-20), 0.0, 1.0));
}

// Unit side vector of a view-facing ribbon: perpendicular to the tangent and to the direction to the eye.
fn baker_hair_ribbon_side(position: vec3f, tangent: vec3f, eye: vec3f) -> vec3f {
    var s = cross(tangent, eye - position);
    var len = length(s);
    if (len < 1e-12) {  // looking straight along the strand: any perpendicular will do
        s = cross(tangent, select(vec3f(1.0, 0.0, 0.0), vec3f(0.0, 1.0, 0.0), abs(tangent.y) < 0.9));
        len = length(s);
    }
    return s / len;
}

// Ribbon vertex: the line vertex moved half the width to side 0 (-) or 1 (+).
fn baker_hair_ribbon_position(position: vec3f, tangent: vec3f, eye: vec3f, width: f32, side: f32) -> vec3f {
    return position + baker_hair_ribbon_side(position, tangent, eye) * (width * (side - 0.5));
}

// ------------------------------------------------------------------------------------------------ guides, LODs
// A child from its 3 guides (guides.interpolation "offset"): childRoot + sum_i w_i (guide_i(t) - guideRoot_i).
fn baker_hair_offset_child(childRoot: vec3f, weights: vec3f, guide0: vec3f, guideRoot0: vec3f, guide1: vec3f,
                           guideRoot1: vec3f, guide2: vec3f, guideRoot2: vec3f) -> vec3f {
    return childRoot + weights.x * (guide0 - guideRoot0) + weights.y * (guide1 - guideRoot1)
         + weights.z * (guide2 - guideRoot2);
}

// LODs by prefix (lods, order "lodPrefix"): level k draws this many first entries of ribbonIndices...
fn baker_hair_lod_index_count(strandCount: i32, verticesPerStrand: i32) -> i32 {
    return strandCount * 6 * (verticesPerStrand - 1);
}

// ... with every width times lods[k].widthScale.
fn baker_hair_lod_width(width: f32, lodWidthScale: f32) -> f32 {
    return width * lodWidthScale;
}

// ------------------------------------------------------------------------------------------------ shading
// Kajiya & Kay 1989: diffuse sin(T, L); specular (sin(T,L) sin(T,V) - cos(T,L) cos(T,V))^p. T, L, V unit.
fn baker_hair_kajiya_kay(T: vec3f, L: vec3f, V: vec3f, diffuseColor: vec3f, specularColor: vec3f,
                         exponent: f32) -> vec3f {
    let tl = dot(T, L);
    let tv = dot(T, V);
    let sinTL = sqrt(max(0.0, 1.0 - tl * tl));
    let sinTV = sqrt(max(0.0, 1.0 - tv * tv));
    let spec = pow(max(0.0, sinTL * sinTV - tl * tv), exponent);
    return diffuseColor * sinTL + specularColor * spec;
}

// Scheuermann 2004: shift the tangent along the normal to move a highlight towards the root or the tip.
fn baker_hair_shift_tangent(T: vec3f, N: vec3f, shift: f32) -> vec3f {
    return normalize(T + shift * N);
}

// Scheuermann's strand specular with the half vector: smoothstep(-1, 0, T.H) sin(T, H)^p.
fn baker_hair_strand_specular(T: vec3f, V: vec3f, L: vec3f, exponent: f32) -> f32 {
    let H = normalize(L + V);
    let th = dot(T, H);
    let sinTH = sqrt(max(0.0, 1.0 - th * th));
    return smoothstep(-1.0, 0.0, th) * pow(sinTH, exponent);
}

// Scheuermann 2004 (ATI, "Hair Rendering and Shading"): wrapped diffuse + two shifted specular lobes, the second
// modulated by a noise mask. Returns the radiance for a unit white light.
fn baker_hair_scheuermann(T: vec3f, N: vec3f, V: vec3f, L: vec3f, baseColor: vec3f, specularColor1: vec3f,
                          specularColor2: vec3f, shift1: f32, shift2: f32, exponent1: f32, exponent2: f32,
                          mask: f32) -> vec3f {
    let t1 = baker_hair_shift_tangent(T, N, shift1);
    let t2 = baker_hair_shift_tangent(T, N, shift2);
    let diffuse = clamp(mix(0.25, 1.0, dot(N, L)), 0.0, 1.0);
    let spec = specularColor1 * baker_hair_strand_specular(t1, V, L, exponent1)
             + specularColor2 * (mask * baker_hair_strand_specular(t2, V, L, exponent2));
    return baseColor * diffuse + spec * diffuse;
}

fn baker_hair_gaussian(beta: f32, x: f32) -> f32 {
    return exp(-0.5 * x * x / (beta * beta)) / (sqrt(2.0 * BAKER_HAIR_PI) * beta);
}

fn baker_hair_fresnel(cosTheta: f32) -> f32 {
    const f0 = 0.0465;  // hair cortex, eta = 1.55
    let m = 1.0 - clamp(cosTheta, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// Marschner et al. 2003 R / TT / TRT lobes in the real-time form of Karis 2016 ("Physically Based Hair Shading in
// Unreal"): longitudinal Gaussians with shifts -2a, a, 4a and widths r^2, r^2 / 2, 2 r^2; azimuthal terms
// cos(phi / 2) / 4, exp(-3.65 cos phi - 3.98), exp(17 cos phi - 16.78); Fresnel and absorption
// baseColor^(k / cos thetaD). No multiple scattering. Returns the BSDF times cosine for a unit light.
fn baker_hair_marschner(T: vec3f, V: vec3f, L: vec3f, baseColor: vec3f, roughness: f32, shift: f32) -> vec3f {
    let sinL = clamp(dot(T, L), -1.0, 1.0);
    let sinV = clamp(dot(T, V), -1.0, 1.0);
    let cosThetaD = cos(0.5 * abs(asin(sinV) - asin(sinL)));
    let lp = L - sinL * T;
    let vp = V - sinV * T;
    let cosPhi = dot(lp, vp) * inverseSqrt(dot(lp, lp) * dot(vp, vp) + 1e-4);
    let cosHalfPhi = sqrt(clamp(0.5 + 0.5 * cosPhi, 0.0, 1.0));
    let beta = max(roughness * roughness, 1e-3);
    let x = sinL + sinV;

    let mR = baker_hair_gaussian(beta, x + 2.0 * shift);
    let nR = 0.25 * cosHalfPhi;
    let aR = baker_hair_fresnel(sqrt(clamp(0.5 + 0.5 * dot(L, V), 0.0, 1.0)));

    let mTT = baker_hair_gaussian(0.5 * beta, x - shift);
    let nTT = exp(-3.65 * cosPhi - 3.98);
    let fT = baker_hair_fresnel(cosThetaD * 0.5);
    let absorbTT = pow(baseColor, vec3f(0.5 / max(cosThetaD, 0.05)));

    let mTRT = baker_hair_gaussian(2.0 * beta, x - 4.0 * shift);
    let nTRT = exp(17.0 * cosPhi - 16.78);
    let absorbTRT = pow(baseColor, vec3f(0.8 / max(cosThetaD, 0.05)));

    return vec3f(mR * nR * aR) + (mTT * nTT * (1.0 - fT) * (1.0 - fT)) * absorbTT
         + (mTRT * nTRT * (1.0 - fT) * (1.0 - fT) * fT) * absorbTRT * absorbTRT;
}
