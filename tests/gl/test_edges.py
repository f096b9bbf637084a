"""``runtime-shaders/baker_edges.glsl``: compiles as GLSL ES 3.00 and 3.30 core, and does what its twin says.

Everything goes through the written file: a cube (24 vertices, split normals) and an icosphere are baked with fins,
saved as .glb and read back. Fins: the vertex shader's outputs are captured with transform feedback and compared with
the twin, and a sphere's contour fins cover the ring 2 pi R w a w-pixel line should. Shell outline: rendered with
_OUTLINE_NORMAL, its coverage equals the area between the convex hulls of the twin-displaced and the original
vertices, and the cube's corners are closed (with the split NORMALs they crack open). Open meshes: through the window
of a single-sided sphere no shell ink shows once the open primitive's back faces go into depth first (unit normals
and no such pass: the whole window), and an open bowl's shell is pinned to its rim by the zero _OUTLINE_NORMAL there.
Wireframe: coverage matches the twin on every pixel, and the quad diagonal of the face seen head-on is hidden by the
mask.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import ConvexHull

import baker
from baker.gltf.document import GltfDocument
from baker.pipeline import save

from . import twins_edges as twins

from .glsl import HEADERS, assert_compiles, read_host

REPO = Path(__file__).parents[2]
MODULE = (REPO / "runtime-shaders" / "baker_edges.glsl").read_text()
SIZE = 256

# the preview's fin wrapper (runtime-shaders/hosts/edges_fin.vert.glsl; u_depthOffset unset: 0)
FIN_VS = read_host("edges_fin.vert.glsl")

# the fin shader's outputs, one point per vertex into a float texture (transform feedback is not reliable on
# every EGL/llvmpipe build): the same function calls, with gl_Position moved to the vertex's texel
CAPTURE_VS = FIN_VS.replace("out vec4 v_clip;", "uniform int u_columns;\nflat out vec4 v_clip;").replace(
    "out float v_kind;", "flat out float v_kind;").replace(
    "gl_Position = v_clip;",
    "gl_Position = vec4((vec2(gl_VertexID % u_columns, gl_VertexID / u_columns) + 0.5) / vec2(u_columns) * 2.0 - 1.0,"
    " 0.0, 1.0);\n    gl_PointSize = 1.0;")

CAPTURE_FS = """
flat in vec4 v_clip;
flat in float v_kind;
layout(location = 0) out vec4 o_clip;
layout(location = 1) out vec4 o_kind;
void main() {
    o_clip = v_clip;
    o_kind = vec4(v_kind);
}
"""

SOLID_FS = read_host("solid.frag.glsl")

OBJECT_VS = """
in vec3 POSITION;
uniform mat4 u_viewProjection;
void main() {
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""

SHELL_VS = """
in vec3 POSITION;
in vec3 a_outlineNormal;
uniform mat4 u_viewProjection;
uniform float u_width;
uniform float u_viewportHeight;
uniform float u_projectionScaleY;
void main() {
    float w = (u_viewProjection * vec4(POSITION, 1.0)).w;
    vec3 p = baker_shell_position(POSITION, a_outlineNormal, w, u_width, u_viewportHeight, u_projectionScaleY);
    gl_Position = u_viewProjection * vec4(p, 1.0);
}
"""

WIRE_VS = """
in vec3 POSITION;
in float a_mask;
uniform mat4 u_viewProjection;
out vec3 v_bary;
flat out int v_mask;
void main() {
    v_bary = baker_barycentric(gl_VertexID);
    v_mask = int(a_mask + 0.5);
    gl_Position = u_viewProjection * vec4(POSITION, 1.0);
}
"""

WIRE_FS = """
in vec3 v_bary;
flat in int v_mask;
uniform float u_width;
uniform float u_halo;
layout(location = 0) out vec4 o_bary;
layout(location = 1) out vec4 o_slope;
layout(location = 2) out vec4 o_wire;
void main() {
    vec3 slope = fwidth(v_bary);
    o_bary = vec4(v_bary, float(v_mask));
    o_slope = vec4(slope, 1.0);
    o_wire = vec4(baker_wireframe(v_bary, slope, v_mask, u_width, u_halo), 0.0, 1.0);
}
"""

PROGRAMS = {"fin": (FIN_VS, SOLID_FS), "capture": (CAPTURE_VS, CAPTURE_FS), "object": (OBJECT_VS, SOLID_FS), "shell": (SHELL_VS, SOLID_FS),
            "wire": (WIRE_VS, WIRE_FS)}


def source(version: str, body: str) -> str:
    return HEADERS[version] + MODULE + body


def program(ctx, name: str, **kwargs):
    vs, fs = PROGRAMS[name]
    return ctx.program(vertex_shader=source("330 core", vs), fragment_shader=source("330 core", fs), **kwargs)


@pytest.mark.parametrize("stage", ["vert", "frag"])
@pytest.mark.parametrize("name", sorted(PROGRAMS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_compiles(glslang_validator, tmp_path, version, name, stage):
    assert_compiles(glslang_validator, tmp_path, version, name, stage, source(version, PROGRAMS[name][0 if stage == "vert" else 1]))


# ---------------------------------------------------------------------------------------------------------- data
def split_cube() -> trimesh.Trimesh:
    import sys

    sys.path.insert(0, str(REPO / "tests"))
    from techniques.test_edges import split_cube as make

    return make()


def baked(folder: Path, mesh: trimesh.Trimesh, name: str) -> dict:
    src = folder / f"{name}.glb"
    mesh.export(str(src), include_normals=True)
    out = folder / f"{name}_edges.glb"
    save(baker.bake(str(src), bakes=["edges"], options={"edges": {"fins": True}}), out)
    doc = GltfDocument.load(out)
    prims = doc.json["meshes"][0]["primitives"]
    prim = prims[0]
    ext = prim["extensions"]["BAKER_edges"]
    fin = prims[ext["fins"]]["attributes"]
    attr = prim["attributes"]
    return {
        "positions": doc.accessor(attr["POSITION"]).astype(np.float32),
        "normals": doc.accessor(attr["NORMAL"]).astype(np.float32),
        "outline": doc.accessor(attr["_OUTLINE_NORMAL"]).astype(np.float32),
        "indices": doc.accessor(prim["indices"]).astype(np.uint32),
        "mask": doc.accessor(ext["wireframeMask"]).astype(np.float32),
        "fin": {k: doc.accessor(v).astype(np.float32) for k, v in fin.items()},
        "fin_indices": doc.accessor(prims[ext["fins"]]["indices"]).astype(np.uint32),
    }


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    return baked(tmp_path_factory.mktemp("cube"), split_cube(), "cube")


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    return baked(tmp_path_factory.mktemp("sphere"), trimesh.creation.icosphere(3, radius=1.0), "sphere")


def perspective(yfov, aspect, near, far):
    f = 1.0 / math.tan(yfov / 2)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0], [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                     [0, 0, -1, 0]])


def look_at(eye, target, up):
    f = (target - eye) / np.linalg.norm(target - eye)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def view_projection(eye, yfov=math.radians(40.0)):
    return perspective(yfov, 1.0, 0.1, 20.0) @ look_at(np.asarray(eye, float), np.zeros(3), np.array([0.0, 1.0, 0.0]))


def set_matrix(prog, name, m):
    prog[name].write(np.ascontiguousarray(m.T, np.float32).tobytes())  # GLSL matrices are column-major


def to_pixels(clip):
    ndc = clip[:, :2] / clip[:, 3:4]
    return (ndc + 1.0) * 0.5 * SIZE


# ---------------------------------------------------------------------------------------------------------- fins
def _fin_setup(ctx, name, data, vp, eye, width, show):
    prog = program(ctx, name)
    set_matrix(prog, "u_viewProjection", vp)
    prog["u_eye"].value = tuple(map(float, eye))
    prog["u_creaseCos"].value = math.cos(math.radians(60.0))
    prog["u_width"].value = width
    prog["u_viewport"].value = (SIZE, SIZE)
    prog["u_show"].value = show
    fin = data["fin"]
    # the buffers as written (FLOAT VEC3, scalars in x) bound as "3f" to `in float`: GL reads x
    content = [(ctx.buffer(np.ascontiguousarray(fin[k]).tobytes()), "3f", k)
               for k in ("_FIN_V0", "_FIN_V1", "_FIN_V2", "_FIN_V3", "_FIN_CORNER", "_FIN_FLAGS")]
    return prog, content


def _fin_feedback(ctx, data, vp, eye, width, show):
    """The fin vertex shader's (v_clip, v_kind) for every fin vertex, read back from a float texture."""
    import moderngl

    prog, content = _fin_setup(ctx, "capture", data, vp, eye, width, show)
    n = len(data["fin"]["_FIN_V0"])
    columns = int(math.ceil(math.sqrt(n)))
    prog["u_columns"].value = columns
    targets = [ctx.texture((columns, columns), 4, dtype="f4") for _ in range(2)]
    fbo = ctx.framebuffer(targets)
    fbo.use()
    fbo.clear()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, content).render(moderngl.POINTS, vertices=n)
    ctx.finish()
    clip, kind = (np.frombuffer(t.read(), np.float32).reshape(-1, 4)[:n] for t in targets)
    return np.concatenate([clip, kind[:, :1]], axis=1)


def test_fin_vertex_shader_matches_twin(gl_context, cube):
    eye = np.array([2.2, 1.7, 3.1])
    vp = view_projection(eye)
    gpu = _fin_feedback(gl_context, cube, vp, eye, 3.0, 15)
    fin = cube["fin"]
    kind = twins.baker_fin_classify(fin["_FIN_V0"], fin["_FIN_V1"], fin["_FIN_V2"], fin["_FIN_V3"], fin["_FIN_FLAGS"][:, 0],
                                    eye, math.cos(math.radians(60.0)))
    assert np.array_equal(gpu[:, 4].astype(int), kind)
    # a cube from a generic viewpoint: 6 of its 12 edges are contours, all 12 are ridges, none valleys
    per_edge = kind[::4]
    assert np.count_nonzero(per_edge & twins.BAKER_FIN_CONTOUR) == 6
    assert np.count_nonzero(per_edge & twins.BAKER_FIN_RIDGE) == 12
    assert np.count_nonzero(per_edge & (twins.BAKER_FIN_VALLEY | twins.BAKER_FIN_BOUNDARY)) == 0
    h = lambda p: np.concatenate([p, np.ones((len(p), 1), np.float32)], axis=1) @ vp.T.astype(np.float32)  # noqa: E731
    clip = twins.baker_fin_position(h(fin["_FIN_V0"]), h(fin["_FIN_V1"]), fin["_FIN_CORNER"][:, 0], 3.0, (SIZE, SIZE))
    drawn = kind != 0
    np.testing.assert_allclose(gpu[drawn, :4], clip[drawn], rtol=1e-4, atol=1e-4)
    assert np.all(gpu[~drawn, :4] == twins.baker_fin_culled())
    # the drawn quads are 3 pixels wide: the two long sides of each fin are 3 px apart in the image
    px = to_pixels(clip)
    quads = px.reshape(-1, 4, 2)[drawn[::4]]
    along = quads[:, 1] - quads[:, 0]
    across = quads[:, 3] - quads[:, 0]
    normal = np.stack([-along[:, 1], along[:, 0]], axis=1) / np.linalg.norm(along, axis=1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.sum(across * normal, axis=1)), 3.0, atol=1e-2)


def test_sphere_contour_fins_cover_a_ring(gl_context, sphere):
    import moderngl

    ctx = gl_context
    eye = np.array([0.0, 0.0, 4.0])
    vp = view_projection(eye)
    width = 4.0
    prog, content = _fin_setup(ctx, "fin", sphere, vp, eye, width, 1)  # contours only
    prog["u_color"].value = (1.0, 1.0, 1.0, 1.0)
    ibo = ctx.buffer(sphere["fin_indices"].tobytes())
    vao = ctx.vertex_array(prog, content, index_buffer=ibo, index_element_size=4)
    target = ctx.texture((SIZE, SIZE), 4, dtype="f1")
    fbo = ctx.framebuffer([target])
    fbo.use()
    fbo.clear()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    vao.render(moderngl.TRIANGLES)
    ctx.finish()
    image = np.frombuffer(target.read(), np.uint8).reshape(SIZE, SIZE, 4)[..., 0] > 0
    radius = math.tan(math.asin(0.25)) / math.tan(math.radians(20.0)) * SIZE / 2
    expected = 2 * math.pi * radius * width
    assert abs(image.sum() - expected) / expected < 0.12
    yy, xx = np.nonzero(image)
    r = np.hypot(xx + 0.5 - SIZE / 2, yy + 0.5 - SIZE / 2)
    assert np.all(np.abs(r - radius) < width)  # a ring around the projected sphere, nothing elsewhere


# ---------------------------------------------------------------------------------------------------------- shell
def _render_outline(ctx, data, normals, eye, width, occluder=False, double_sided=False):
    """Object in red (single-sided: back faces culled, unless ``double_sided``), then its shell's back faces in green
    behind it: returns the green mask. ``occluder``: between the two, the object's back faces into depth only, as the
    hosts draw an open single-sided primitive (its inside, seen through an opening, then hides the shell)."""
    import moderngl

    vp = view_projection(eye)
    target = ctx.texture((SIZE, SIZE), 4, dtype="f1")
    depth = ctx.depth_renderbuffer((SIZE, SIZE))
    fbo = ctx.framebuffer([target], depth)
    fbo.use()
    fbo.clear(depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ibo = ctx.buffer(data["indices"].tobytes())
    pos = ctx.buffer(data["positions"].tobytes())
    obj = program(ctx, "object")
    set_matrix(obj, "u_viewProjection", vp)
    obj["u_color"].value = (1.0, 0.0, 0.0, 1.0)
    ctx.front_face = "ccw"
    ctx.cull_face = "back"
    if double_sided:
        ctx.disable(moderngl.CULL_FACE)
    ctx.vertex_array(obj, [(pos, "3f", "POSITION")], index_buffer=ibo, index_element_size=4).render()
    ctx.enable(moderngl.CULL_FACE)
    if occluder:
        fbo.color_mask = (False, False, False, False)
        ctx.cull_face = "front"
        ctx.vertex_array(obj, [(pos, "3f", "POSITION")], index_buffer=ibo, index_element_size=4).render()
        fbo.color_mask = (True, True, True, True)
    shell = program(ctx, "shell")
    set_matrix(shell, "u_viewProjection", vp)
    shell["u_color"].value = (0.0, 1.0, 0.0, 1.0)
    shell["u_width"].value = width
    shell["u_viewportHeight"].value = float(SIZE)
    shell["u_projectionScaleY"].value = 1.0 / math.tan(math.radians(20.0))
    ctx.cull_face = "front"
    nrm = ctx.buffer(np.ascontiguousarray(normals, np.float32).tobytes())
    ctx.vertex_array(shell, [(pos, "3f", "POSITION"), (nrm, "3f", "a_outlineNormal")], index_buffer=ibo,
                     index_element_size=4).render()
    ctx.finish()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.cull_face = "back"
    image = np.frombuffer(target.read(), np.uint8).reshape(SIZE, SIZE, 4)
    return image[..., 1] > 127, vp


def _inside(hull: ConvexHull, points: np.ndarray) -> np.ndarray:
    return np.all(points @ hull.equations[:, :2].T + hull.equations[:, 2] <= 0.0, axis=1)


def _hull_ring(data, vp, normals, width):
    """Twin prediction: the pixels whose centres lie inside the hull of the projected displaced vertices and outside
    the hull of the projected original ones (both shapes are convex here)."""
    p = data["positions"]
    h = np.concatenate([p, np.ones((len(p), 1), np.float32)], axis=1) @ vp.T.astype(np.float32)
    moved = twins.baker_shell_position(p, normals, h[:, 3], width, SIZE, 1.0 / math.tan(math.radians(20.0)))
    hm = np.concatenate([moved, np.ones((len(p), 1), np.float32)], axis=1) @ vp.T.astype(np.float32)
    outer, inner = ConvexHull(to_pixels(hm)), ConvexHull(to_pixels(h))
    yy, xx = np.mgrid[0:SIZE, 0:SIZE]
    centres = np.stack([xx.ravel() + 0.5, yy.ravel() + 0.5], axis=1)
    return (_inside(outer, centres) & ~_inside(inner, centres)).reshape(SIZE, SIZE)


@pytest.mark.parametrize("shape", ["cube", "sphere"])
def test_shell_outline_coverage_matches_twin(gl_context, cube, sphere, shape):
    data = cube if shape == "cube" else sphere
    eye = np.array([0.0, 0.0, 3.0]) if shape == "cube" else np.array([0.3, 0.4, 3.5])
    width = 6.0
    green, vp = _render_outline(gl_context, data, data["outline"], eye, width)
    expected = _hull_ring(data, vp, data["outline"], width)
    assert expected.sum() > 1000
    # the same pixels, up to the facets of the sphere between vertices and ties on pixel centres
    assert np.count_nonzero(green != expected) <= 0.03 * expected.sum()
    assert abs(int(green.sum()) - int(expected.sum())) <= 0.02 * expected.sum()


def test_cube_outline_corners_close_only_with_outline_normals(gl_context, cube):
    eye = np.array([0.0, 0.0, 3.0])
    width = 8.0
    merged, vp = _render_outline(gl_context, cube, cube["outline"], eye, width)
    split, _ = _render_outline(gl_context, cube, cube["normals"], eye, width)
    # the front face's corners on screen; the probe sits diagonally just outside each corner
    corners = np.array([[x, y, 0.5] for x in (-0.5, 0.5) for y in (-0.5, 0.5)], np.float32)
    px = to_pixels(np.concatenate([corners, np.ones((4, 1), np.float32)], axis=1) @ vp.T.astype(np.float32))
    for (x, y), (sx, sy) in zip(px, np.sign(px - SIZE / 2)):
        col, row = int(x + sx * 2.0), int(y + sy * 2.0)
        assert merged[row, col], "the outline is closed at the corner"
        assert not split[row, col], "split normals crack the shell open at the corner"


def holed_sphere() -> tuple[trimesh.Trimesh, np.ndarray]:
    """A single-sided icosphere with a rectangular window cut into its +z side: (the open mesh, the cut triangles)."""
    s = trimesh.creation.icosphere(3, radius=1.0)
    c = s.triangles_center
    cut = (c[:, 2] > 0.3) & (np.abs(c[:, 0]) < 0.5) & (np.abs(c[:, 1]) < 0.35)
    return trimesh.Trimesh(s.vertices, s.faces[~cut], process=False), s.vertices[s.faces[cut]]


def window_pixels(triangles: np.ndarray, vp: np.ndarray, margin: int) -> np.ndarray:
    """Pixels whose centres lie inside the projected (cut-out) triangles, at least ``margin`` pixels from the
    window's rim (the rim's own line may be there)."""
    from scipy import ndimage

    h = np.concatenate([triangles.reshape(-1, 3), np.ones((triangles.size // 3, 1))], axis=1) @ vp.T
    corners = to_pixels(h).reshape(-1, 3, 2)
    yy, xx = np.mgrid[0:SIZE, 0:SIZE]
    px, py = xx.ravel() + 0.5, yy.ravel() + 0.5
    inside = np.zeros(len(px), bool)
    for a, b, c in corners:
        sides = [(q[0] - p[0]) * (py - p[1]) - (q[1] - p[1]) * (px - p[0]) for p, q in ((a, b), (b, c), (c, a))]
        inside |= np.all([d >= 0 for d in sides], axis=0) | np.all([d <= 0 for d in sides], axis=0)
    inside = inside.reshape(SIZE, SIZE)
    return ndimage.binary_erosion(inside, iterations=margin) if margin > 0 else \
        ndimage.binary_dilation(inside, iterations=-margin) if margin < 0 else inside


def test_open_mesh_shell_leaves_its_window_clear(gl_context, tmp_path):
    """RTR4 15.2.2-15.2.3: a shell fails on an open mesh: through the window of a single-sided sphere the inflated
    back faces fill the opening with ink. With the bake's _OUTLINE_NORMAL (zero on the rim) and the hosts'
    depth-only back-face pass, no ink is left inside the window, and the silhouette ring is as wide as before."""
    from baker.geometry.edges import outline_normals

    mesh, cut = holed_sphere()
    data = baked(tmp_path, mesh, "holed_sphere")
    baked_normals = data["outline"]
    length = np.linalg.norm(baked_normals, axis=1)
    boundary = mesh.edges_sorted[trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)]
    rim = {tuple(p) for p in mesh.vertices[np.unique(boundary)].astype(np.float32).round(5)}
    zero = {tuple(p) for p in data["positions"][length < 0.5].round(5)}
    assert len(rim) >= 10 and zero == rim  # zero exactly on the window's rim
    assert np.all(np.abs(length[length >= 0.5] - 1.0) < 1e-5)
    unit = outline_normals(data["positions"], data["indices"].reshape(-1, 3)).astype(np.float32)  # what baker wrote
    eye = np.array([0.4, 0.3, 3.2])
    width = 5.0
    before, vp = _render_outline(gl_context, data, unit, eye, width)
    after, _ = _render_outline(gl_context, data, baked_normals, eye, width, occluder=True)
    window = window_pixels(cut, vp.astype(np.float32), margin=2)
    print("ink inside the window: unit normals", int(before[window].sum()), "baked + occluder", int(after[window].sum()),
          "of", int(window.sum()), "window pixels")
    assert window.sum() > 2000
    assert before[window].mean() > 0.5  # the failure this guards against shows
    assert after[window].sum() == 0
    # the silhouette ring, away from the window: the same pixels
    outside = ~window_pixels(cut, vp.astype(np.float32), margin=-int(width) - 2)
    ring_before, ring_after = before & outside, after & outside
    assert ring_before.sum() > 2000 and np.count_nonzero(ring_before != ring_after) == 0


def test_shell_is_pinned_to_an_open_bowls_rim(gl_context, tmp_path):
    """A double-sided open bowl seen from inside: the shell lies behind it, but with unit normals everywhere the
    rim's normals lean outwards and push ink out past the rim (a window's far rim seen through the window does the
    same). With _OUTLINE_NORMAL zero on the rim the shell is pinned there: no ink beyond the bowl's own pixels."""
    from baker.geometry.edges import outline_normals

    grid = np.linspace(-0.8, 0.8, 9)
    xx, yy = np.meshgrid(grid, grid)
    # a shallow bowl opening towards the eye (normals +z, the rim bent towards -z): seen from inside, like a
    # window's far rim seen through the window
    vertices = np.stack([xx.ravel(), yy.ravel(), -0.4 * (xx.ravel() ** 2 + yy.ravel() ** 2)], axis=1)
    quads = np.array([[r * 9 + c, r * 9 + c + 1, (r + 1) * 9 + c + 1, (r + 1) * 9 + c] for r in range(8) for c in range(8)])
    sheet = trimesh.Trimesh(vertices, np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]), process=False)
    data = baked(tmp_path, sheet, "sheet")
    unit = outline_normals(data["positions"], data["indices"].reshape(-1, 3)).astype(np.float32)
    eye = np.array([0.5, 0.4, -3.0])  # inside: the bowl's back faces are what the shell draws
    width = 6.0
    before, vp = _render_outline(gl_context, data, unit, eye, width, double_sided=True)
    after, _ = _render_outline(gl_context, data, data["outline"], eye, width, double_sided=True)
    beyond = ~window_pixels(sheet.vertices[sheet.faces], vp.astype(np.float32), margin=-1)
    print("shell ink beyond the bowl's rim: unit normals", int(before[beyond].sum()), "baked", int(after[beyond].sum()))
    assert before[beyond].sum() > 200
    assert after[beyond].sum() == 0


# ---------------------------------------------------------------------------------------------------------- wireframe
def _render_wire(ctx, data, eye, mask):
    import moderngl

    vp = view_projection(eye)
    tris = data["indices"].reshape(-1, 3)
    flat = data["positions"][tris.reshape(-1)]
    masks = np.repeat(mask.astype(np.float32), 3)
    prog = program(ctx, "wire")
    set_matrix(prog, "u_viewProjection", vp)
    prog["u_width"].value = 2.0
    prog["u_halo"].value = 2.0
    targets = [ctx.texture((SIZE, SIZE), 4, dtype="f4") for _ in range(3)]
    depth = ctx.depth_renderbuffer((SIZE, SIZE))
    fbo = ctx.framebuffer(targets, depth)
    fbo.use()
    fbo.clear(depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    ctx.vertex_array(prog, [(ctx.buffer(flat.tobytes()), "3f", "POSITION"),
                            (ctx.buffer(masks.tobytes()), "1f", "a_mask")]).render(moderngl.TRIANGLES)
    ctx.finish()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    return [np.frombuffer(t.read(), np.float32).reshape(SIZE, SIZE, 4) for t in targets]


def test_wireframe_matches_twin_and_hides_quad_diagonals(gl_context, cube):
    eye = np.array([0.0, 0.0, 3.0])
    assert np.all(cube["mask"] != 7)  # each triangle of a cube face hides its diagonal
    bary, slope, wire = _render_wire(gl_context, cube, eye, cube["mask"])
    covered = slope[..., 3] > 0
    assert covered.sum() > 1000
    twin = twins.baker_wireframe(bary[covered][:, :3], slope[covered][:, :3],
                                 bary[covered][:, 3].round().astype(np.int32), 2.0, 2.0)
    np.testing.assert_allclose(wire[covered][:, :2], twin, atol=1e-5)
    # the front face (a square seen head-on): its diagonal is not drawn, its border is
    center = SIZE // 2
    assert wire[center, center, 0] == 0.0
    _, _, all_edges = _render_wire(gl_context, cube, eye, np.full_like(cube["mask"], 7))
    diagonal = all_edges[center - 3: center + 4, center - 3: center + 4, 0]
    assert diagonal.max() == 1.0
    assert wire[center - 3: center + 4, center - 3: center + 4, 0].max() == 0.0
    border_x = int(round(to_pixels(np.array([[0.5, 0.0, 0.5, 1.0]], np.float32) @ view_projection(eye).T
                                   .astype(np.float32))[0, 0]))
    # at the silhouette only the inner half of the line lies on the triangle (RTR4 15.4: half as thick)
    assert wire[center, border_x - 3: border_x + 3, 0].max() > 0.5
