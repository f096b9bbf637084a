"""The hatching cross field (issue 38, Knöppel et al. 2013) against analytic truth: a torus's principal directions,
Poincaré-Hopf on a sphere and a torus, an artist's combing honoured, independence of the mesh's scale."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh

from baker.geometry.normals import vertex_normals
from baker.techniques.curvature.kernel import principal_curvatures
from baker.geometry.direction_field import anisotropy, cross_field


def torus(R=1.0, r=0.35, nu=120, nv=48):
    """A torus grid with outward normals and, per vertex, the analytic direction along the tube's circle (the
    meridian: curvature 1/r, the largest) and the parallel."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False), np.linspace(0, 2 * np.pi, nv, endpoint=False),
                       indexing="ij")
    u, v = u.reshape(-1), v.reshape(-1)
    positions = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1)
    idx = np.arange(nu * nv).reshape(nu, nv)
    a, b, c = idx, np.roll(idx, -1, 0), np.roll(idx, -1, 1)
    d = np.roll(b, -1, 1)
    faces = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    normals = vertex_normals(positions, faces)
    if np.einsum("ij,ij->i", normals, positions - np.stack([R * np.cos(u), R * np.sin(u), 0 * u], -1)).mean() < 0:
        faces = faces[:, ::-1].copy()
        normals = vertex_normals(positions, faces)
    meridian = np.stack([-np.sin(v) * np.cos(u), -np.sin(v) * np.sin(u), np.cos(v)], -1)
    return positions, faces, normals, meridian


def cross_angle_degrees(field: np.ndarray, reference: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Per vertex, the angle between a cross direction and a reference direction, modulo the cross's 90 degrees."""
    field = field - normals * np.einsum("ij,ij->i", field, normals)[:, None]
    field /= np.linalg.norm(field, axis=1)[:, None]
    reference = reference / np.linalg.norm(reference, axis=1)[:, None]
    angle = np.degrees(np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", field, reference)), 0, 1)))
    return np.minimum(angle, 90 - angle)


def test_torus_field_follows_the_analytic_principal_directions():
    positions, faces, normals, meridian = torus()
    curvature = principal_curvatures(positions, faces)
    field = cross_field(positions, faces, normals, directions=curvature.direction1,
                        strength=anisotropy(curvature.k1, curvature.k2))
    error = cross_angle_degrees(field.direction, meridian, normals)
    assert np.sqrt(np.mean(error ** 2)) < 5.0  # issue 38's bar on the torus (measured: 0.15 degrees)
    assert error.max() < 10.0
    assert len(field.singular_faces) == 0  # a torus's principal directions have no umbilic: no singularity
    # unit tangents
    assert np.allclose(np.linalg.norm(field.direction, axis=1), 1.0)
    assert np.abs(np.einsum("ij,ij->i", field.direction, normals)).max() < 1e-9


@pytest.mark.parametrize("shape", ["sphere", "torus"])
def test_smoothest_field_singularities_sum_to_the_euler_characteristic(shape):
    if shape == "sphere":
        mesh = trimesh.creation.icosphere(4)
        positions, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
        normals, expected = vertex_normals(positions, faces), 2.0
    else:
        positions, faces, normals, _ = torus(nu=60, nv=24)
        expected = 0.0
    field = cross_field(positions, faces, normals)
    assert field.euler_characteristic == pytest.approx(expected)  # Poincaré-Hopf
    if shape == "sphere":
        # the smoothest cross field on a round sphere: eight +1/4 singularities (Knöppel et al. 2013, fig. 1)
        assert sorted(field.singular_index.tolist()) == [1] * 8


def test_combing_is_honoured_where_given_and_smooth_elsewhere():
    mesh = trimesh.creation.icosphere(4)
    positions, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    normals = vertex_normals(positions, faces)
    along_latitude = np.cross([0.0, 0.0, 1.0], positions)  # an artist's combing: around the z axis
    combed = np.abs(positions[:, 2]) < 0.5  # given on a belt around the equator only
    field = cross_field(positions, faces, normals, directions=np.where(combed[:, None], along_latitude, 0.0))
    error = cross_angle_degrees(field.direction[combed], along_latitude[combed], normals[combed])
    assert np.sqrt(np.mean(error ** 2)) < 3.0
    assert field.euler_characteristic == pytest.approx(2.0)  # the singularities moved to the uncombed caps
    caps = np.unique(faces[field.singular_faces])
    assert (np.abs(positions[caps, 2]) > 0.5).all()


def test_field_does_not_depend_on_the_mesh_scale_and_is_deterministic():
    positions, faces, normals, _ = torus(nu=60, nv=24)
    curvature = principal_curvatures(positions, faces)
    strength = anisotropy(curvature.k1, curvature.k2)
    one = cross_field(positions, faces, normals, directions=curvature.direction1, strength=strength)
    again = cross_field(positions, faces, normals, directions=curvature.direction1, strength=strength)
    assert one.direction.tobytes() == again.direction.tobytes()
    scaled = cross_field(positions * 100.0, faces, normals, directions=curvature.direction1, strength=strength)
    assert np.abs(cross_angle_degrees(scaled.direction, one.direction, normals)).max() < 1e-4  # degrees: rounding only


def test_iterative_solve_matches_the_factorization_and_falls_back_to_it():
    """The aligned field's system solved by preconditioned CG agrees with SuperLU's factorization; where CG cannot
    converge (one iteration allowed) the factorization's answer comes back unchanged."""
    import scipy.sparse as sp

    from baker.geometry.direction_field import hermitian_solver, solve_with_data_term

    n = 1500
    rng = np.random.default_rng(3)
    i = np.arange(n)
    ring = sp.csr_matrix((np.full(n, -0.3 + 0.2j), (i, (i + 1) % n)), shape=(n, n))
    matrix = sp.eye(n) * 2.0 + ring + ring.conj().T + sp.diags(rng.uniform(0.0, 0.5, n))
    rhs = rng.normal(size=n) + 1j * rng.normal(size=n)
    direct = hermitian_solver(matrix)(rhs)
    assert np.allclose(matrix @ direct, rhs, atol=1e-10)
    iterative = solve_with_data_term(matrix, rhs)
    assert np.abs(iterative - direct).max() < 1e-7 * np.abs(direct).max()
    assert not np.array_equal(iterative, direct)  # CG ran, not the fallback
    assert np.array_equal(solve_with_data_term(matrix, rhs, max_iterations=1), direct)
