"""The compiled weld against numpy's own arithmetic and a brute-force merge."""
import numpy as np

from baker import readers
from baker.geometry.welding import position_cells
from baker.geometry.welding import weld


def numpy_cells(positions, cell):
    with np.errstate(all="ignore"):
        return np.round(positions / cell).astype(np.int64)


def test_cells_equal_numpy_round_and_cast_including_ties_and_overflow():
    rng = np.random.default_rng(3)
    ties = np.array([[0.5, 1.5, 2.5], [-0.5, -1.5, -2.5], [1e30, -1e30, 9.3e18], [9.2e18, 1e300, -1e300]])
    positions = np.concatenate([rng.normal(size=(5000, 3)) * 10, ties])
    for cell in (1e-6, 0.5, 1.0, 3e-7):
        assert np.array_equal(position_cells(positions, cell), numpy_cells(positions, cell))


def test_weld_merges_like_brute_force_and_returns_the_input_when_nothing_merges():
    rng = np.random.default_rng(4)
    base = rng.random((300, 3))
    positions = np.concatenate([base, base[::3] + 1e-9])  # near-copies of every third vertex
    welded, inverse = weld(positions)
    assert len(welded) == 300
    # brute force: first occurrence of each rounded cell
    diag = np.linalg.norm(positions.max(0) - positions.min(0))
    cells = [tuple(c) for c in numpy_cells(positions, diag * 1e-6)]
    first = {}
    for i, c in enumerate(cells):
        first.setdefault(c, i)
    ids = {c: k for k, c in enumerate(sorted(first, key=first.get))}
    assert np.array_equal(inverse, [ids[c] for c in cells])
    assert np.allclose(welded[inverse], positions, atol=1e-8)
    alone, identity = weld(base)
    assert alone is base and np.array_equal(identity, np.arange(300))


def test_welded_mesh_of_an_unmerged_mesh_keeps_its_faces(tmp_path):
    import trimesh

    path = tmp_path / "sphere.ply"
    trimesh.creation.icosphere(2).export(path)
    asset = readers.read(path)
    mesh = asset.welded(0, [0])
    g = asset.primitive(0, 0)
    assert np.array_equal(mesh.faces, g.faces) and np.array_equal(mesh.positions, g.positions)
    assert np.array_equal(mesh.inverse, np.arange(len(g.positions)))
    vertices, faces = asset.mesh_triangles(0)
    assert np.array_equal(vertices, g.positions) and np.array_equal(faces, g.faces)


def test_assigning_the_default_material_keeps_the_decoded_primitive(tmp_path):
    import trimesh


    from baker.gltf.document import GltfDocument

    sphere = trimesh.creation.icosphere(1)
    path = tmp_path / "sphere.glb"
    # a glTF primitive without a material (mesh files now get baker's explicit dielectric when read)
    GltfDocument.from_triangles(path, "sphere", {"POSITION": sphere.vertices.astype(np.float32)},
                                sphere.faces.reshape(-1), "test").save(path)
    asset = readers.read(path)
    before = asset.primitive(0, 0)
    asset.welded(0, [0])
    assert before.material is None
    groups = asset.material_groups()  # the primitive has no material: a default one is added
    (material,) = groups
    after = asset.primitive(0, 0)
    assert after.material == material and after.positions is before.positions  # moved, not decoded again
    assert not [k for k in asset.cache if k[0] == "welded"]  # keyed by the old material: welded again on demand
    assert asset.welded(0, [0]).geometries[0].material == material
