// baker_hair.glsl: hair strands from BAKER_hair (glTF) as view-facing ribbons, and three hair shading models.
// RTR4 14.7.1-14.7.2. No #version, no precision, no uniforms: the includer owns the header and the bindings.
//
// Data (BAKER_hair primitive): POSITION, _STRAND_TANGENT (unit, root -> tip), _STRAND_PARAM (0 root .. 1 tip),
// rootWidth / tipWidth (mesh units), widthScale[strand], ribbonIndices (6 per segment over 2 x vertexCount ribbon
// vertices: ribbon vertex r extrudes line vertex r / 2 to side r % 2).
#ifndef BAKER_HAIR_GLSL
#define BAKER_HAIR_GLSL

const float BAKER_HAIR_PI = 3.14159265358979;

// ------------------------------------------------------------------------------------------------ geometry
// Strand width at parameter t (0 root, 1 tip): linear taper, times the strand's width scale.
float baker_hair_width(float rootWidth, float tipWidth, float param, float widthScale) {
    return mix(rootWidth, tipWidth, param) * widthScale;
}

// World size of one pixel at distance viewDistance for a perspective camera (vertical fov, viewport height px).
float baker_hair_pixel_size(float viewDistance, float tanHalfFovY, float viewportHeight) {
    return 2.0 * viewDistance * tanHalfFovY / viewportHeight;
}

// Pixel coverage (TressFX): a strand thinner than a pixel is drawn one pixel wide and its opacity scaled by the
// fraction of the pixel it really covers. Returns (drawn width, opacity scale).
vec2 baker_hair_coverage(float width, float pixelSize) {
    return vec2(max(width, pixelSize), clamp(width / max(pixelSize, 1e-20), 0.0, 1.0));
}

// Unit side vector of a view-facing ribbon: perpendicular to the tangent and to the direction to the eye (the
// cylinder constraint: the ribbon turns about the strand, never away from it).
vec3 baker_hair_ribbon_side(vec3 position, vec3 tangent, vec3 eye) {
    vec3 s = cross(tangent, eye - position);
    float len = length(s);
    if (len < 1e-12) {  // looking straight along the strand: any perpendicular will do
        s = cross(tangent, abs(tangent.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0));
        len = length(s);
    }
    return s / len;
}

// Ribbon vertex: the line vertex moved half the width to side 0 (-) or 1 (+).
vec3 baker_hair_ribbon_position(vec3 position, vec3 tangent, vec3 eye, float width, float side) {
    return position + baker_hair_ribbon_side(position, tangent, eye) * (width * (side - 0.5));
}

// ------------------------------------------------------------------------------------------------ guides, LODs
// A child from its 3 guides (BAKER_hair guides.interpolation "offset", written by `baker guides`):
// child(t) = childRoot + sum_i w_i (guide_i(t) - guideRoot_i), t the vertex index along the strand. Feed it the
// animated guides to move the children with the simulation; the rest pose gives back the stored child.
vec3 baker_hair_offset_child(vec3 childRoot, vec3 weights, vec3 guide0, vec3 guideRoot0, vec3 guide1,
                             vec3 guideRoot1, vec3 guide2, vec3 guideRoot2) {
    return childRoot + weights.x * (guide0 - guideRoot0) + weights.y * (guide1 - guideRoot1)
         + weights.z * (guide2 - guideRoot2);
}

// LODs by prefix (BAKER_hair lods, order "lodPrefix"): level k draws the first lods[k].strandCount strands, i.e.
// the first baker_hair_lod_index_count(lods[k].strandCount, verticesPerStrand) entries of ribbonIndices...
int baker_hair_lod_index_count(int strandCount, int verticesPerStrand) {
    return strandCount * 6 * (verticesPerStrand - 1);
}

// ... with every width times lods[k].widthScale, so the fewer strands cover about the same area.
float baker_hair_lod_width(float width, float lodWidthScale) {
    return width * lodWidthScale;
}

// ------------------------------------------------------------------------------------------------ shading
// Kajiya & Kay 1989: diffuse sin(T, L); specular cone around the mirror direction about the fiber:
// (sin(T,L) sin(T,V) - cos(T,L) cos(T,V))^p. T, L, V unit; L and V point away from the fiber.
vec3 baker_hair_kajiya_kay(vec3 T, vec3 L, vec3 V, vec3 diffuseColor, vec3 specularColor, float exponent) {
    float tl = dot(T, L);
    float tv = dot(T, V);
    float sinTL = sqrt(max(0.0, 1.0 - tl * tl));
    float sinTV = sqrt(max(0.0, 1.0 - tv * tv));
    float spec = pow(max(0.0, sinTL * sinTV - tl * tv), exponent);
    return diffuseColor * sinTL + specularColor * spec;
}

// Scheuermann 2004: shift the tangent along the normal to move a highlight towards the root or the tip.
vec3 baker_hair_shift_tangent(vec3 T, vec3 N, float shift) {
    return normalize(T + shift * N);
}

// Scheuermann's strand specular with the half vector: smoothstep(-1, 0, T.H) sin(T, H)^p.
float baker_hair_strand_specular(vec3 T, vec3 V, vec3 L, float exponent) {
    vec3 H = normalize(L + V);
    float th = dot(T, H);
    float sinTH = sqrt(max(0.0, 1.0 - th * th));
    return smoothstep(-1.0, 0.0, th) * pow(sinTH, exponent);
}

// Scheuermann 2004 (ATI, "Hair Rendering and Shading"): wrapped diffuse + two shifted specular lobes, the second
// (coloured, TRT-like) lobe modulated by a noise mask. Returns the radiance for a unit white light.
vec3 baker_hair_scheuermann(vec3 T, vec3 N, vec3 V, vec3 L, vec3 baseColor, vec3 specularColor1,
                            vec3 specularColor2, float shift1, float shift2, float exponent1, float exponent2,
                            float mask) {
    vec3 t1 = baker_hair_shift_tangent(T, N, shift1);
    vec3 t2 = baker_hair_shift_tangent(T, N, shift2);
    float diffuse = clamp(mix(0.25, 1.0, dot(N, L)), 0.0, 1.0);
    vec3 spec = specularColor1 * baker_hair_strand_specular(t1, V, L, exponent1)
              + specularColor2 * (mask * baker_hair_strand_specular(t2, V, L, exponent2));
    return baseColor * diffuse + spec * diffuse;
}

float baker_hair_gaussian(float beta, float x) {
    return exp(-0.5 * x * x / (beta * beta)) / (sqrt(2.0 * BAKER_HAIR_PI) * beta);
}

float baker_hair_fresnel(float cosTheta) {
    const float f0 = 0.0465;  // hair cortex, eta = 1.55
    float m = 1.0 - clamp(cosTheta, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// Marschner et al. 2003 R / TT / TRT lobes in the real-time form of Karis 2016 ("Physically Based Hair Shading in
// Unreal"): longitudinal Gaussians M_p(sin thetaL + sin thetaV - alpha_p) with shifts alpha_R = -2 a, alpha_TT = a,
// alpha_TRT = 4 a and widths beta_R = r^2, beta_TT = r^2 / 2, beta_TRT = 2 r^2; fitted azimuthal terms
// N_R = cos(phi / 2) / 4, N_TT = exp(-3.65 cos phi - 3.98), N_TRT = exp(17 cos phi - 16.78); Fresnel and
// absorption baseColor^(k / cos thetaD). No multiple scattering. Returns the BSDF times cosine for a unit light.
vec3 baker_hair_marschner(vec3 T, vec3 V, vec3 L, vec3 baseColor, float roughness, float shift) {
    float sinL = clamp(dot(T, L), -1.0, 1.0);
    float sinV = clamp(dot(T, V), -1.0, 1.0);
    float cosThetaD = cos(0.5 * abs(asin(sinV) - asin(sinL)));
    vec3 lp = L - sinL * T;
    vec3 vp = V - sinV * T;
    float cosPhi = dot(lp, vp) * inversesqrt(dot(lp, lp) * dot(vp, vp) + 1e-4);
    float cosHalfPhi = sqrt(clamp(0.5 + 0.5 * cosPhi, 0.0, 1.0));
    float beta = max(roughness * roughness, 1e-3);
    float x = sinL + sinV;

    float mR = baker_hair_gaussian(beta, x + 2.0 * shift);
    float nR = 0.25 * cosHalfPhi;
    float aR = baker_hair_fresnel(sqrt(clamp(0.5 + 0.5 * dot(L, V), 0.0, 1.0)));

    float mTT = baker_hair_gaussian(0.5 * beta, x - shift);
    float nTT = exp(-3.65 * cosPhi - 3.98);
    float fT = baker_hair_fresnel(cosThetaD * 0.5);
    vec3 absorbTT = pow(baseColor, vec3(0.5 / max(cosThetaD, 0.05)));

    float mTRT = baker_hair_gaussian(2.0 * beta, x - 4.0 * shift);
    float nTRT = exp(17.0 * cosPhi - 16.78);
    vec3 absorbTRT = pow(baseColor, vec3(0.8 / max(cosThetaD, 0.05)));

    return vec3(mR * nR * aR) + (mTT * nTT * (1.0 - fT) * (1.0 - fT)) * absorbTT
         + (mTRT * nTRT * (1.0 - fT) * (1.0 - fT) * fT) * absorbTRT * absorbTRT;
}

#endif  // BAKER_HAIR_GLSL
