"""The direct binary-PLY reader (issue 18): what the file has reaches the document (positions, normals, UVs, exactly
as float32), nothing is added (no computed normals), and anything else goes through trimesh, which keeps it."""
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
def test_positions_and_faces_only_no_normals_added(tmp_path, fmt):
    path = write_ply(tmp_path / "t.ply", {"x": TETRA[:, 0], "y": TETRA[:, 1], "z": TETRA[:, 2]}, FACES, fmt=fmt)
    attrs, indices = attributes(readers.read(path))
    assert sorted(attrs) == ["POSITION"]  # nothing computed that the file did not have
    assert attrs["POSITION"].dtype == np.float32 and np.array_equal(attrs["POSITION"], TETRA)
    assert np.array_equal(indices.reshape(-1, 3), FACES)


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
