"""Edge adjacency, classes and line drawings against independent truth (analytic shapes, trimesh, brute force)."""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

import baker
from baker.geometry import edges as E
from baker.cli import main as cli_main
from baker.techniques.edges import extension as X
from baker.gltf.document import GltfDocument
from baker.pipeline import save
from baker.validate import validate_file
from conftest import assert_khronos_clean

MESHES = Path(__file__).resolve().parents[3] / "shared" / "assets" / "meshes"
SPOT = Path(__file__).resolve().parents[2] / "examples" / "spot" / "spot.obj"


def split_cube(open_top: bool = False) -> trimesh.Trimesh:
    """A unit cube with one vertex per face corner (24 vertices) and flat per-face normals, as exporters write it."""
    box = trimesh.creation.box()
    verts, faces, normals = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            if open_top and axis == 2 and sign > 0:
                continue
            n = np.zeros(3)
            n[axis] = sign
            u, v = np.roll(np.eye(3), 1, axis=0)[axis], np.roll(np.eye(3), 2, axis=0)[axis]
            corners = [0.5 * n + 0.5 * (a * u + b * v) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            base = len(verts)
            verts += corners
            normals += [n] * 4
            quad = [[0, 1, 2], [0, 2, 3]]
            if np.dot(np.cross(u, v), n) < 0:
                quad = [[0, 2, 1], [0, 3, 2]]
            faces += [[base + i for i in q] for q in quad]
    del box
    return trimesh.Trimesh(np.array(verts), np.array(faces), vertex_normals=np.array(normals), process=False)


def bake_file(mesh: trimesh.Trimesh, folder: Path, name: str, options=None) -> tuple[Path, GltfDocument]:
    src = folder / f"{name}.glb"
    mesh.export(str(src), include_normals=True)
    out = folder / f"{name}_edges.glb"
    save(baker.bake(str(src), bakes=["edges"], options={"edges": options or {}}), out)
    assert_khronos_clean(out)
    return out, GltfDocument.load(out)


def primitive_data(doc: GltfDocument, p: int = 0) -> dict:
    prim = doc.json["meshes"][0]["primitives"][p]
    ext = prim["extensions"]["BAKER_edges"]
    out = {"prim": prim, "ext": ext, "positions": doc.accessor(prim["attributes"]["POSITION"]).astype(np.float64),
           "faces": doc.accessor(prim["indices"]).astype(np.int64).reshape(-1, 3)}
    for key in ("edges", "oppositeVertices", "flags", "dihedralAngles", "wireframeMask"):
        if key in ext:
            out[key] = doc.accessor(ext[key])
    if "_OUTLINE_NORMAL" in prim["attributes"]:
        out["outline"] = doc.accessor(prim["attributes"]["_OUTLINE_NORMAL"]).astype(np.float64)
    vis = prim.get("extensions", {}).get(X.EXT_VISIBILITY)
    if vis:
        out["codes"] = E.unpack_visibility(doc.accessor(vis["visibility"]), len(out["faces"]))
        out["mates"] = doc.accessor(vis["silhouetteMates"]) if "silhouetteMates" in vis else np.zeros(0, np.int64)
    return out


# ---------------------------------------------------------------------------------------------------------- cube
@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    mesh = split_cube()
    assert len(mesh.vertices) == 24
    _, doc = bake_file(mesh, tmp_path_factory.mktemp("cube"), "cube",
                       {"fins": True, "opposite_vertices": True, "dihedral_angles": True})
    return primitive_data(doc)


def test_cube_has_12_creases_and_no_boundary(cube):
    flags = cube["flags"].astype(np.int64)
    assert cube["ext"]["counts"]["crease"] == 12 and cube["ext"]["counts"]["boundary"] == 0
    assert np.count_nonzero(flags & E.CREASE) == 12
    assert np.count_nonzero(flags & E.RIDGE) == 12 and np.count_nonzero(flags & E.VALLEY) == 0
    assert np.count_nonzero(flags & E.BOUNDARY) == 0
    # every crease is a 90-degree convex fold; the 6 face diagonals are planar quad diagonals
    crease = (flags & E.CREASE) != 0
    np.testing.assert_allclose(cube["dihedralAngles"][crease], math.pi / 2, atol=1e-6)
    assert np.count_nonzero(flags & E.PLANAR) == 6 and np.count_nonzero(flags & E.QUAD_DIAGONAL) == 6
    # crease edges are geometric cube edges: length 1, endpoints differ in exactly one coordinate
    pos = cube["positions"]
    ends = pos[cube["edges"][crease].astype(np.int64)]
    np.testing.assert_allclose(np.linalg.norm(ends[:, 0] - ends[:, 1], axis=1), 1.0, atol=1e-6)


def test_cube_corner_copies_share_one_outline_normal(cube):
    pos, normals = cube["positions"], cube["outline"]
    corners = np.unique(np.round(pos, 6), axis=0)
    assert len(corners) == 8
    for corner in corners:  # a loop over the 8 corners of the test shape
        copies = np.flatnonzero(np.all(np.abs(pos - corner) < 1e-6, axis=1))
        assert len(copies) == 3
        assert np.ptp(normals[copies], axis=0).max() == 0.0  # bit-identical
        # angle weighting makes it the exact diagonal, however each face was triangulated
        np.testing.assert_allclose(normals[copies[0]], np.sign(corner) / math.sqrt(3), atol=1e-6)


def test_cube_edge_visibility_encodes_each_hard_edge_once(cube):
    codes, faces, pos = cube["codes"], cube["faces"], cube["positions"]
    assert codes.shape == (12, 3)
    # brute force: per geometric edge (rounded endpoint positions), the codes of its two triangle sides
    seen = {}
    for t in range(len(faces)):
        for k in range(3):
            a, b = (tuple(np.round(pos[faces[t, j]], 6)) for j in (k, (k + 1) % 3))
            seen.setdefault(tuple(sorted((a, b))), []).append(int(codes[t, k]))
    hard = [sorted(v) for v in seen.values() if 2 in v]
    assert len(hard) == 12 and all(v == [2, 3] for v in hard)
    assert sorted(v for values in seen.values() if 2 not in values for v in values) == [0] * 12  # diagonals
    assert len(cube["mates"]) == 0 and "silhouetteMates" not in cube["prim"]["extensions"][X.EXT_VISIBILITY]


def test_cube_fins_carry_the_edge_and_its_faces(cube, tmp_path):
    ext = cube["ext"]
    assert "fins" in ext
    # fin corner positions equal the edge list's vertices (v0, v1, v2, v3) read through the primitive's indices
    edges, opposite, pos = cube["edges"].astype(np.int64), cube["oppositeVertices"].astype(np.int64), cube["positions"]
    assert np.all(opposite[:, 1] != 0xFFFF)  # closed cube: every edge has its far face in the same primitive
    # (v0, v1, v2) is a face of the primitive in its winding; (v1, v0, v3) the other face, welded by position
    face_set = {tuple(np.roll(f, -np.argmin(f))) for f in cube["faces"].tolist()}
    for (v0, v1), (v2, _) in zip(edges.tolist(), opposite.tolist()):
        tri = [v0, v1, v2]
        assert tuple(np.roll(tri, -int(np.argmin(tri)))) in face_set


def opposite_from_triangles(faces: np.ndarray, positions: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """v2, v3 of each edge rebuilt as a reader does without oppositeVertices: v2 the third vertex of the face holding
    (v0, v1) in its winding, v3 that of the face holding (v1, v0) by position (this cube's copies are exact); 65535
    where no face has it."""
    _, weld = np.unique(positions, axis=0, return_inverse=True)
    weld = weld.reshape(-1)
    by_index, by_position = {}, {}
    for f in faces.tolist():
        for k in range(3):
            a, b, c = f[k], f[(k + 1) % 3], f[(k + 2) % 3]
            by_index[(a, b)] = c
            by_position.setdefault((weld[a], weld[b]), c)
    return np.array([[by_index[(v0, v1)], by_position.get((weld[v1], weld[v0]), 0xFFFF)]
                     for v0, v1 in edges.tolist()], np.int64)


def test_opposite_vertices_are_left_out_by_default_and_rebuilt_from_the_triangles(cube, tmp_path):
    """Compact by default: oppositeVertices (as large as the edge list) only on request; what it holds is what the
    triangles and the edge list give, on the closed cube and on the open one (65535 beyond its rim)."""
    _, doc = bake_file(split_cube(), tmp_path, "plain")
    plain = primitive_data(doc)
    assert "oppositeVertices" not in plain["ext"] and "edges" in plain["ext"]
    np.testing.assert_array_equal(plain["edges"], cube["edges"])
    rebuilt = opposite_from_triangles(plain["faces"], plain["positions"], plain["edges"].astype(np.int64))
    np.testing.assert_array_equal(rebuilt, cube["oppositeVertices"].astype(np.int64))
    _, doc = bake_file(split_cube(open_top=True), tmp_path, "open", {"opposite_vertices": True})
    open_cube = primitive_data(doc)
    rebuilt = opposite_from_triangles(open_cube["faces"], open_cube["positions"], open_cube["edges"].astype(np.int64))
    np.testing.assert_array_equal(rebuilt, open_cube["oppositeVertices"].astype(np.int64))
    assert np.count_nonzero(rebuilt[:, 1] == 0xFFFF) == 4


def test_open_cube_has_4_boundary_edges(tmp_path):
    out, doc = bake_file(split_cube(open_top=True), tmp_path, "open", {"opposite_vertices": True})
    data = primitive_data(doc)
    flags = data["flags"].astype(np.int64)
    assert np.count_nonzero(flags & E.BOUNDARY) == 4 and data["ext"]["counts"]["boundary"] == 4
    assert np.count_nonzero(flags & E.CREASE) == 8
    pos, edges = data["positions"], data["edges"].astype(np.int64)
    boundary = edges[(flags & E.BOUNDARY) != 0]
    np.testing.assert_allclose(pos[boundary][..., 2], 0.5)  # the rim of the missing top face
    assert np.all(data["oppositeVertices"][(flags & E.BOUNDARY) != 0][:, 1] == 0xFFFF)
    # the shell is pinned to the open rim: _OUTLINE_NORMAL zero on every copy of the 4 rim corners, unit elsewhere
    length = np.linalg.norm(data["outline"], axis=1)
    on_rim = np.isin(np.arange(len(pos)), boundary) | np.isclose(pos[:, 2], 0.5)
    assert on_rim.sum() >= 4 and np.all(length[on_rim] == 0.0) and np.allclose(length[~on_rim], 1.0)
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0

    def half_length(d, prim):
        prim["attributes"]["_OUTLINE_NORMAL"] = d.add_accessor((data["outline"] * 0.5).astype(np.float32))

    assert "BAKER_EDGES_OUTLINE_NOT_UNIT" in _codes(_corrupt(out, tmp_path / "half.glb", half_length))


# ---------------------------------------------------------------------------------------------------------- fandisk
@pytest.mark.skipif(not (MESHES / "fandisk.obj").is_file(), reason="shared test meshes not present")
def test_fandisk_crease_count_matches_trimesh(tmp_path):
    reference = trimesh.load(str(MESHES / "fandisk.obj"))  # process=True: vertices merged
    angles = reference.face_adjacency_angles
    truth = int(np.count_nonzero(angles > math.radians(60.0)))
    assert truth > 100
    out = tmp_path / "fandisk.glb"
    save(baker.bake(str(MESHES / "fandisk.obj"), bakes=["edges"]), out)
    doc = GltfDocument.load(out)
    data = primitive_data(doc)
    assert data["ext"]["counts"]["crease"] == truth
    assert np.count_nonzero(data["flags"].astype(np.int64) & E.CREASE) == truth
    # the dihedral angles are not stored by default; derived from the triangles as a reader does, those of all
    # interior edges agree with trimesh's (as multisets)
    assert "dihedralAngles" not in data["ext"]
    derived = E.dihedral_angles_of(data["positions"], data["faces"], data["edges"])
    interior = (data["flags"].astype(np.int64) & (E.BOUNDARY | E.NON_MANIFOLD)) == 0
    ours = np.sort(np.abs(derived[interior]))
    np.testing.assert_allclose(ours, np.sort(angles), atol=1e-4)  # float32 positions, arccos near 0
    # and they are what the bake stores on request (--edges-dihedral-angles true), sign included
    _, doc = bake_file(trimesh.load(str(MESHES / "fandisk.obj")), tmp_path, "stored", {"dihedral_angles": True})
    stored = primitive_data(doc)
    np.testing.assert_allclose(E.dihedral_angles_of(stored["positions"], stored["faces"], stored["edges"]),
                               stored["dihedralAngles"], atol=1e-5)


# ---------------------------------------------------------------------------------------------------------- contours
def _closed_meshes():
    meshes = [("icosphere", trimesh.creation.icosphere(3)), ("torus", trimesh.creation.torus(1.0, 0.35)),
              ("cube", split_cube())]
    if SPOT.is_file():
        meshes.append(("spot", trimesh.load(str(SPOT), process=False, force="mesh")))
    return meshes


@pytest.mark.parametrize("name,mesh", _closed_meshes(), ids=lambda x: x if isinstance(x, str) else "")
def test_every_vertex_touches_an_even_number_of_contour_edges(name, mesh):
    analysis = E.analyze_mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    assert analysis.counts()["boundary"] == 0 and analysis.counts()["nonManifold"] == 0
    rng = np.random.default_rng(4)
    center = analysis.welded.mean(0)
    size = float(np.linalg.norm(np.ptp(analysis.welded, axis=0)))
    total = 0
    for _ in range(12):  # random perspective views from outside and inside, and orthographic views
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        for kwargs in ({"eye": center + d * size * rng.uniform(0.1, 3.0)}, {"direction": d}):
            contour = E.contour_edges(analysis, **kwargs)
            degree = np.bincount(analysis.topology.edges[contour].reshape(-1), minlength=len(analysis.welded))
            assert np.all(degree % 2 == 0)
            total += int(contour.sum())
    assert total > 0
    # eq. 15.1 evaluated literally at each contour edge's midpoint agrees with the per-face evaluation
    eye = center + np.array([0.3, 0.4, 2.0]) * size
    contour = E.contour_edges(analysis, eye=eye)
    n, _ = E.face_normals(analysis.welded, analysis.faces_welded)
    topo = analysis.topology
    f0, f1 = topo.first_halfedge // 3, topo.second_halfedge // 3
    mid = analysis.welded[topo.edges].mean(axis=1)
    v = eye - mid
    literal = np.einsum("ij,ij->i", n[f0], v) * np.einsum("ij,ij->i", n[f1], v) < 0
    assert np.array_equal(literal, contour)


# ---------------------------------------------------------------------------------------------------------- EXT
def test_pack_visibility_matches_the_spec_examples():
    assert E.pack_visibility(np.array([[2, 0, 1], [0, 2, 0]])).tolist() == [18, 2]
    assert E.pack_visibility(np.array([[2, 0, 2], [3, 2, 0]])).tolist() == [226, 2]
    codes = np.random.default_rng(1).integers(0, 4, (37, 3))
    packed = E.pack_visibility(codes)
    assert len(packed) == math.ceil(6 * 37 / 8)
    assert np.array_equal(E.unpack_visibility(packed, 37), codes)


def test_sphere_silhouette_mates_close_each_edge(tmp_path):
    out, doc = bake_file(trimesh.creation.icosphere(2), tmp_path, "sphere")
    data = primitive_data(doc)
    codes, faces = data["codes"], data["faces"]
    assert set(np.unique(codes)) == {0, 1}  # smooth closed surface: every edge is a potential silhouette
    n_edges = len(faces) * 3 // 2
    assert np.count_nonzero(codes == 1) == n_edges and len(data["mates"]) == n_edges
    # mate n belongs to the n-th 1 in bitfield order: (v_k+1, v_k, mate) is a triangle of the mesh
    t, k = np.nonzero(codes == 1)
    a, b = faces[t, k], faces[t, (k + 1) % 3]
    tris = {tuple(np.roll(f, -np.argmin(f))) for f in faces.tolist()}
    for x, y, z in zip(b.tolist(), a.tolist(), data["mates"].astype(np.int64).tolist()):
        tri = [x, y, z]
        assert tuple(np.roll(tri, -int(np.argmin(tri)))) in tris
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]


def _corrupt(src: Path, dst: Path, edit) -> dict:
    doc = GltfDocument.load(src)
    edit(doc, doc.json["meshes"][0]["primitives"][0])
    doc.save(dst)
    return validate_file(dst, khronos=False)


def _codes(report) -> set:
    return {m["code"] for m in report["issues"]["messages"] if m["severity"] == 0}


def test_validate_checks_bit_count_and_accessors(tmp_path):
    out, doc = bake_file(split_cube(), tmp_path, "cube", {"dihedral_angles": True})
    assert validate_file(out, khronos=False)["issues"]["numErrors"] == 0
    data = primitive_data(doc)
    packed = E.pack_visibility(data["codes"])

    def short_bitfield(d, prim):
        prim["extensions"][X.EXT_VISIBILITY]["visibility"] = d.add_accessor(packed[:-1], target=None)

    assert "EDGE_VISIBILITY_BIT_COUNT" in _codes(_corrupt(out, tmp_path / "a.glb", short_bitfield))
    assert cli_main(["validate", "--no-khronos", "-q", str(tmp_path / "a.glb")]) == 1

    def twice_hard(d, prim):
        codes = data["codes"].copy()
        codes[codes == 3] = 2
        prim["extensions"][X.EXT_VISIBILITY]["visibility"] = d.add_accessor(E.pack_visibility(codes), target=None)

    assert "EDGE_VISIBILITY_REPEATED" in _codes(_corrupt(out, tmp_path / "b.glb", twice_hard))

    def edges_out_of_range(d, prim):
        prim["extensions"]["BAKER_edges"]["edges"] = d.add_accessor((data["edges"] + 100).astype(np.uint16),
                                                                    target=None)

    assert "BAKER_EDGES_INDEX_OOB" in _codes(_corrupt(out, tmp_path / "c.glb", edges_out_of_range))

    def flags_as_float(d, prim):
        prim["extensions"]["BAKER_edges"]["flags"] = d.add_accessor(data["flags"].astype(np.float32), target=None)

    assert "BAKER_EDGES_ACCESSOR_FORMAT" in _codes(_corrupt(out, tmp_path / "d.glb", flags_as_float))

    def short_angles(d, prim):
        prim["extensions"]["BAKER_edges"]["dihedralAngles"] = d.add_accessor(data["dihedralAngles"][:-1],
                                                                             target=None)

    assert "BAKER_EDGES_ACCESSOR_COUNT" in _codes(_corrupt(out, tmp_path / "e.glb", short_angles))

    def unknown_property(d, prim):
        prim["extensions"]["BAKER_edges"]["colour"] = 1

    assert "BAKER_SCHEMA" in _codes(_corrupt(out, tmp_path / "f.glb", unknown_property))


# ---------------------------------------------------------------------------------------------------------- material/UV
def test_material_and_uv_seam_edges():
    sphere = trimesh.creation.uv_sphere(count=[16, 16])
    # two materials meeting at a latitude ring: exactly the ring's edges (a closed loop) are material edges
    ring = np.unique(np.round(sphere.vertices[:, 2], 9))[8]
    upper = sphere.triangles_center[:, 2] > ring
    analysis = E.analyze_mesh(sphere.vertices, sphere.faces, face_group=upper.astype(int))
    material = (analysis.flags & E.MATERIAL) != 0
    ends = analysis.welded[analysis.topology.edges[material]]
    on_ring = np.count_nonzero(np.abs(analysis.welded[:, 2] - ring) < 1e-9)
    assert material.sum() == on_ring > 8 and np.allclose(ends[..., 2], ring, atol=1e-9)
    # texture coordinates cut along the meridian phi = 0: the corners there disagree (u = 0 vs u = 1)
    phi = np.mod(np.arctan2(sphere.vertices[:, 1], sphere.vertices[:, 0]), 2 * math.pi)
    phi[np.abs(sphere.vertices[:, 1]) < 1e-12] = np.where(sphere.vertices[np.abs(sphere.vertices[:, 1]) < 1e-12, 0] > 0,
                                                          0.0, math.pi)
    corner_phi = phi[sphere.faces]
    wrap = (corner_phi.max(1) - corner_phi.min(1)) > math.pi
    corner_phi = np.where(wrap[:, None] & (corner_phi < math.pi / 2), corner_phi + 2 * math.pi, corner_phi)
    uv = np.stack([corner_phi / (2 * math.pi), np.zeros_like(corner_phi)], axis=-1)
    analysis = E.analyze_mesh(sphere.vertices, sphere.faces, corner_uv=uv)
    seam = (analysis.flags & E.UV_SEAM) != 0
    ends = analysis.welded[analysis.topology.edges[seam]]
    # away from the poles (where every face has its own u), the seam edges are exactly the meridian's edges
    pole = np.any(np.abs(ends[..., 2]) > 1 - 1e-9, axis=1)
    ends = ends[~pole]
    assert np.allclose(ends[..., 1], 0.0, atol=1e-9) and np.all(ends[..., 0] >= -1e-9)
    meridian = np.count_nonzero((np.abs(analysis.welded[:, 1]) < 1e-9) & (analysis.welded[:, 0] > 1e-9))
    assert len(ends) == meridian - 1 > 10


def test_seams_of_vertex_attributes_are_looked_for_only_where_positions_are_split():
    """A function for the corner values (the edges bake's vertex attributes) is called only when the weld merges
    vertices, and then flags what the array does; on a mesh whose vertices are all distinct it is never called."""
    sphere = trimesh.creation.icosphere(2)
    calls = []

    def corners(values):
        def gather():
            calls.append(1)
            return values
        return gather

    normals = np.asarray(sphere.vertex_normals)[sphere.faces]
    analysis = E.analyze_mesh(sphere.vertices, sphere.faces, corner_normals=corners(normals))
    assert not calls and not np.any(analysis.flags & E.NORMAL_SEAM)
    # the same sphere with its faces split apart (flat shaded): every edge is a normal seam, with or without a function
    flat_positions = sphere.vertices[sphere.faces].reshape(-1, 3)
    flat_faces = np.arange(len(flat_positions)).reshape(-1, 3)
    flat_normals = np.repeat(np.asarray(sphere.face_normals)[:, None], 3, axis=1)
    lazy = E.analyze_mesh(flat_positions, flat_faces, corner_normals=corners(flat_normals))
    eager = E.analyze_mesh(flat_positions, flat_faces, corner_normals=flat_normals)
    assert calls == [1] and np.array_equal(lazy.flags, eager.flags)
    assert np.count_nonzero(lazy.flags & E.NORMAL_SEAM) == len(sphere.edges_unique)


# ---------------------------------------------------------------------------------------------------------- lines
def _svg_paths(text: str) -> list[tuple[str, np.ndarray, bool]]:
    out = []
    for cls, body in re.findall(r'<g class="([^"]+)"[^>]*>(.*?)</g>', text, re.S):
        for d in re.findall(r'd="([^"]+)"', body):
            pts = np.array([[float(a), float(b)] for a, b in re.findall(r"(-?[\d.]+) (-?[\d.]+)", d)])
            out.append((cls, pts, d.rstrip().endswith("Z")))
    return out


def test_sphere_svg_is_one_closed_loop_at_the_projected_radius(tmp_path):
    src = tmp_path / "sphere.glb"
    trimesh.creation.icosphere(4, radius=1.0).export(str(src))
    out = tmp_path / "sphere.svg"
    assert cli_main(["lines", str(src), "-o", str(out), "--camera", "0,0,4", "--target", "0,0,0", "--fov", "40",
                     "--size", "512x512", "--hidden"]) == 0
    paths = _svg_paths(out.read_text())
    assert len(paths) == 1
    cls, pts, closed = paths[0]
    assert cls == "contour visible" and closed
    expected = math.tan(math.asin(1.0 / 4.0)) / math.tan(math.radians(20.0)) * 256.0
    radius = np.linalg.norm(pts - 256.0, axis=1)
    assert np.all(np.abs(radius / expected - 1.0) < 0.005)
    # the loop goes once around the centre
    angle = np.unwrap(np.arctan2(pts[:, 1] - 256.0, pts[:, 0] - 256.0))
    assert abs(abs(angle[-1] - angle[0]) - 2 * math.pi) < 0.1


def test_hidden_lines_of_a_cube_split_where_visibility_changes(tmp_path):
    src = tmp_path / "cube.glb"
    split_cube().export(str(src), include_normals=True)
    out = tmp_path / "cube.svg"
    # a generic view of a cube shows 9 edges (6 contour + 3 crease) and hides 3
    assert cli_main(["lines", str(src), "-o", str(out), "--camera", "2.5,1.9,3.1", "--target", "0,0,0",
                     "--hidden", "--size", "400x400"]) == 0
    paths = _svg_paths(out.read_text())
    visible = [p for p in paths if "visible" in p[0]]
    hidden = [p for p in paths if "hidden" in p[0]]
    visible_len = sum(np.linalg.norm(np.diff(p[1], axis=0), axis=1).sum() + (np.linalg.norm(p[1][0] - p[1][-1])
                                                                             if p[2] else 0) for p in visible)
    hidden_len = sum(np.linalg.norm(np.diff(p[1], axis=0), axis=1).sum() for p in hidden)
    assert {p[0] for p in visible} == {"contour visible", "crease visible"}
    assert hidden and all(p[0] == "crease hidden" for p in hidden)
    # brute-force truth: project the 12 cube edges; the 3 edges at the corner facing away are hidden
    from baker.techniques.edges.line_drawing import Camera

    cam = Camera(np.array([2.5, 1.9, 3.1]), np.zeros(3), np.array([0.0, 1.0, 0.0]), 400, 400, math.radians(40))
    corners = np.array([[x, y, z] for x in (-.5, .5) for y in (-.5, .5) for z in (-.5, .5)])
    far = np.argmin(corners @ np.array([2.5, 1.9, 3.1]))
    px, _ = cam.project(corners)
    lengths_hidden = [np.linalg.norm(px[far] - px[j]) for j in range(8)
                      if np.count_nonzero(corners[j] != corners[far]) == 1]
    assert abs(hidden_len - sum(lengths_hidden)) / sum(lengths_hidden) < 0.03
    all_len = sum(np.linalg.norm(px[i] - px[j]) for i in range(8) for j in range(i + 1, 8)
                  if np.count_nonzero(corners[i] != corners[j]) == 1)
    assert abs(visible_len - (all_len - sum(lengths_hidden))) / all_len < 0.03


def test_lines_rejects_bad_input(tmp_path, capsys):
    src = tmp_path / "cube.glb"
    split_cube().export(str(src))
    assert cli_main(["lines", str(src), "-o", str(tmp_path / "x.png")]) == 2
    assert cli_main(["lines", str(src), "-o", str(tmp_path / "x.svg"), "--camera", "nosuchcamera"]) == 2
    assert not (tmp_path / "x.svg").exists()


# ---------------------------------------------------------------------------------------------------------- misc
def test_weld_matches_the_asset_weld_and_is_deterministic(tmp_path):
    from baker.geometry.welding import weld

    mesh = split_cube()
    rng = np.random.default_rng(0)
    pts = np.concatenate([mesh.vertices, rng.normal(size=(500, 3))])[rng.permutation(524)]
    a, ia = weld(pts)
    b, ib = E.weld_positions(pts)
    assert np.array_equal(a, b) and np.array_equal(ia, ib)
    src = tmp_path / "s.glb"
    trimesh.creation.icosphere(2).export(str(src))
    outs = []
    for i in range(2):
        out = tmp_path / f"o{i}.glb"
        save(baker.bake(str(src), bakes=["edges"], options={"edges": {"fins": True}}), out)
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]


def test_usd_gets_outline_normals_and_basis_curves(tmp_path):
    from pxr import Usd, UsdGeom

    out, doc = bake_file(split_cube(), tmp_path, "cube")
    usd = tmp_path / "cube.usda"
    save(baker.bake(str(out), bakes=[]), usd)
    stage = Usd.Stage.Open(str(usd))
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    assert meshes and meshes[0].GetAttribute("primvars:baker:outline_normal").HasValue()
    stage = Usd.Stage.CreateInMemory()
    curves = X.usd_basis_curves(stage, "/Edges", doc, 0, 0)
    assert list(curves.GetCurveVertexCountsAttr().Get()) == [2] * 12
    points = np.array(curves.GetPointsAttr().Get())
    assert np.allclose(np.abs(points), 0.5)


def test_schema_accepts_what_the_writer_writes_and_the_readme_example(cube):
    import json

    from jsonschema import Draft202012Validator

    from baker.data import SCHEMA_ROOT

    schema = json.loads((SCHEMA_ROOT / "BAKER_edges" / "schema" / "mesh.primitive.BAKER_edges.schema.json").read_text())
    validator = Draft202012Validator(schema)
    assert not list(validator.iter_errors(cube["ext"]))
    readme = (SCHEMA_ROOT / "BAKER_edges" / "README.md").read_text()
    example = json.loads(readme.split("```json")[1].split("```")[0])
    for prim in example["meshes"][0]["primitives"]:
        assert not list(validator.iter_errors(prim["extensions"]["BAKER_edges"]))
    assert list(validator.iter_errors({"finsOf": 0, "creaseAngle": 1.0}))  # a fin primitive carries only finsOf
    assert list(validator.iter_errors({"creaseAngle": 1.0}))  # a source primitive needs its settings


def test_parallel_passes_match_the_separate_definitions_at_any_thread_count():
    """analyze_mesh fuses classification, material and quad-diagonal flags into one parallel pass and splits the
    outline normals and the per-primitive pass over threads: the same edges and bits as the separate functions and
    a serial numpy reference, and byte-identical arrays with 1 thread and with all."""
    import numba

    sphere = trimesh.creation.icosphere(6)  # 81,920 faces: enough for several chunks per thread
    box = trimesh.creation.box().subdivide().subdivide()  # quads split in two: quad diagonals
    mesh = trimesh.util.concatenate([sphere, box])
    v, f = np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64)
    group = (np.arange(len(f)) // 7) % 3  # material edges inside both shells
    welded, inverse = E.weld(v, 1e-6)
    fw = inverse[f]
    # topology against numpy: unique sorted vertex pairs, and every half-edge maps to its pair
    topo = E.edge_topology(fw, len(welded))
    pairs = np.sort(np.stack([fw, np.roll(fw, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    assert np.array_equal(topo.edges, np.unique(pairs, axis=0))
    assert np.array_equal(topo.edges[topo.edge_of_halfedge], pairs)
    # outline normals against a serial numpy sum (np.add.at adds in face order)
    a, b, c = (welded[fw[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    ref = np.zeros_like(welded)
    for k in range(3):
        p, q, r = (welded[fw[:, (k + j) % 3]] for j in range(3))
        e, g = q - p, r - p
        w = np.arctan2(np.linalg.norm(np.cross(e, g), axis=1), np.einsum("ij,ij->i", e, g))
        np.add.at(ref, fw[:, k], w[:, None] * n)
    ref /= np.linalg.norm(ref, axis=1, keepdims=True)

    def run():
        m = E.analyze_mesh(v, f, face_group=group)
        return m, [E.primitive_edges(m, r, (0, len(v))) for r in ((0, len(f)), (1000, len(f) - 5000))]

    settings = E.EdgeSettings()
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        serial, serial_prims = run()
    finally:
        numba.set_num_threads(threads)
    mesh_edges, prims = run()
    classes = E.classify_edges(welded, fw, topo, crease_angle=settings.crease_angle,
                               planar_angle=settings.planar_angle)
    separate = classes.flags | E.material_flags(topo, group)
    separate |= E.quad_diagonal_flags(welded, fw, topo, separate, classes.angle, settings.quad_angle)
    assert np.array_equal(mesh_edges.flags, separate) and np.array_equal(mesh_edges.angle, classes.angle)
    assert np.count_nonzero(separate & E.QUAD_DIAGONAL) > 0 and np.count_nonzero(separate & E.MATERIAL) > 0
    assert np.allclose(mesh_edges.outline_normals, ref[inverse], atol=1e-12)
    assert np.array_equal(mesh_edges.flags, serial.flags)
    assert mesh_edges.outline_normals.tobytes() == serial.outline_normals.tobytes()
    for mine, theirs in zip(prims, serial_prims):
        for name in ("visibility_codes", "silhouette_mates", "edges", "opposite", "flags", "angle", "wireframe_mask"):
            assert getattr(mine, name).tobytes() == getattr(theirs, name).tobytes(), name
    # the sub-range's edges are those its faces draw, each once
    sub = prims[1]
    assert len(sub.edges) == len(np.unique(np.sort(inverse[sub.edges + 0], axis=1), axis=0))
