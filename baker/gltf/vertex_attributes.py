"""The one layout of baker's custom vertex attributes (``_NAME``): FLOAT VEC3, whatever the data's width.

Why: Blender's glTF importer (io_scene_gltf2 4.5, ``blender/imp/mesh.py`` ``do_primitives``) keeps a mesh's custom
attributes in a Python ``set`` but makes their (initially empty) per-attribute arrays in first-seen order; it then
fills and names them in the set's order, which string hashing makes arbitrary. When two custom attributes of one
glTF mesh (all its primitives together) differ in component count, the arrays it concatenates disagree in width and
the import fails with ``ValueError`` (e.g. ``_THICKNESS`` SCALAR next to ``_OUTLINE_NORMAL`` VEC3). Attributes of
equal width import correctly in any order. Several bakes add attributes to the same mesh, so the only layout that
composes is one width for all; VEC3 is the widest that any bake needs (normals, positions, directions). Scalar data
sits in x and pairs in x, y; the other components are zero. A shader binds a scalar as ``float`` (GL reads x of a
3-component buffer) or as ``vec3`` and takes ``.x``.
"""
from __future__ import annotations

import numpy as np

TYPE = "VEC3"
WIDTH = 3


def padded(values: np.ndarray) -> np.ndarray:
    """(N,) or (N, k <= 3) values -> (N, 3) float32, zeros in the unused components."""
    values = np.asarray(values, np.float32)
    if values.ndim == 1:
        values = values[:, None]
    if values.ndim != 2 or values.shape[1] > WIDTH:
        raise ValueError(f"a custom vertex attribute holds at most {WIDTH} components, not shape {values.shape}")
    out = np.zeros((len(values), WIDTH), np.float32)
    out[:, :values.shape[1]] = values
    return out


def unpadded(values: np.ndarray, width: int) -> np.ndarray:
    """The ``width`` meaningful components of a custom attribute as read: (N,) for width 1, else (N, width)."""
    values = np.asarray(values)
    if values.ndim == 1:
        return values if width == 1 else values.reshape(len(values), -1)[:, :width]
    return values[:, 0] if width == 1 else values[:, :width]


def used_columns(values: np.ndarray) -> np.ndarray:
    """A custom attribute's values without trailing all-zero columns (the padding of a scalar or pair), for
    summaries such as ``baker inspect`` that do not know the attribute's width; at least one column is kept."""
    values = np.asarray(values)
    if values.ndim != 2:
        return values
    width = values.shape[1]
    while width > 1 and not values[:, width - 1].any():
        width -= 1
    return values[:, 0] if width == 1 else values[:, :width]
