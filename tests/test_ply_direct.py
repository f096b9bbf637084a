"""The direct binary-PLY reader (issue 18): what the file has reaches the document (positions, normals, UVs, exactly
as float32), a file without normals gets the smooth normals the other readers compute, and anything else goes through
trimesh, which keeps it."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh

from baker.errors import BakerError
from baker import readers
from baker.readers.ply import read_ply_triangles


def write_ply(path, vertices: dict, faces, fmt="binary_little_endian", count_type="uchar", index_type="int"):
    """A PLY written here from its spec (independent of trimesh's writer): ``vertices`` maps property -> column."""
    names = list(vertices)
    n = len(vertices[names[0]])
    head = f"ply\nformat {fmt} 1.0\nelement vertex {n}\n"
    head += "".join(f"property float {name}\n" for name in names)
    head += f"element face {len(faces)}\nproperty list {count_type} {index_type} vertex_indices\nend_header\n"
    order = ">" if fmt == "binary_big_endian" else "<"
    vertex = np.empty(n, [(name, order + "f4") for name in names])
    for name in names:
        vertex[name] = vertices[name]
    codes = {"uchar": "u1", "int": "i4", "uint": "u4", "ushort": "u2"}
    face = np.empty(len(faces), [("n", order + codes[count_type]), ("v", order + codes[index_type], 3)])
    face["n"], face["v"] = 3, faces
    path.write_bytes(head.encode() + vertex.tobytes() + face.tobytes())
    return path


TETRA = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def attributes(asset):
    prim = asset.doc.json["meshes"][0]["primitives"][0]
    return {k: asset.doc.accessor(v) for k, v in prim["attributes"].items()}, asset.doc.accessor(prim["indices"])


@pytest.mark.parametrize("fmt", ["binary_little_endian", "binary_big_endian"])
def test_positions_and_faces_only_get_smooth_normals(tmp_path, fmt):
    path = write_ply(tmp_path / "t.ply", {"x": TETRA[:, 0], "y": TETRA[:, 1], "z": TETRA[:, 2]}, FACES, fmt=fmt)
    attrs, indices = attributes(readers.read(path))
    assert sorted(attrs) == ["NORMAL", "POSITION"]
    assert attrs["POSITION"].dtype == np.float32 and np.array_equal(attrs["POSITION"], TETRA)
    assert np.array_equal(indices.reshape(-1, 3), FACES)
    # the corner at the origin sees three right angles: its angle-weighted normal is -(1, 1, 1)/sqrt(3)
    assert np.allclose(attrs["NORMAL"][0], -np.ones(3) / np.sqrt(3), atol=1e-6)
    assert np.allclose(np.linalg.norm(attrs["NORMAL"], axis=1), 1, atol=1e-6)


def test_computed_normals_match_the_ascii_and_obj_readers(tmp_path):
    """A bunny-like irregular mesh written as binary PLY, ASCII PLY (trimesh's path) and OBJ without ``vn``: the
    three readers give the same smooth normals, so the format a mesh comes in does not change its shading."""
    sphere = trimesh.creation.icosphere(subdivisions=2)
    rng = np.random.default_rng(3)
    vertices = (sphere.vertices * (1 + 0.2 * rng.random((len(sphere.vertices), 1)))).astype(np.float32)
    faces = sphere.faces
    columns = {"x": vertices[:, 0], "y": vertices[:, 1], "z": vertices[:, 2]}
    binary, _ = attributes(readers.read(write_ply(tmp_path / "b.ply", columns, faces)))
    obj = tmp_path / "m.obj"
    obj.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices.tolist())
                   + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist()))
    from_obj, _ = attributes(readers.read(obj))
    assert np.allclose(binary["POSITION"], from_obj["POSITION"])
    assert np.allclose(binary["NORMAL"], from_obj["NORMAL"], atol=1e-6)
    # an independent reference: the angle-weighted normal summed here from each face's corner angles
    v = vertices.astype(np.float64)
    reference = np.zeros_like(v)
    for face in faces:
        p = v[face]
        n = np.cross(p[1] - p[0], p[2] - p[0])
        n /= np.linalg.norm(n)
        for k in range(3):
            a, b = p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]
            angle = np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1))
            reference[face[k]] += angle * n
    reference /= np.linalg.norm(reference, axis=1, keepdims=True)
    assert np.allclose(binary["NORMAL"], reference, atol=1e-5)


def test_normals_and_uvs_survive(tmp_path):
    normals = TETRA - 0.25
    uv = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0.25]], np.float32)
    columns = {"x": TETRA[:, 0], "y": TETRA[:, 1], "z": TETRA[:, 2], "nx": normals[:, 0], "ny": normals[:, 1],
               "nz": normals[:, 2], "s": uv[:, 0], "t": uv[:, 1]}
    path = write_ply(tmp_path / "n.ply", columns, FACES, index_type="uint", count_type="ushort")
    attrs, _ = attributes(readers.read(path))
    assert np.array_equal(attrs["NORMAL"], normals.astype(np.float32))
    # PLY's t runs up the image, glTF's v down (what trimesh's reader and GLB exporter did before)
    assert np.allclose(attrs["TEXCOORD_0"], np.column_stack([uv[:, 0], 1 - uv[:, 1]]))
    # the same file through trimesh gives the same positions, normals and UVs
    ref = trimesh.load(path, process=False)
    assert np.allclose(ref.vertex_normals, normals, atol=1e-6)
    assert np.allclose(ref.visual.uv, uv)


def test_other_properties_and_polygons_go_through_trimesh(tmp_path):
    colored = tmp_path / "c.ply"
    trimesh.Trimesh(TETRA, FACES, vertex_colors=np.tile([255, 0, 0, 255], (4, 1)), process=False).export(colored)
    assert read_ply_triangles(colored) is None
    prim = readers.read(colored).doc.json["meshes"][0]["primitives"][0]
    assert "COLOR_0" in prim["attributes"]  # kept, as before
    quads = tmp_path / "q.ply"
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")
    quads.write_bytes(head.encode() + TETRA.tobytes() + bytes([4]) + np.array([0, 1, 2, 3], "<i4").tobytes())
    assert read_ply_triangles(quads) is None
    assert len(readers.read(quads).primitive(0, 0).faces) == 2  # trimesh triangulates the quad


def test_bad_index_and_nan_are_refused_in_one_line(tmp_path):
    bad = write_ply(tmp_path / "i.ply", {"x": TETRA[:, 0], "y": TETRA[:, 1], "z": TETRA[:, 2]},
                    np.array([[0, 1, 9]]))
    with pytest.raises(BakerError, match="face 0: vertex index out of range"):
        readers.read(bad)
    v = TETRA.copy()
    v[2, 1] = np.nan
    nan = write_ply(tmp_path / "nan.ply", {"x": v[:, 0], "y": v[:, 1], "z": v[:, 2]}, FACES)
    with pytest.raises(BakerError, match="vertex 2: property 'y'"):
        readers.read(nan)
