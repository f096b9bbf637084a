// baker_edges.glsl: lines from baked edge adjacency (RTR4 section 15.2): fins, shell outlines, wireframes.
//
// Three techniques, each a few pure functions:
//
// 1. Fins (McGuire & Hughes, "Hardware-Determined Feature Edge Extraction for GPGPU", NPAR 2004; RTR4 15.2.4):
//    every edge is drawn as a degenerate quad whose four vertices all carry the edge (v0, v1), the third vertex v2 of
//    its face (v0, v1, v2) and the third vertex v3 of the other face (v1, v0, v3). The vertex shader classifies the
//    edge - contour by eq. 15.1, (n0 . v)(n1 . v) < 0, ridge/valley by the angle between the face normals, boundary
//    from the baked flags - and, when the edge is wanted, extrudes the quad to a constant width in pixels.
//    Data: the fin primitive of BAKER_edges (attributes _FIN_V0.._FIN_V3, _FIN_CORNER, _FIN_FLAGS).
// 2. Shell outline (RTR4 15.2.2, "shell or halo method"): draw the back faces again, pushed out along
//    _OUTLINE_NORMAL by a distance proportional to the view depth, so the outline is `width` pixels wide. The baked
//    normal is one average per welded position: a cube's corners do not crack open. A shell needs a closed mesh: on
//    an open one the inflated back faces show through every opening. So the bake writes _OUTLINE_NORMAL = 0 at
//    vertices on boundary and non-manifold edges (the shell is pinned to the rim and cannot cross it), and a host
//    draws an open primitive of a single-sided material's back faces into depth only (colour writes off) before the
//    shell, so where its inside shows through an opening the shell stays hidden; boundary lines come from the fins.
// 3. Single-pass wireframe (Baerentzen et al., "Single-pass Wireframe Rendering", SIGGRAPH 2006 sketch; RTR4 15.4):
//    the fragment's distance in pixels to each triangle edge is its barycentric coordinate divided by the screen-space
//    rate of change of that coordinate; BAKER_edges.wireframeMask (bit k: edge v_k -> v_k+1) hides quad diagonals.
//    Barycentrics come from a non-indexed draw: baker_barycentric(gl_VertexID).
//
// How to include: no #version, no precision statement, no uniforms, inputs or outputs; prepend your header and paste
// (or #include) this file. Compiles as GLSL ES 3.00 (WebGL2) and GLSL 3.30 core. Every function has a numpy twin in
// tests/gl/twins_edges.py, checked by tests/gl/test_edges.py.

#ifndef BAKER_EDGES_GLSL
#define BAKER_EDGES_GLSL

// BAKER_edges per-edge flags (the `flags` accessor and the _FIN_FLAGS attribute)
const int BAKER_EDGE_BOUNDARY = 1;
const int BAKER_EDGE_NON_MANIFOLD = 2;
const int BAKER_EDGE_CREASE = 4;
const int BAKER_EDGE_RIDGE = 8;
const int BAKER_EDGE_VALLEY = 16;
const int BAKER_EDGE_MATERIAL = 32;

// what baker_fin_classify finds
const int BAKER_FIN_CONTOUR = 1;
const int BAKER_FIN_RIDGE = 2;
const int BAKER_FIN_VALLEY = 4;
const int BAKER_FIN_BOUNDARY = 8;

// Classify an edge for the current eye (perspective; for an orthographic view pass eye = v0 - 1e6 * viewDirection).
// v0, v1, v2, v3 in the same space as eye; flags = _FIN_FLAGS; creaseCos = cos(crease angle between face normals).
// Boundary and non-manifold edges (flags) are never contours; the ridge/valley test uses the current geometry, so a
// deforming mesh works too.
int baker_fin_classify(vec3 v0, vec3 v1, vec3 v2, vec3 v3, float flags, vec3 eye, float creaseCos) {
    int f = int(flags + 0.5);
    if ((f & (BAKER_EDGE_BOUNDARY | BAKER_EDGE_NON_MANIFOLD)) != 0) {
        return BAKER_FIN_BOUNDARY;
    }
    vec3 n0 = cross(v1 - v0, v2 - v0);
    vec3 n1 = cross(v0 - v1, v3 - v1);
    vec3 toEye = eye - v0;
    int result = 0;
    if (dot(n0, toEye) * dot(n1, toEye) < 0.0) {
        result |= BAKER_FIN_CONTOUR;
    }
    float len0 = length(n0);
    float len1 = length(n1);
    if (len0 > 0.0 && len1 > 0.0 && dot(n0, n1) < creaseCos * len0 * len1) {
        result |= dot(n0, v3 - v0) <= 0.0 ? BAKER_FIN_RIDGE : BAKER_FIN_VALLEY;
    }
    return result;
}

// Clip-space position of fin corner `corner` (0: v0, 1: v1, 2: v1, 3: v0; corners 0-1 on one side of the edge, 2-3
// on the other) for a line `widthPx` pixels wide, centred on the edge and extended by half the width past both ends
// (square caps: neighbouring fins overlap instead of leaving chinks). clip0, clip1: the edge's ends in clip space;
// viewport: its size in pixels. Ends behind the eye (w <= 0) are the caller's to avoid (near-plane clipping).
vec4 baker_fin_position(vec4 clip0, vec4 clip1, float corner, float widthPx, vec2 viewport) {
    vec2 s0 = clip0.xy / clip0.w * viewport;
    vec2 s1 = clip1.xy / clip1.w * viewport;
    vec2 d = s1 - s0;
    float len = length(d);
    vec2 dir = len > 1e-6 ? d / len : vec2(1.0, 0.0);
    vec2 normal = vec2(-dir.y, dir.x);
    int c = int(corner + 0.5);
    bool atV1 = c == 1 || c == 2;
    float side = c < 2 ? -0.5 : 0.5;
    float along = atV1 ? 0.5 : -0.5;
    vec4 at = atV1 ? clip1 : clip0;
    // viewport-scaled NDC: 1 pixel = 2 / viewport in NDC
    vec2 offset = (normal * side + dir * along) * widthPx * 2.0 / viewport;
    return vec4(at.xy + offset * at.w, at.zw);
}

// A clip position outside the view volume: where a fin that is not drawn goes (the quad is culled).
vec4 baker_fin_culled() {
    return vec4(2.0, 2.0, 2.0, 1.0);
}

// Shell outline (RTR4 15.2.2): the vertex pushed out along the outline normal so the shell is `widthPx` pixels
// wide at the vertex's depth (unit normal; zero on an open rim: the vertex stays put). clipW: w of the unpushed vertex in clip space (its view depth for a perspective
// projection, 1 for an orthographic one); projectionScaleY: the projection matrix's [1][1] (cot(yfov / 2), or
// 1 / ymag); viewportHeight in pixels. Draw the result with front faces culled, after the object.
vec3 baker_shell_position(vec3 position, vec3 outlineNormal, float clipW, float widthPx, float viewportHeight,
                          float projectionScaleY) {
    float unitsPerPixel = 2.0 * clipW / (viewportHeight * projectionScaleY);
    return position + outlineNormal * (widthPx * unitsPerPixel);
}

// Corner `vertexId % 3` of a triangle as barycentric coordinates, for a non-indexed draw of the triangles.
vec3 baker_barycentric(int vertexId) {
    int k = vertexId - (vertexId / 3) * 3;
    return vec3(k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0);
}

// Distance in pixels from the fragment to the nearest edge the mask keeps (1e6 when none). bary: interpolated
// barycentrics; barySlope: fwidth(bary) in the fragment shader; mask: BAKER_edges.wireframeMask of the triangle,
// bit k = edge (v_k, v_k+1), which lies opposite corner k+2.
float baker_wireframe_distance(vec3 bary, vec3 barySlope, int mask) {
    vec3 d = bary / max(barySlope, vec3(1e-8));
    float best = 1e6;
    if ((mask & 1) != 0) best = min(best, d.z);  // edge v0 -> v1, opposite v2
    if ((mask & 2) != 0) best = min(best, d.x);  // edge v1 -> v2, opposite v0
    if ((mask & 4) != 0) best = min(best, d.y);  // edge v2 -> v0, opposite v1
    return best;
}

// Anti-aliased line coverage (x) and halo coverage (y) for a line `widthPx` wide with a halo `haloPx` wide around
// it (Baerentzen et al.; a 1-pixel linear ramp at each border). Blend: color = mix(mix(fill, haloColor, y), line, x).
vec2 baker_wireframe(vec3 bary, vec3 barySlope, int mask, float widthPx, float haloPx) {
    float d = baker_wireframe_distance(bary, barySlope, mask);
    float line = clamp(0.5 * widthPx - d + 0.5, 0.0, 1.0);
    float halo = clamp(0.5 * widthPx + haloPx - d + 0.5, 0.0, 1.0);
    return vec2(line, halo);
}

#endif // BAKER_EDGES_GLSL
