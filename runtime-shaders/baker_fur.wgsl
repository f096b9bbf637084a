// baker_fur.wgsl: shell-and-fin fur from BAKER_fur (Lengyel et al., I3D 2001; RTR4 14.7.3); the WGSL twin of
// baker_fur.glsl (same functions, same arguments, same meaning; see there and schemas/BAKER_fur/README.md).
// No entry point, no bindings: paste it once (names are unique across the runtime modules). tests/gl/test_wgsl.py
// compiles it in Chromium's WebGPU and checks it against tests/gl/twins_fur.py.

// Height (0..1 of the fur length) of shell i's slice, as baked: (i + 0.5) / shellCount.
fn baker_fur_shell_height(shell: f32, shellCount: f32) -> f32 {
    return (shell + 0.5) / shellCount;
}

// Shell vertex: out along the normal by (shell + 1) x spacing, plus a displacement (mesh units at the outermost
// shell) growing with the square of the height, so hairs bend rather than slant.
fn baker_fur_shell_position(position: vec3f, normal: vec3f, shell: f32, shellSpacing: f32, shellCount: f32,
                            displacement: vec3f) -> vec3f {
    let h = (shell + 1.0) / shellCount;
    return position + normal * ((shell + 1.0) * shellSpacing) + displacement * (h * h);
}

fn baker_fur_shell_uv(uv: vec2f, tiling: f32) -> vec2f {
    return uv * tiling;
}

// Shell fragment: the texel's colour darkened towards the root (occlusionAtRoot in 0..1), its coverage as alpha.
fn baker_fur_shell_shade(texel: vec4f, height: f32, occlusionAtRoot: f32) -> vec4f {
    return vec4f(texel.rgb * mix(occlusionAtRoot, 1.0, height), texel.a);
}

// The two face normals of a fin's edge from its four corners (v0, v1 the edge, v2 opposite in the first face, v3
// opposite in the second, which runs v1 -> v0). GLSL's `out` parameters are pointers here.
fn baker_fur_fin_face_normals(v0: vec3f, v1: vec3f, v2: vec3f, v3: vec3f, n0: ptr<function, vec3f>,
                              n1: ptr<function, vec3f>) {
    *n0 = normalize(cross(v1 - v0, v2 - v0));
    *n1 = normalize(cross(v0 - v1, v3 - v1));
}

// Fin vertex: corner 0 at v0, 1 at v1 on the surface; 2 above v1 and 3 above v0 by `finLength` along `normal`.
fn baker_fur_fin_position(v0: vec3f, v1: vec3f, normal: vec3f, corner: f32, finLength: f32) -> vec3f {
    let base = select(v1, v0, corner < 0.5 || corner > 2.5);
    let up = select(0.0, 1.0, corner > 1.5);
    return base + normal * (finLength * up);
}

// How much of a fin to show: 1 on the silhouette, falling to 0 when |N . V| reaches `threshold` (Lengyel et al.
// fade fins in near the silhouette). V: unit, towards the eye.
fn baker_fur_fin_weight(n0: vec3f, n1: vec3f, V: vec3f, threshold: f32) -> f32 {
    let n = normalize(n0 + n1);
    return 1.0 - smoothstep(0.0, threshold, abs(dot(n, V)));
}
