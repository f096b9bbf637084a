// baker_edges.wgsl: lines from baked edge adjacency (RTR4 15.2): fins, shell outlines, wireframes; the WGSL twin
// of baker_edges.glsl (same functions, same arguments, same meaning; see there and schemas/BAKER_edges/README.md).
//
// 1. Fins (McGuire & Hughes, NPAR 2004; RTR4 15.2.4): every edge a degenerate quad carrying v0, v1 and the opposite
//    vertices v2, v3; contour by eq. 15.1, (n0 . v)(n1 . v) < 0, ridge/valley by the face-normal angle.
// 2. Shell outline (RTR4 15.2.2): back faces pushed out along _OUTLINE_NORMAL, `width` pixels at any depth; the
//    normal is zero on open rims (boundary, non-manifold edges) and hosts write an open single-sided primitive's back
//    faces to depth before the shell (see baker_edges.glsl).
// 3. Single-pass wireframe (Baerentzen et al., SIGGRAPH 2006 sketch; RTR4 15.4): the distance in pixels to an edge
//    is the barycentric coordinate over its screen-space rate (pass fwidth(bary) from a fragment shader).
//
// How to include: no entry point, no bindings: paste it once (names are unique across the runtime modules).
// tests/gl/test_wgsl.py compiles it in Chromium's WebGPU and checks it against tests/gl/twins_edges.py.

// BAKER_edges per-edge flags (the `flags` accessor and the _FIN_FLAGS attribute)
const BAKER_EDGE_BOUNDARY: i32 = 1;
const BAKER_EDGE_NON_MANIFOLD: i32 = 2;
const BAKER_EDGE_CREASE: i32 = 4;
const BAKER_EDGE_RIDGE: i32 = 8;
const BAKER_EDGE_VALLEY: i32 = 16;
const BAKER_EDGE_MATERIAL: i32 = 32;

// what baker_fin_classify finds
const BAKER_FIN_CONTOUR: i32 = 1;
const BAKER_FIN_RIDGE: i32 = 2;
const BAKER_FIN_VALLEY: i32 = 4;
const BAKER_FIN_BOUNDARY: i32 = 8;

// Classify an edge for the current eye (orthographic: eye = v0 - 1e6 * viewDirection). flags = _FIN_FLAGS;
// creaseCos = cos(crease angle between face normals). Boundary and non-manifold edges are never contours.
fn baker_fin_classify(v0: vec3f, v1: vec3f, v2: vec3f, v3: vec3f, flags: f32, eye: vec3f, creaseCos: f32) -> i32 {
    let f = i32(flags + 0.5);
    if ((f & (BAKER_EDGE_BOUNDARY | BAKER_EDGE_NON_MANIFOLD)) != 0) {
        return BAKER_FIN_BOUNDARY;
    }
    let n0 = cross(v1 - v0, v2 - v0);
    let n1 = cross(v0 - v1, v3 - v1);
    let toEye = eye - v0;
    var result = 0;
    if (dot(n0, toEye) * dot(n1, toEye) < 0.0) {
        result |= BAKER_FIN_CONTOUR;
    }
    let len0 = length(n0);
    let len1 = length(n1);
    if (len0 > 0.0 && len1 > 0.0 && dot(n0, n1) < creaseCos * len0 * len1) {
        result |= select(BAKER_FIN_VALLEY, BAKER_FIN_RIDGE, dot(n0, v3 - v0) <= 0.0);
    }
    return result;
}

// Clip-space position of fin corner `corner` (0: v0, 1: v1, 2: v1, 3: v0; 0-1 on one side, 2-3 on the other) for
// a line `widthPx` pixels wide with square caps half the width past both ends. clip0, clip1: the edge's ends in clip
// space; viewport in pixels. Ends behind the eye (w <= 0) are the caller's to avoid.
fn baker_fin_position(clip0: vec4f, clip1: vec4f, corner: f32, widthPx: f32, viewport: vec2f) -> vec4f {
    let s0 = clip0.xy / clip0.w * viewport;
    let s1 = clip1.xy / clip1.w * viewport;
    let d = s1 - s0;
    let len = length(d);
    let dir = select(vec2f(1.0, 0.0), d / len, len > 1e-6);
    let normal = vec2f(-dir.y, dir.x);
    let c = i32(corner + 0.5);
    let atV1 = c == 1 || c == 2;
    let side = select(0.5, -0.5, c < 2);
    let along = select(-0.5, 0.5, atV1);
    let at = select(clip0, clip1, atV1);
    // viewport-scaled NDC: 1 pixel = 2 / viewport in NDC
    let offset = (normal * side + dir * along) * widthPx * 2.0 / viewport;
    return vec4f(at.xy + offset * at.w, at.zw);
}

// A clip position outside the view volume: where a fin that is not drawn goes (the quad is culled).
fn baker_fin_culled() -> vec4f {
    return vec4f(2.0, 2.0, 2.0, 1.0);
}

// Shell outline (RTR4 15.2.2): the vertex pushed out along the outline normal (unit; zero on an open rim) so the
// shell is `widthPx` pixels wide at its depth. clipW: w of the unpushed vertex in clip space; projectionScaleY: the projection's [1][1].
fn baker_shell_position(position: vec3f, outlineNormal: vec3f, clipW: f32, widthPx: f32, viewportHeight: f32,
                        projectionScaleY: f32) -> vec3f {
    let unitsPerPixel = 2.0 * clipW / (viewportHeight * projectionScaleY);
    return position + outlineNormal * (widthPx * unitsPerPixel);
}

// Corner `vertexId % 3` of a triangle as barycentric coordinates, for a non-indexed draw of the triangles.
fn baker_barycentric(vertexId: i32) -> vec3f {
    let k = vertexId - (vertexId / 3) * 3;
    return vec3f(select(0.0, 1.0, k == 0), select(0.0, 1.0, k == 1), select(0.0, 1.0, k == 2));
}

// Distance in pixels from the fragment to the nearest edge the mask keeps (1e6 when none). bary: interpolated
// barycentrics; barySlope: fwidth(bary); mask: BAKER_edges.wireframeMask, bit k = edge (v_k, v_k+1).
fn baker_wireframe_distance(bary: vec3f, barySlope: vec3f, mask: i32) -> f32 {
    let d = bary / max(barySlope, vec3f(1e-8));
    var best = 1e6;
    if ((mask & 1) != 0) { best = min(best, d.z); }  // edge v0 -> v1, opposite v2
    if ((mask & 2) != 0) { best = min(best, d.x); }  // edge v1 -> v2, opposite v0
    if ((mask & 4) != 0) { best = min(best, d.y); }  // edge v2 -> v0, opposite v1
    return best;
}

// Anti-aliased line coverage (x) and halo coverage (y) (Baerentzen et al.; a 1-pixel ramp at each border).
// Blend: color = mix(mix(fill, haloColor, y), line, x).
fn baker_wireframe(bary: vec3f, barySlope: vec3f, mask: i32, widthPx: f32, haloPx: f32) -> vec2f {
    let d = baker_wireframe_distance(bary, barySlope, mask);
    let line = clamp(0.5 * widthPx - d + 0.5, 0.0, 1.0);
    let halo = clamp(0.5 * widthPx + haloPx - d + 0.5, 0.0, 1.0);
    return vec2f(line, halo);
}
