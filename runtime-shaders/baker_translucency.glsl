// baker_translucency.glsl: cheap back-lit translucency from a baked local thickness.
//
// Implements the subsurface term of Barre-Brisebois & Bouchard, "Approximating Translucency for a Fast, Cheap and
// Convincing Subsurface Scattering Look" (GDC 2011), in the form of RTR4 (Real-Time Rendering, 4th ed.) section
// 14.6.6, eq. 14.30:
//
//     t_ss * c_ss * ((v . -l)^+)^p            (times the light's color, intensity and distance attenuation)
//
// plus the GDC 2011 variant that bends the light vector by the normal and adds a constant term:
//
//     lt   = normalize(l + n * distortion)
//     back = pow(clamp(v . -lt, 0, 1), power) * scale
//     c_ss * (back + ambient) * t_ss
//
// l is the unit vector from the surface to the light, v from the surface to the eye, n the unit outward normal.
// Unlike the paper's 0-1 "local thickness" texture, baker stores the thickness in mesh units (the mean chord
// length to the far side, seen from inside) and the runtime turns it into the transmittance t_ss with Beer-Lambert:
//
//     t_ss = exp(-thickness / attenuationDistance)
//
// Data written by baker (schemas/BAKER_thickness/README.md):
//   vertex attribute  _THICKNESS                               FLOAT VEC3, x in mesh units (bind as `in float _THICKNESS;`: GL reads x)
//   texture           KHR_materials_volume.thicknessTexture    GREEN channel; thickness = texel.g * thicknessFactor
//   uniform           KHR_materials_volume.thicknessFactor     float, mesh units
//   material params   BAKER_thickness.{attenuationDistance, distortion, power, scale, ambient, subsurfaceColor}
//                     -> the fields of struct BakerThickness below, same names
//
// How to include: this file has no #version line and no precision statement, and declares no uniforms, inputs or
// outputs; it only defines a struct and pure functions. Prepend your own header and paste (or #include through your
// engine's preprocessor) the file after it:
//
//     #version 300 es                        |   #version 330 core
//     precision highp float;                 |
//     <baker_translucency.glsl>              |   <baker_translucency.glsl>
//
// Compiles as GLSL ES 3.00 (WebGL2) and GLSL 3.30 core. Every function has a numpy twin in tests/gl/twins.py, and
// tests/gl/test_translucency.py renders it headlessly and checks the pixels against the twin.
//
// Every function returns the translucent contribution of ONE light before its radiance: the caller multiplies by
// the light color * intensity * distance attenuation and adds it to the regular surface lighting. `power` must be > 0.

#ifndef BAKER_TRANSLUCENCY_GLSL
#define BAKER_TRANSLUCENCY_GLSL

// The runtime half of the BAKER_thickness material extension, field for field (bake-only fields such as rays,
// distribution, spreadAngle, maxDistance, bias and meanThickness are not needed at runtime).
struct BakerThickness {
    float attenuationDistance;  // mesh units; t_ss = exp(-thickness / attenuationDistance)
    float distortion;           // GDC 2011: how far the normal bends the light vector (0 = eq. 14.30's l)
    float power;                // exponent p of (v . -l)^p, a phase-function approximation; > 0
    float scale;                // GDC 2011: scale of the back-lit term
    float ambient;              // GDC 2011: constant back-lit term, seen from every direction
    vec3 subsurfaceColor;       // c_ss, the subsurface albedo, linear RGB
};

// Thickness in mesh units from a KHR_materials_volume.thicknessTexture texel (the green channel, glTF convention).
float baker_thickness_from_texture(vec4 texel, float thicknessFactor) {
    return texel.g * thicknessFactor;
}

// Beer-Lambert transmittance through `thickness` mesh units: 1 at zero thickness, 1/e at attenuationDistance.
float baker_thickness_transmittance(float thickness, float attenuationDistance) {
    return exp(-max(thickness, 0.0) / attenuationDistance);
}

// RTR4 eq. 14.30: tss * subsurfaceColor * ((V . -L)^+)^power. V, L unit vectors from the surface to eye and light.
vec3 baker_translucency_rtr(vec3 V, vec3 L, float tss, vec3 subsurfaceColor, float power) {
    float forward = max(dot(V, -L), 0.0);
    return tss * subsurfaceColor * pow(forward, power);
}

// GDC 2011 variant: the light vector bent by the normal, then scaled, plus an ambient term. N, V, L unit vectors.
vec3 baker_translucency_gdc(vec3 N, vec3 V, vec3 L, float tss, vec3 subsurfaceColor, float distortion, float power,
                            float scale, float ambient) {
    vec3 bent = L + N * distortion;
    // normalize without a NaN when L + N * distortion vanishes (distortion = 1 and N = -L): the back term is then 0
    vec3 lt = bent * inversesqrt(max(dot(bent, bent), 1e-12));
    float back = pow(clamp(dot(V, -lt), 0.0, 1.0), power) * scale;
    return subsurfaceColor * (back + ambient) * tss;
}

// Convenience: the GDC variant with its parameters taken from a BakerThickness and the thickness in mesh units.
vec3 baker_translucency(BakerThickness params, vec3 N, vec3 V, vec3 L, float thickness) {
    float tss = baker_thickness_transmittance(thickness, params.attenuationDistance);
    return baker_translucency_gdc(N, V, L, tss, params.subsurfaceColor, params.distortion, params.power,
                                  params.scale, params.ambient);
}

#endif // BAKER_TRANSLUCENCY_GLSL
