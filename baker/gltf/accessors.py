"""Accessor data as geometry: float conversion of (normalized) accessors, triangles from any triangle mode,
and the test for fin primitives baker derives itself."""
from __future__ import annotations

import numpy as np

from baker.checks import is_derived_fins  # defined with the checks that skip fins; geometry reads it from here
from baker.gltf.document import GltfDocument


MODE_TRIANGLES, MODE_STRIP, MODE_FAN = 4, 5, 6

__all__ = ["MODE_TRIANGLES", "MODE_STRIP", "MODE_FAN", "is_derived_fins", "to_float", "faces_from_indices"]


def to_float(doc: GltfDocument, accessor: int) -> np.ndarray:
    data = doc.accessor(accessor, copy=False)  # converted below into a new array
    acc = doc.json["accessors"][accessor]
    if acc.get("normalized") and data.dtype.kind in "iu":
        info = np.iinfo(data.dtype)
        out = data.astype(np.float64) / info.max
        return np.maximum(out, -1.0) if data.dtype.kind == "i" else out
    return data.astype(np.float64)


def faces_from_indices(indices: np.ndarray, mode: int) -> np.ndarray:
    """Triangles of a primitive in glTF's order (spec 3.7.2.1), degenerate ones included: per-triangle data such
    as EXT_mesh_primitive_edge_visibility counts them, and they carry no area for the bakes that sample surfaces."""
    n = len(indices)
    if mode == MODE_TRIANGLES:
        return indices[: n // 3 * 3].reshape(-1, 3)
    if n < 3 or mode not in (MODE_STRIP, MODE_FAN):
        return np.zeros((0, 3), np.int64)
    k = np.arange(n - 2)
    if mode == MODE_STRIP:
        even = (k % 2) == 0
        a = indices[k]
        b = np.where(even, indices[k + 1], indices[k + 2])
        c = np.where(even, indices[k + 2], indices[k + 1])
        return np.stack([a, b, c], axis=1)
    # fan: triangle i is (v[i+1], v[i+2], v[0])
    return np.stack([indices[k + 1], indices[k + 2], np.full_like(k, indices[0])], axis=1)
