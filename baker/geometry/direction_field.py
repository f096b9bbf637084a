"""A smooth cross field (4-RoSy) on a triangle mesh, aligned with the principal curvature directions where the
surface is clearly anisotropic: the direction field hatching strokes follow (RTR4 15.3; issue 38), shared by the tam
bake's stroke coordinates and ``baker lines --hatching``.

Praun et al.'s real-time hatching applies a tonal art map through a lapped-texture parameterization oriented by a
smooth direction field (Praun, Finkelstein & Hoppe, SIGGRAPH 2000); Hertzmann & Zorin ("Illustrating smooth
surfaces", SIGGRAPH 2000) draw strokes along principal directions smoothed into a cross field. The field here is
Knöppel, Crane, Pinkall & Schröder's "Globally Optimal Direction Fields" (SIGGRAPH 2013), on vertices:

- every vertex i has a tangent frame (e1, e2) around its normal; a direction at angle theta is stored as the complex
  number u = exp(i n theta), n = 4, so that the four directions of a cross are one value;
- moving a vector along edge ij turns it by alpha_ij in the frames' angles: the rotation that takes the normal of i
  onto the normal of j (the discrete Levi-Civita connection of the minimal rotation), read in j's frame;
- smoothness is the connection Dirichlet energy E(u) = sum_ij w_ij |u_j - exp(i n alpha_ij) u_i|^2, w_ij the
  cotangent weights (clamped at zero so E stays positive semi-definite on obtuse triangles);
- alignment adds t sum_i a_i s_i |u_i - q_i|^2 with q_i = exp(i n phi_i) the principal direction's angle phi_i and
  s_i in [0, 1] how clearly anisotropic vertex i is (|k1 - k2| against a noise level); minimizing both is one
  sparse Hermitian solve, (A + t M S) u = t M S q. Where s = 0 everywhere, the smoothest field is the eigenvector
  of the smallest eigenvalue of A u = lambda M u (Knöppel's eq. 6), found by inverse iteration from a fixed start
  vector, so the result is deterministic.

Singularities are reported per face as the field's index around it: +1/4 or -1/4 for a cross field (Poincaré-Hopf:
they sum to the Euler characteristic, 2 on a sphere, 0 on a torus).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ROSY = 4  # a cross field: strokes and cross-hatching strokes are the same field turned by 90 degrees


@dataclass
class CrossField:
    """Per-vertex cross field of a welded mesh."""

    direction: np.ndarray  # (n, 3) unit tangent: one of the cross's four directions (the others: turned by 90 deg)
    confidence: np.ndarray  # (n,) |u| in [0, 1]: near 0 where the field is close to a singularity
    singular_faces: np.ndarray  # (s,) faces around which the field turns
    singular_index: np.ndarray  # (s,) their index, in quarter turns (+1: +1/4, -1: -1/4, ...)

    @property
    def euler_characteristic(self) -> float:
        """The sum of the singularities' indices (Poincaré-Hopf: V - E + F of a closed surface)."""
        return float(self.singular_index.sum()) / ROSY


def tangent_frames(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(e1, e2): unit tangents orthogonal to each unit normal, e2 = n x e1; e1 is the coordinate axis least
    aligned with the normal, projected (any frame serves: the field is stored relative to it)."""
    axis = np.zeros_like(normals)
    axis[np.arange(len(normals)), np.argmin(np.abs(normals), axis=1)] = 1.0
    e1 = axis - normals * np.einsum("ij,ij->i", axis, normals)[:, None]
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    return e1, np.cross(normals, e1)


def unique_edges(faces: np.ndarray) -> np.ndarray:
    """(e, 2) undirected edges, each once, lower vertex first, sorted."""
    edges = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2).astype(np.int64)
    lo, hi = edges.min(axis=1), edges.max(axis=1)
    n = int(hi.max()) + 1 if len(hi) else 1
    keys = np.unique(lo * n + hi)  # one int64 per edge: sorting rows (np.unique(axis=0)) was 10x slower
    return np.stack([keys // n, keys % n], axis=1)


def cotangent_weights(positions: np.ndarray, faces: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Per edge of ``edges``: (cot a + cot b) / 2 of the angles opposite it, clamped at 0."""
    n = len(positions)
    keys = edges[:, 0].astype(np.int64) * n + edges[:, 1]
    order = np.argsort(keys)
    weights = np.zeros(len(edges))
    tri = positions[faces]
    for corner in range(3):
        a, b = (corner + 1) % 3, (corner + 2) % 3  # the edge opposite this corner
        u, v = tri[:, a] - tri[:, corner], tri[:, b] - tri[:, corner]
        cross = np.linalg.norm(np.cross(u, v), axis=1)
        cot = np.einsum("ij,ij->i", u, v) / np.maximum(cross, 1e-300)
        lo, hi = np.minimum(faces[:, a], faces[:, b]), np.maximum(faces[:, a], faces[:, b])
        slot = order[np.searchsorted(keys[order], lo.astype(np.int64) * n + hi)]
        np.add.at(weights, slot, 0.5 * cot)
    return np.maximum(weights, 0.0)


def vertex_areas(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Lumped mass: a third of the area of every triangle at each vertex."""
    tri = positions[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    out = np.zeros(len(positions))
    np.add.at(out, faces.reshape(-1), np.repeat(area / 3.0, 3))
    return out


def transport_angles(normals: np.ndarray, e1: np.ndarray, e2: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Per edge ij, the angle a tangent vector gains going from i's frame to j's under the minimal rotation taking
    normal i onto normal j."""
    i, j = edges[:, 0], edges[:, 1]
    ni, nj = normals[i], normals[j]
    axis = np.cross(ni, nj)
    sin = np.linalg.norm(axis, axis=1)
    cos = np.einsum("ij,ij->i", ni, nj)
    safe = sin > 1e-12
    k = np.zeros_like(axis)
    k[safe] = axis[safe] / sin[safe][:, None]
    v = e1[i]
    # Rodrigues: v rotated about k by the angle between the normals
    rotated = (v * cos[:, None] + np.cross(k, v) * sin[:, None]
               + k * np.einsum("ij,ij->i", k, v)[:, None] * (1.0 - cos)[:, None])
    return np.arctan2(np.einsum("ij,ij->i", rotated, e2[j]), np.einsum("ij,ij->i", rotated, e1[j]))


def connection_laplacian(edges: np.ndarray, weights: np.ndarray, alpha: np.ndarray, n: int):
    """The Hermitian matrix A of E(u) = sum w |u_j - exp(i ROSY alpha) u_i|^2 = u^H A u."""
    import scipy.sparse as sp

    i, j = edges[:, 0], edges[:, 1]
    r = np.exp(1j * ROSY * alpha)
    diagonal = np.zeros(n)
    np.add.at(diagonal, i, weights)
    np.add.at(diagonal, j, weights)
    rows = np.concatenate([np.arange(n), j, i])
    cols = np.concatenate([np.arange(n), i, j])
    data = np.concatenate([diagonal.astype(complex), -weights * r, -weights * np.conj(r)])
    return sp.csc_matrix((data, (rows, cols)), shape=(n, n))


def anisotropy(k1: np.ndarray, k2: np.ndarray, noise: float | None = None) -> np.ndarray:
    """s in [0, 1]: how clearly the principal directions are defined, |k1 - k2| against ``noise`` (default: the
    median of |k1 - k2|, so that half the surface counts as clearly anisotropic and the rest follows smoothly)."""
    spread = np.abs(np.asarray(k1, np.float64) - np.asarray(k2, np.float64))
    if noise is None:
        noise = float(np.median(spread)) if len(spread) else 0.0
    if noise <= 0:
        return (spread > 0).astype(np.float64)
    return np.clip(spread / (2.0 * noise) - 0.25, 0.0, 1.0)


def cross_field(positions: np.ndarray, faces: np.ndarray, normals: np.ndarray, directions: np.ndarray | None = None,
                strength: np.ndarray | None = None, alignment: float = 1.0, iterations: int = 30) -> CrossField:
    """A smooth cross field on the welded mesh (``positions``, ``faces``, unit vertex ``normals``).

    ``directions`` (n, 3): tangents the field should follow (principal directions, or an artist's combing), with
    ``strength`` (n,) in [0, 1] per vertex (0: no preference; default 1 where a direction is non-zero).
    ``alignment`` trades smoothness against following them: the data term's weight relative to the Laplacian's
    mean diagonal per unit area, so its effect does not depend on the mesh's scale or density. Without
    directions (or all strengths 0) the result is the smoothest cross field."""
    import scipy.sparse as sp

    positions = np.asarray(positions, np.float64)
    faces = np.asarray(faces, np.int64)
    normals = np.asarray(normals, np.float64)
    n = len(positions)
    e1, e2 = tangent_frames(normals)
    edges = unique_edges(faces)
    weights = cotangent_weights(positions, faces, edges)
    alpha = transport_angles(normals, e1, e2, edges)
    laplacian = connection_laplacian(edges, weights, alpha, n)
    mass = np.maximum(vertex_areas(positions, faces), 1e-300)
    # the scale of A per unit of mass: a weight of ``alignment`` then means "as strong as the smoothness term"
    scale = float(laplacian.diagonal().real.mean() / mass.mean()) if n else 0.0

    target, weight = None, np.zeros(n)
    if directions is not None:
        directions = np.asarray(directions, np.float64)
        phi = np.arctan2(np.einsum("ij,ij->i", directions, e2), np.einsum("ij,ij->i", directions, e1))
        length = np.linalg.norm(directions, axis=1)
        weight = (np.ones(n) if strength is None else np.clip(np.asarray(strength, np.float64), 0, 1)) * (length > 0)
        target = np.exp(1j * ROSY * phi)
    if target is not None and weight.any():
        data = sp.diags(alignment * scale * mass * weight)
        u = solve_with_data_term(laplacian + data, data @ target)
    else:
        # inverse iteration for the smallest eigenpair of A u = lambda M u, shifted a hair off zero (A is
        # singular on a flat or developable patch, whose smoothest field is parallel)
        shift = 1e-8 * scale
        solve = hermitian_solver(laplacian + sp.diags(shift * mass))
        u = np.exp(1j * np.arange(n) * 0.7) + 0.5  # fixed start: deterministic
        for _ in range(iterations):
            u = solve(mass * u)
            u /= np.sqrt(np.sum(mass * np.abs(u) ** 2))
    magnitude = np.abs(u)
    theta = np.angle(u) / ROSY
    direction = np.cos(theta)[:, None] * e1 + np.sin(theta)[:, None] * e2
    confidence = magnitude / magnitude.max() if n and magnitude.max() > 0 else magnitude
    singular_faces, index = singularities(faces, edges, alpha, np.angle(u))
    return CrossField(direction, confidence, singular_faces, index)


def solve_with_data_term(matrix, rhs: np.ndarray, rtol: float = 1e-9, max_iterations: int = 2000) -> np.ndarray:
    """x with ``matrix`` x = ``rhs`` for the aligned field's (A + t M S): conjugate gradients preconditioned by the
    diagonal, falling back to the direct :func:`hermitian_solver` where they do not converge. The data term makes
    the system well conditioned wherever the surface is clearly anisotropic, so CG needs ~150 iterations on the
    bunny (35k vertices: 0.1 s against 1.0 s for the factorization, the directions within 2e-4 degrees of it);
    a mesh with large stretches of no preference (flat or spherical regions) converges slower and gets the
    factorization. The loop is written out with numpy's own reductions instead of SciPy's ``cg``, whose BLAS dot
    products run multithreaded: beside the unwrap's child process on two cores the spinning threads made the
    solve 3x slower. A fixed sequence of operations: the result is deterministic."""
    import scipy.sparse as sp

    matrix = sp.csr_matrix(matrix)
    diagonal = matrix.diagonal().real
    if len(rhs) and diagonal.min() > 0:
        x, converged = conjugate_gradients(matrix, np.asarray(rhs, complex), 1.0 / diagonal, rtol, max_iterations)
        if converged and np.isfinite(x).all():
            return x
    return hermitian_solver(matrix)(rhs)


def real_dot(a: np.ndarray, b: np.ndarray) -> float:
    """Re(a^H b), summed pairwise by numpy (no BLAS threads)."""
    return float(np.sum(a.real * b.real + a.imag * b.imag))


def conjugate_gradients(matrix, rhs: np.ndarray, inverse_diagonal: np.ndarray, rtol: float,
                        max_iterations: int) -> tuple[np.ndarray, bool]:
    """Jacobi-preconditioned CG for a Hermitian positive definite ``matrix`` (Hestenes & Stiefel 1952; for a
    Hermitian system every r^H z and p^H A p is real). Returns (x, whether |b - A x| <= rtol |b|)."""
    x = np.zeros_like(rhs)
    residual = rhs.copy()
    stop = rtol * np.sqrt(real_dot(rhs, rhs))
    if stop == 0.0:
        return x, True
    z = inverse_diagonal * residual
    direction = z.copy()
    rz = real_dot(residual, z)
    for _ in range(max_iterations):
        image = matrix @ direction
        curvature = real_dot(direction, image)
        if not curvature > 0.0:  # not positive definite (or NaN): let the factorization decide
            return x, False
        step = rz / curvature
        x += step * direction
        residual -= step * image
        if np.sqrt(real_dot(residual, residual)) <= stop:
            return x, True
        z = inverse_diagonal * residual
        rz_next = real_dot(residual, z)
        direction = z + (rz_next / rz) * direction
        rz = rz_next
    return x, False


def hermitian_solver(matrix):
    """A solve for the Hermitian positive definite ``matrix``, as the real system [[Re, -Im], [Im, Re]] factored by
    SuperLU. SciPy's complex SuperLU factored the same matrices 5-10x slower (an icosphere of 2,562 vertices: 0.8 s
    against 0.12 s; the bunny's 35k vertices: minutes against ~6 s)."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    matrix = sp.csc_matrix(matrix)
    real, imag = sp.csc_matrix(matrix.real), sp.csc_matrix(matrix.imag)
    lu = splu(sp.bmat([[real, -imag], [imag, real]]).tocsc())
    n = matrix.shape[0]

    def solve(rhs: np.ndarray) -> np.ndarray:
        x = lu.solve(np.concatenate([rhs.real, rhs.imag]))
        return x[:n] + 1j * x[n:]

    return solve


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped into (-pi, pi]."""
    return angle - 2 * np.pi * np.ceil((angle - np.pi) / (2 * np.pi))


def singularities(faces: np.ndarray, edges: np.ndarray, alpha: np.ndarray, psi: np.ndarray):
    """(faces, indices in quarter turns) where the field psi = ROSY theta turns around a face: the jumps
    delta_ij = wrap(psi_j - psi_i - ROSY alpha_ij) summed around the face, plus ROSY times the connection's
    holonomy there (the angle a vector turns transported around the face, the face's share of Gaussian curvature),
    make a whole number of turns. Each edge's jump is wrapped once, lower vertex to higher, and taken with its sign
    by the two faces beside it: wrapping per face put a jump of almost exactly pi (the cross turning 45 degrees
    along one edge) at +pi in one face and +pi in the other, a quarter turn too many in the sum."""
    n = int(faces.max()) + 1 if len(faces) else 0
    keys = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(keys)
    jump = wrap(psi[edges[:, 1]] - psi[edges[:, 0]] - ROSY * alpha)
    total_jump = np.zeros(len(faces))
    holonomy = np.zeros(len(faces))
    for a, b in ((0, 1), (1, 2), (2, 0)):
        i, j = faces[:, a], faces[:, b]
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        slot = order[np.searchsorted(keys[order], lo * n + hi)]
        sign = np.where(i == lo, 1.0, -1.0)  # alpha and the jump are stored lower -> higher
        holonomy += sign * alpha[slot]
        total_jump += sign * jump[slot]
    turns = np.rint((total_jump + ROSY * wrap(holonomy)) / (2 * np.pi)).astype(np.int64)
    where = np.nonzero(turns)[0]
    return where, turns[where]
