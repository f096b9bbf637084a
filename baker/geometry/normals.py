"""Vertex normals of triangle meshes."""
from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def _area_weighted_normals(vertices, faces, out):
    """Unit sums of the incident face normals (cross products, |n| = twice the area) into ``out`` (zeroed).

    The sums run corner by corner (every face's corner 0, then corner 1, then corner 2), the order of the
    ``np.add.at`` reference this replaces, so the float64 results are bit-identical to it, ~8x faster at 1M faces."""
    m = faces.shape[0]
    face_normals = np.empty((m, 3))
    for f in range(m):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        e0, e1, e2 = vertices[b, 0] - vertices[a, 0], vertices[b, 1] - vertices[a, 1], vertices[b, 2] - vertices[a, 2]
        g0, g1, g2 = vertices[c, 0] - vertices[a, 0], vertices[c, 1] - vertices[a, 1], vertices[c, 2] - vertices[a, 2]
        face_normals[f, 0] = e1 * g2 - e2 * g1
        face_normals[f, 1] = e2 * g0 - e0 * g2
        face_normals[f, 2] = e0 * g1 - e1 * g0
    for corner in range(3):
        for f in range(m):
            v = faces[f, corner]
            out[v, 0] += face_normals[f, 0]
            out[v, 1] += face_normals[f, 1]
            out[v, 2] += face_normals[f, 2]
    for v in range(out.shape[0]):
        x, y, z = out[v, 0], out[v, 1], out[v, 2]
        length = np.sqrt(x * x + y * y + z * z)
        if length > 1e-30:
            out[v, 0], out[v, 1], out[v, 2] = x / length, y / length, z / length
        else:  # zero-area neighbourhood (or an unused vertex)
            out[v, 0], out[v, 1], out[v, 2] = 0.0, 0.0, 1.0


@numba.njit(cache=True, nogil=True)
def angle_weighted_normals(positions, faces, out):
    """Unit angle-weighted vertex normals (Thuermer & Wuethrich 1998) into ``out`` (zeroed), with trimesh's
    arithmetic (:func:`baker.geometry.angle_normals.vertex_normals` documents the rules): each face's unit normal
    ``(b - a) x (c - b)``, scaled by the reciprocal of its length, times the corner angle (arccos of the unit edges'
    dot product, the third as pi minus the others; a face with an angle under 1e-8 adds nothing, nor does one whose
    normal is shorter than 1e-13), summed face by face, corner by corner (numpy's ``bincount`` order), then unitized
    where the sum is longer than 1e-13. One pass over the faces without (faces, 3, 3) temporaries: at 4.4M
    triangles ~30x faster than the numpy arithmetic it replaces."""
    tiny = 1e-13  # numpy's float64 resolution x 100, trimesh's unitize threshold
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ab0, ab1, ab2 = positions[b, 0] - positions[a, 0], positions[b, 1] - positions[a, 1], \
            positions[b, 2] - positions[a, 2]
        ac0, ac1, ac2 = positions[c, 0] - positions[a, 0], positions[c, 1] - positions[a, 1], \
            positions[c, 2] - positions[a, 2]
        bc0, bc1, bc2 = positions[c, 0] - positions[b, 0], positions[c, 1] - positions[b, 1], \
            positions[c, 2] - positions[b, 2]
        n0, n1, n2 = ab1 * bc2 - ab2 * bc1, ab2 * bc0 - ab0 * bc2, ab0 * bc1 - ab1 * bc0
        length = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        if not length > tiny:
            continue
        inverse = 1.0 / length
        n0, n1, n2 = n0 * inverse, n1 * inverse, n2 * inverse
        if not n0 * n0 + n1 * n1 + n2 * n2 > 0.5:
            continue
        length = np.sqrt(ab0 * ab0 + ab1 * ab1 + ab2 * ab2)
        if length > tiny:
            inverse = 1.0 / length
            ab0, ab1, ab2 = ab0 * inverse, ab1 * inverse, ab2 * inverse
        length = np.sqrt(ac0 * ac0 + ac1 * ac1 + ac2 * ac2)
        if length > tiny:
            inverse = 1.0 / length
            ac0, ac1, ac2 = ac0 * inverse, ac1 * inverse, ac2 * inverse
        length = np.sqrt(bc0 * bc0 + bc1 * bc1 + bc2 * bc2)
        if length > tiny:
            inverse = 1.0 / length
            bc0, bc1, bc2 = bc0 * inverse, bc1 * inverse, bc2 * inverse
        angle0 = np.arccos(min(max(ab0 * ac0 + ab1 * ac1 + ab2 * ac2, -1.0), 1.0))
        angle1 = np.arccos(min(max(-ab0 * bc0 + -ab1 * bc1 + -ab2 * bc2, -1.0), 1.0))
        angle2 = np.pi - angle0 - angle1
        if angle0 < 1e-8 or angle1 < 1e-8 or angle2 < 1e-8:
            continue
        out[a, 0] += angle0 * n0
        out[a, 1] += angle0 * n1
        out[a, 2] += angle0 * n2
        out[b, 0] += angle1 * n0
        out[b, 1] += angle1 * n1
        out[b, 2] += angle1 * n2
        out[c, 0] += angle2 * n0
        out[c, 1] += angle2 * n1
        out[c, 2] += angle2 * n2
    for v in range(out.shape[0]):
        x, y, z = out[v, 0], out[v, 1], out[v, 2]
        length = np.sqrt(x * x + y * y + z * z)
        if length > tiny:
            inverse = 1.0 / length
            out[v, 0], out[v, 1], out[v, 2] = x * inverse, y * inverse, z * inverse


@numba.njit(cache=True, nogil=True)
def gathered_unit_normals(unit_or_zero, rows, out):
    """``out[i] = unit_or_zero[rows[i]]`` in ``out``'s dtype, +Z where that row is (nearly) zero: the normals of
    :func:`angle_weighted_normals` per input vertex as glTF requires them (unit), in one pass."""
    for i in range(rows.shape[0]):
        r = rows[i]
        x, y, z = unit_or_zero[r, 0], unit_or_zero[r, 1], unit_or_zero[r, 2]
        if x * x + y * y + z * z > 0.5:
            out[i, 0], out[i, 1], out[i, 2] = x, y, z
        else:
            out[i, 0], out[i, 1], out[i, 2] = 0.0, 0.0, 1.0


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals (unit length; zero-area neighbourhoods get +Z)."""
    vertices = np.ascontiguousarray(vertices, np.float64)
    out = np.zeros_like(vertices)
    if len(faces):
        _area_weighted_normals(vertices, np.ascontiguousarray(faces, np.int64), out)
    else:
        out[:, 2] = 1.0
    return out
