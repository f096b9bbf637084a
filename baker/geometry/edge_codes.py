"""The vocabulary of edge data, light enough for validation: per-edge flag bits (the ``BAKER_edges`` ``flags``),
``EXT_mesh_primitive_edge_visibility`` codes and their 2-bit packing, the position weld edges are built on, and the
settings of edge classification. The numba kernels that compute edges are in :mod:`baker.geometry.edges`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


# per-edge flags (the BAKER_edges ``flags`` accessor, UNSIGNED_SHORT)
BOUNDARY = 1 << 0  # exactly one face


NON_MANIFOLD = 1 << 1  # more than two faces


CREASE = 1 << 2  # dihedral angle above crease_angle


RIDGE = 1 << 3  # convex crease


VALLEY = 1 << 4  # concave crease


MATERIAL = 1 << 5  # the faces belong to different primitives or materials


UV_SEAM = 1 << 6  # the faces' TEXCOORD_0 differ along the edge


NORMAL_SEAM = 1 << 7  # the faces' NORMALs differ along the edge (split, "hard" shading)


PLANAR = 1 << 8  # dihedral angle below planar_angle: can never be a contour edge


QUAD_DIAGONAL = 1 << 9  # the diagonal of a quad split into two triangles (hidden in the wireframe mask)


INCONSISTENT_WINDING = 1 << 10  # both faces traverse the edge in the same direction


FLAG_NAMES = {BOUNDARY: "boundary", NON_MANIFOLD: "nonManifold", CREASE: "crease", RIDGE: "ridge", VALLEY: "valley",
              MATERIAL: "material", UV_SEAM: "uvSeam", NORMAL_SEAM: "normalSeam", PLANAR: "planar",
              QUAD_DIAGONAL: "quadDiagonal", INCONSISTENT_WINDING: "inconsistentWinding"}


# EXT_mesh_primitive_edge_visibility values (2 bits per triangle edge)
VIS_HIDDEN, VIS_SILHOUETTE, VIS_HARD, VIS_REPEATED_HARD = 0, 1, 2, 3


# ----------------------------------------------------------------------------------------------------------- weld
@dataclass(frozen=True)
class EdgeSettings:
    """How edges are welded and classified. The edges technique's options (``EdgesOptions``) carry the same names and
    defaults and can be passed wherever these are (any object with these attributes is accepted)."""

    weld_tolerance: float = 1e-6  # x the bounding-box diagonal
    crease_angle: float = 60.0  # degrees
    planar_angle: float = 0.01  # degrees
    quad_angle: float = 30.0  # degrees
    hard_uv_seams: bool = False
    wireframe: str = "quad-diagonals"  # quad-diagonals | planar | none | off


def weld_positions(positions: np.ndarray, tolerance: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices that round to the same cell of a grid of ``tolerance`` x the bounding-box diagonal.

    The same cells and the same result as :func:`baker.geometry.welding.weld` (welded vertices numbered by first occurrence),
    with the three cell coordinates packed into one int64 so the sort is a 1D integer argsort.
    """
    positions = np.asarray(positions, np.float64)
    n = len(positions)
    if n == 0:
        return positions.copy(), np.zeros(0, np.int64)
    diag = float(np.linalg.norm(positions.max(0) - positions.min(0))) or 1.0
    cell = diag * tolerance if tolerance > 0 else 0.0
    if cell > 0:
        keys = np.round(positions / cell).astype(np.int64)
        keys -= keys.min(0)
        span = keys.max(0) + 1
    if cell > 0 and float(span[0]) * float(span[1]) * float(span[2]) < 2.0**62:
        packed = (keys[:, 0] * span[1] + keys[:, 1]) * span[2] + keys[:, 2]
        order = np.argsort(packed, kind="stable")
        sorted_keys = packed[order]
        start = np.ones(n, bool)
        start[1:] = sorted_keys[1:] != sorted_keys[:-1]
    else:  # exact positions (tolerance 0) or a grid too fine for 62 bits: sort rows
        rows = keys if cell > 0 else positions
        order = np.lexsort(rows.T[::-1])
        sorted_rows = rows[order]
        start = np.ones(n, bool)
        start[1:] = np.any(sorted_rows[1:] != sorted_rows[:-1], axis=1)
    group = np.cumsum(start) - 1  # group of each sorted vertex; stable sort: a group's first entry is its first use
    first = order[start]
    # number groups by first occurrence in the input, so the order does not depend on coordinates
    rank = np.empty(len(first), np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    inverse = np.empty(n, np.int64)
    inverse[order] = rank[group]
    welded = np.empty((len(first), 3), np.float64)
    welded[rank] = positions[first]
    return welded, inverse


# ----------------------------------------------------------------------------------------------------------- bit packing
def pack_visibility(codes: np.ndarray) -> np.ndarray:
    """Pack (N, 3) 2-bit codes LSB first, edges (v0:v1, v1:v2, v2:v0) per triangle: ceil(6N / 8) bytes."""
    flat = np.asarray(codes, np.uint8).reshape(-1)
    n_bytes = (2 * len(flat) + 7) // 8
    padded = np.zeros(n_bytes * 4, np.uint8)
    padded[: len(flat)] = flat & 3
    quads = padded.reshape(-1, 4)
    return (quads[:, 0] | (quads[:, 1] << 2) | (quads[:, 2] << 4) | (quads[:, 3] << 6)).astype(np.uint8)


def unpack_visibility(data: np.ndarray, n_triangles: int) -> np.ndarray:
    """The inverse of :func:`pack_visibility`: (n_triangles, 3) codes."""
    data = np.asarray(data, np.uint8)
    codes = np.stack([(data >> s) & 3 for s in (0, 2, 4, 6)], axis=1).reshape(-1)
    return codes[: 3 * n_triangles].reshape(-1, 3)
