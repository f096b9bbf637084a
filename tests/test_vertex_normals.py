"""Area-weighted vertex normals (baker.geometry.normals): bit-identical to the np.add.at sums they replaced, and
right on analytic shapes."""
from __future__ import annotations

import numpy as np
import trimesh

from baker.geometry.normals import vertex_normals


def add_at_reference(vertices, faces):
    """The previous implementation: face cross products summed with np.add.at corner by corner, then normalized."""
    fn = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    out = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(out, faces[:, k], fn)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return np.where(length > 1e-30, out / np.maximum(length, 1e-30), np.array([0.0, 0.0, 1.0]))


def test_bit_identical_to_the_add_at_sums():
    rng = np.random.default_rng(7)
    for trial in range(30):
        n = int(rng.integers(3, 300))
        vertices = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-6, 6)
        faces = rng.integers(0, n, (int(rng.integers(1, 600)), 3))
        vertices[: n // 10] = 0.0  # some degenerate (zero-area) faces and +Z fallbacks
        assert np.array_equal(vertex_normals(vertices, faces), add_at_reference(vertices, faces)), trial
    # a real mesh with many faces per vertex, integer and read-only inputs as the Asset hands them over
    sphere = trimesh.creation.icosphere(4)
    vertices = np.array(sphere.vertices)
    faces = np.array(sphere.faces, np.int32)
    vertices.setflags(write=False)
    assert np.array_equal(vertex_normals(vertices, faces), add_at_reference(vertices, faces.astype(np.int64)))


def test_sphere_normals_are_radial_and_degenerate_vertices_get_plus_z():
    sphere = trimesh.creation.icosphere(3, radius=2.0)
    normals = vertex_normals(np.asarray(sphere.vertices), np.asarray(sphere.faces))
    radial = sphere.vertices / np.linalg.norm(sphere.vertices, axis=1, keepdims=True)
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    assert np.einsum("ij,ij->i", normals, radial).min() > 0.999
    # an unused vertex and a zero-area triangle's vertices: +Z; a mesh without faces: all +Z
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5], [2, 2, 2]], np.float64)
    normals = vertex_normals(vertices, np.array([[0, 1, 2], [4, 4, 4]]))
    assert np.allclose(normals[:3], [0, 0, 1]) and np.allclose(normals[3:], [0, 0, 1])
    flipped = vertex_normals(vertices, np.array([[0, 2, 1]]))
    assert np.allclose(flipped[:3], [0, 0, -1])
    assert np.array_equal(vertex_normals(vertices, np.zeros((0, 3), np.int64)), np.tile([0.0, 0.0, 1.0], (5, 1)))


def test_angle_weighted_normals_match_trimesh():
    """The compiled angle-weighted normals the readers give a file without normals
    (baker.geometry.angle_normals.vertex_normals) against trimesh's own (an independent implementation, numpy):
    random meshes with zero-area and sliver faces and unused vertices, at scales 1e-6 to 1e5."""
    from baker.geometry.angle_normals import seamless_vertex_normals, vertex_normals as angle_weighted

    rng = np.random.default_rng(11)
    for trial in range(30):
        n = int(rng.integers(3, 300))
        vertices = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-6, 6)
        vertices[: n // 10] = vertices[0]  # zero-area faces: they add nothing
        faces = rng.integers(0, n, (int(rng.integers(1, 600)), 3))
        reference = trimesh.Trimesh(vertices, faces, process=False).vertex_normals
        assert np.abs(angle_weighted(vertices, faces) - reference).max() < 1e-12, trial
    sphere = trimesh.creation.icosphere(4)
    vertices, faces = np.array(sphere.vertices), np.array(sphere.faces, np.int32)
    assert np.abs(angle_weighted(vertices, faces) - trimesh.Trimesh(vertices, faces, process=False).vertex_normals
                  ).max() < 1e-12
    # as the PLY reader asks for them: float32, unit, split copies of a position welded, +Z for an unused vertex
    split = np.vstack([vertices, vertices[:10], [[9.0, 9.0, 9.0]]]).astype(np.float32)
    split_faces = faces.copy()
    split_faces[:20][np.isin(split_faces[:20], np.arange(10))] += len(vertices)  # the first faces use the copies
    (normals,) = seamless_vertex_normals([(split, split_faces, None)], np.float32)
    expected = trimesh.Trimesh(vertices, faces, process=False).vertex_normals
    assert normals.dtype == np.float32
    assert np.abs(normals[:len(vertices)] - expected).max() < 1e-6
    assert np.array_equal(normals[len(vertices):-1], normals[:10]) and np.array_equal(normals[-1], [0, 0, 1])
