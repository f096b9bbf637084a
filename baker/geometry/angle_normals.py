"""Vertex normals as trimesh computes them, so a mesh read directly matches the one trimesh reads: angle-weighted
(Thuermer & Wuethrich 1998), with trimesh's arithmetic, over every part of a mesh welded by position."""
from __future__ import annotations

import numpy as np


def vertex_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals as trimesh computes them for a mesh without any: each face's unit normal weighted by the
    corner angle (Thuermer & Wuethrich 1998), summed in face order; faces whose normal is degenerate and vertices
    no usable face touches contribute zero. The operations follow trimesh's so the float64 result matches it to
    rounding (a compiled pass, :func:`baker.geometry.normals.angle_weighted_normals`; numba is imported only here,
    so reading a file that has normals does not load it)."""
    from baker.geometry.normals import angle_weighted_normals

    out = np.zeros((len(positions), 3))
    if len(faces):
        angle_weighted_normals(np.ascontiguousarray(positions, np.float64), np.ascontiguousarray(faces, np.int64), out)
    return out


def seamless_vertex_normals(parts: list, dtype=np.float64) -> list:
    """Vertex normals of several meshes of one space (an OBJ's material groups, the vertices it splits at UV
    seams) computed as one mesh: vertices are welded by position (:func:`baker.geometry.welding.weld`, the cells and
    numbering of :func:`baker.geometry.edge_codes.weld_positions` in one compiled pass) and each welded vertex gets
    the angle-weighted normal of every face around it (:func:`vertex_normals`), so split copies of a vertex agree and
    UV or material seams do not shade. Vertices stay apart only where their smoothing sets differ. ``parts``:
    (positions, faces, smoothing ids or None) per mesh; returns the (n, 3) normals of each mesh's vertices, in order,
    as ``dtype``, unit as glTF requires them (:func:`unit_normals` gives the same: +Z where no usable face touches)."""
    from baker.geometry.normals import gathered_unit_normals
    from baker.geometry.welding import weld

    counts = [len(p[0]) for p in parts]
    offsets = np.cumsum([0] + counts)
    positions = np.concatenate([p[0] for p in parts]) if len(parts) > 1 else np.asarray(parts[0][0])
    faces = np.concatenate([np.asarray(p[1], np.int64) + offsets[i] for i, p in enumerate(parts)]) if len(parts) > 1 \
        else np.asarray(parts[0][1], np.int64)
    welded, vertex = weld(np.asarray(positions, np.float64))
    if any(p[2] is not None for p in parts):
        smoothing = np.concatenate([np.zeros(len(p[0]), np.int64) if p[2] is None else p[2] for p in parts])
        sets = int(smoothing.max()) + 1
        split, vertex = np.unique(vertex * sets + smoothing, return_inverse=True)
        vertex = vertex.reshape(-1)
        welded = welded[split // sets]
    # nothing merged: the vertex ids are the identity (weld numbers by first occurrence), the faces stay as they are
    sums = vertex_normals(welded, faces if len(welded) == len(positions) else vertex[faces])
    normals = np.empty((len(positions), 3), dtype)
    gathered_unit_normals(sums, np.ascontiguousarray(vertex, np.int64), normals)
    return [normals[offsets[i]:offsets[i + 1]] for i in range(len(parts))]


def unitize(vectors: np.ndarray, with_valid: bool = False):
    """Rows scaled to unit length by their reciprocal norm (trimesh's arithmetic, so the bits match); rows shorter
    than 1e-13 stay as they are (``with_valid`` also returns which rows were scaled)."""
    norm = np.sqrt(np.dot(vectors * vectors, [1.0] * vectors.shape[1]))
    valid = norm > np.finfo(np.float64).resolution * 100
    norm[valid] **= -1
    unit = vectors * norm.reshape((-1, 1))
    return (unit, valid) if with_valid else unit


def unit_normals(normals: np.ndarray) -> np.ndarray:
    """Vertex normals as glTF requires them (unit length): the file's, or those trimesh computes when it has none,
    are zero where every adjacent triangle is degenerate (a mesh collapsed to a point or a line), which Khronos'
    validator reports as ACCESSOR_VECTOR3_NON_UNIT. Those get +Z (any unit vector: such a vertex shades nothing);
    the others are renormalised only where float rounding left them off unit length."""
    normals = np.array(normals, np.float64)
    length = np.linalg.norm(normals, axis=1) if len(normals) else np.zeros(0)
    off = np.abs(length - 1.0) > 1e-4
    usable = off & (length > 1e-12)
    normals[usable] /= length[usable, None]
    normals[off & ~usable] = (0.0, 0.0, 1.0)
    return normals
