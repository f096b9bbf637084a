// baker_translucency.wgsl: cheap back-lit translucency from a baked local thickness; the WGSL twin of
// baker_translucency.glsl (same functions, same arguments, same meaning; the data and the formulas are described
// there and in schemas/BAKER_thickness/README.md).
//
// Barre-Brisebois & Bouchard, "Approximating Translucency for a Fast, Cheap and Convincing Subsurface Scattering
// Look" (GDC 2011), in the form of RTR4 (Real-Time Rendering, 4th ed.) 14.6.6, eq. 14.30:
//     t_ss * c_ss * ((v . -l)^+)^p,   t_ss = exp(-thickness / attenuationDistance) (Beer-Lambert)
// and the GDC variant: lt = normalize(l + n * distortion), c_ss * (pow(clamp(v . -lt, 0, 1), p) * scale + ambient) * t_ss.
//
// How to include: no entry point, no bindings, no enable directive: only a struct and functions with explicit
// inputs. Paste it once into your module (every name is prefixed baker_/Baker and unique across the runtime
// modules, so any of them concatenate). tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks every
// function against the numpy twins of tests/gl/twins_translucency.py.

// The runtime half of the BAKER_thickness material extension, field for field.
struct BakerThickness {
    attenuationDistance: f32,  // mesh units; t_ss = exp(-thickness / attenuationDistance)
    distortion: f32,           // GDC 2011: how far the normal bends the light vector (0 = eq. 14.30's l)
    power: f32,                // exponent p of (v . -l)^p; > 0
    scale: f32,                // GDC 2011: scale of the back-lit term
    ambient: f32,              // GDC 2011: constant back-lit term
    subsurfaceColor: vec3f,    // c_ss, linear RGB
}

// Thickness in mesh units from a KHR_materials_volume.thicknessTexture texel (green channel).
fn baker_thickness_from_texture(texel: vec4f, thicknessFactor: f32) -> f32 {
    return texel.g * thicknessFactor;
}

// Beer-Lambert transmittance through `thickness` mesh units: 1 at zero thickness, 1/e at attenuationDistance.
fn baker_thickness_transmittance(thickness: f32, attenuationDistance: f32) -> f32 {
    return exp(-max(thickness, 0.0) / attenuationDistance);
}

// RTR4 eq. 14.30: tss * subsurfaceColor * ((V . -L)^+)^power. V, L unit vectors from the surface to eye and light.
fn baker_translucency_rtr(V: vec3f, L: vec3f, tss: f32, subsurfaceColor: vec3f, power: f32) -> vec3f {
    let forward = max(dot(V, -L), 0.0);
    return tss * subsurfaceColor * pow(forward, power);
}

// GDC 2011 variant: the light vector bent by the normal, then scaled, plus an ambient term. N, V, L unit vectors.
fn baker_translucency_gdc(N: vec3f, V: vec3f, L: vec3f, tss: f32, subsurfaceColor: vec3f, distortion: f32,
                          power: f32, scale: f32, ambient: f32) -> vec3f {
    let bent = L + N * distortion;
    // normalize without a NaN when L + N * distortion vanishes (distortion = 1, N = -L): the back term is then 0
    let lt = bent * inverseSqrt(max(dot(bent, bent), 1e-12));
    let back = pow(clamp(dot(V, -lt), 0.0, 1.0), power) * scale;
    return subsurfaceColor * (back + ambient) * tss;
}

// The GDC variant with its parameters from a BakerThickness and the thickness in mesh units.
fn baker_translucency(params: BakerThickness, N: vec3f, V: vec3f, L: vec3f, thickness: f32) -> vec3f {
    let tss = baker_thickness_transmittance(thickness, params.attenuationDistance);
    return baker_translucency_gdc(N, V, L, tss, params.subsurfaceColor, params.distortion, params.power,
                                  params.scale, params.ambient);
}
