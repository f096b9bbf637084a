"""Tangent frames of a UV layout: per-triangle UV Jacobians and MikkTSpace-like per-vertex tangents.

glTF's tangent space (spec 3.7.2.1, normalTexture): ``bitangent = cross(normal, tangent.xyz) * tangent.w``, the
normal map's +X along +u and its +Y "up" in the image, i.e. along -v (glTF's v grows downwards). A triangle's
Jacobian dP/du, dP/dv follows from its edges and UV edges; a vertex takes the corner-angle-weighted sum of its
triangles' unit dP/du (as MikkTSpace weights by angle; Mikkelsen 2008, "Simulation of wrinkled surfaces revisited"),
made orthogonal to its normal, and w = +1 where the layout is not mirrored (cross(N, T) points along -dP/dv).
"""
from __future__ import annotations

import numpy as np


def uv_jacobians(positions: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(dP/du, dP/dv) per triangle, each (faces, 3), in mesh units per UV unit; zero for triangles with no UV area."""
    p = positions[faces]
    t = uv[faces]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[:, None]
    dpdu = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * inv
    dpdv = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * inv
    return dpdu, dpdv


def corner_angles(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(faces, 3) interior angle at each corner, radians."""
    p = positions[faces]
    out = np.empty(faces.shape, np.float64)
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        cross = np.linalg.norm(np.cross(a, b), axis=1)
        out[:, k] = np.arctan2(cross, np.einsum("ij,ij->i", a, b))
    return out


def vertex_tangents(positions: np.ndarray, faces: np.ndarray, normals: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(vertices, 4) glTF TANGENT: unit xyz orthogonal to ``normals``, w = +-1 (handedness of the layout)."""
    dpdu, dpdv = uv_jacobians(positions, faces, uv)

    def unit(v):
        return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)

    weights = corner_angles(positions, faces)
    tangent = np.zeros((len(positions), 3))
    down = np.zeros((len(positions), 3))
    for k in range(3):
        np.add.at(tangent, faces[:, k], weights[:, k:k + 1] * unit(dpdu))
        np.add.at(down, faces[:, k], weights[:, k:k + 1] * unit(dpdv))
    tangent -= normals * np.einsum("ij,ij->i", tangent, normals)[:, None]
    length = np.linalg.norm(tangent, axis=1)
    # a vertex without UV area around it (or dP/du along the normal) gets any tangent orthogonal to its normal
    fallback = np.where(np.abs(normals[:, 0:1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    fallback = fallback - normals * np.einsum("ij,ij->i", fallback, normals)[:, None]
    tangent = np.where((length > 1e-12)[:, None], tangent, fallback)
    tangent = unit(tangent)
    handedness = np.einsum("ij,ij->i", np.cross(normals, tangent), -down)
    w = np.where(handedness < 0.0, -1.0, 1.0)
    return np.concatenate([tangent, w[:, None]], axis=1)
