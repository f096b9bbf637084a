"""Vertex normals as trimesh computes them, so a mesh read directly matches the one trimesh reads: angle-weighted
(Thuermer & Wuethrich 1998), with trimesh's arithmetic, over every part of a mesh welded by position."""
from __future__ import annotations

import numpy as np


def vertex_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals as trimesh computes them for a mesh without any: each face's unit normal weighted by the
    corner angle (Thuermer & Wuethrich 1998), summed in face order; faces whose normal is degenerate and vertices
    no usable face touches contribute zero. The operations follow trimesh's so the float32 result is the same."""
    triangles = positions[faces]
    cross = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 1])
    face_normals, valid = unitize(cross, with_valid=True)
    face_normals[~valid] = 0.0
    angles = _corner_angles(triangles)
    ok = (face_normals ** 2).sum(axis=1) > 0.5
    weights = angles[ok].reshape(-1)
    corner = faces[ok].reshape(-1)
    summed = np.zeros((len(positions), 3))
    normals_ok = face_normals[ok]
    for axis in range(3):
        summed[:, axis] = np.bincount(corner, weights * np.repeat(normals_ok[:, axis], 3), minlength=len(positions))
    return unitize(summed)


def seamless_vertex_normals(parts: list) -> list:
    """Vertex normals of several meshes of one space (an OBJ's material groups, the vertices it splits at UV
    seams) computed as one mesh: vertices are welded by position (:func:`baker.geometry.edge_codes.weld_positions`,
    the grid of :mod:`baker.geometry.welding`) and each welded vertex gets the angle-weighted normal of every face
    around it (:func:`vertex_normals`), so split copies of a vertex agree and UV or material seams do not shade.
    Vertices stay apart only where their smoothing sets differ. ``parts``: (positions, faces, smoothing ids or
    None) per mesh; returns the (n, 3) normals of each mesh's vertices, in order."""
    from baker.geometry.edge_codes import weld_positions

    counts = [len(p[0]) for p in parts]
    offsets = np.cumsum([0] + counts)
    positions = np.concatenate([p[0] for p in parts]) if len(parts) > 1 else np.asarray(parts[0][0])
    faces = np.concatenate([np.asarray(p[1], np.int64) + offsets[i] for i, p in enumerate(parts)])
    welded, vertex = weld_positions(positions)
    if any(p[2] is not None for p in parts):
        smoothing = np.concatenate([np.zeros(len(p[0]), np.int64) if p[2] is None else p[2] for p in parts])
        sets = int(smoothing.max()) + 1
        split, vertex = np.unique(vertex * sets + smoothing, return_inverse=True)
        vertex = vertex.reshape(-1)
        welded = welded[split // sets]
    normals = vertex_normals(welded, vertex[faces])[vertex]
    return [normals[offsets[i]:offsets[i + 1]] for i in range(len(parts))]


def unitize(vectors: np.ndarray, with_valid: bool = False):
    """Rows scaled to unit length by their reciprocal norm (trimesh's arithmetic, so the bits match); rows shorter
    than 1e-13 stay as they are (``with_valid`` also returns which rows were scaled)."""
    norm = np.sqrt(np.dot(vectors * vectors, [1.0] * vectors.shape[1]))
    valid = norm > np.finfo(np.float64).resolution * 100
    norm[valid] **= -1
    unit = vectors * norm.reshape((-1, 1))
    return (unit, valid) if with_valid else unit


def _corner_angles(triangles: np.ndarray) -> np.ndarray:
    u = unitize(triangles[:, 1] - triangles[:, 0])
    v = unitize(triangles[:, 2] - triangles[:, 0])
    w = unitize(triangles[:, 2] - triangles[:, 1])
    angles = np.zeros((len(triangles), 3))
    angles[:, 0] = np.arccos(np.clip(np.dot(u * v, [1.0] * 3), -1, 1))
    angles[:, 1] = np.arccos(np.clip(np.dot(-u * w, [1.0] * 3), -1, 1))
    angles[:, 2] = np.pi - angles[:, 0] - angles[:, 1]
    angles[(angles < 1e-8).any(axis=1), :] = 0.0
    return angles


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
