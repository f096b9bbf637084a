"""numpy twins of ``runtime-shaders/baker_edges.glsl``: the same math in float32, one function per GLSL one.

Vectors are (..., n) arrays and scalars (...) arrays or Python numbers, so a twin runs over all vertices or pixels
at once. Keep each body a line-for-line transcription of its GLSL function.
"""
from __future__ import annotations

import numpy as np

F32 = np.float32
BAKER_EDGE_BOUNDARY, BAKER_EDGE_NON_MANIFOLD = 1, 2
BAKER_FIN_CONTOUR, BAKER_FIN_RIDGE, BAKER_FIN_VALLEY, BAKER_FIN_BOUNDARY = 1, 2, 4, 8


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a, b) -> np.ndarray:
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


def baker_fin_classify(v0, v1, v2, v3, flags, eye, crease_cos) -> np.ndarray:
    v0, v1, v2, v3, eye = map(_f, (v0, v1, v2, v3, eye))
    f = (_f(flags) + F32(0.5)).astype(np.int32)
    n0 = np.cross(v1 - v0, v2 - v0).astype(F32)
    n1 = np.cross(v0 - v1, v3 - v1).astype(F32)
    to_eye = eye - v0
    result = np.where(_dot(n0, to_eye) * _dot(n1, to_eye) < 0, BAKER_FIN_CONTOUR, 0)
    len0, len1 = np.sqrt(_dot(n0, n0)), np.sqrt(_dot(n1, n1))
    crease = (len0 > 0) & (len1 > 0) & (_dot(n0, n1) < F32(crease_cos) * len0 * len1)
    ridge = _dot(n0, v3 - v0) <= 0
    result = result | np.where(crease, np.where(ridge, BAKER_FIN_RIDGE, BAKER_FIN_VALLEY), 0)
    return np.where((f & (BAKER_EDGE_BOUNDARY | BAKER_EDGE_NON_MANIFOLD)) != 0, BAKER_FIN_BOUNDARY, result)


def baker_fin_position(clip0, clip1, corner, width_px, viewport) -> np.ndarray:
    clip0, clip1, viewport = _f(clip0), _f(clip1), _f(viewport)
    s0 = clip0[..., :2] / clip0[..., 3:4] * viewport
    s1 = clip1[..., :2] / clip1[..., 3:4] * viewport
    d = s1 - s0
    length = np.sqrt(_dot(d, d))
    direction = np.where((length > 1e-6)[..., None], d / np.maximum(length, F32(1e-30))[..., None],
                         np.array([1.0, 0.0], F32))
    normal = np.stack([-direction[..., 1], direction[..., 0]], axis=-1)
    c = (_f(corner) + F32(0.5)).astype(np.int32)
    at_v1 = (c == 1) | (c == 2)
    side = np.where(c < 2, F32(-0.5), F32(0.5))[..., None]
    along = np.where(at_v1, F32(0.5), F32(-0.5))[..., None]
    at = np.where(at_v1[..., None], clip1, clip0)
    offset = (normal * side + direction * along) * F32(width_px) * F32(2.0) / viewport
    return np.concatenate([at[..., :2] + offset * at[..., 3:4], at[..., 2:]], axis=-1).astype(F32)


def baker_fin_culled() -> np.ndarray:
    return np.array([2.0, 2.0, 2.0, 1.0], F32)


def baker_shell_position(position, outline_normal, clip_w, width_px, viewport_height, projection_scale_y):
    units_per_pixel = F32(2.0) * _f(clip_w) / (F32(viewport_height) * F32(projection_scale_y))
    return (_f(position) + _f(outline_normal) * (F32(width_px) * units_per_pixel)[..., None]).astype(F32)


def baker_barycentric(vertex_id) -> np.ndarray:
    k = np.asarray(vertex_id) % 3
    return np.stack([k == 0, k == 1, k == 2], axis=-1).astype(F32)


def baker_wireframe_distance(bary, bary_slope, mask) -> np.ndarray:
    d = _f(bary) / np.maximum(_f(bary_slope), F32(1e-8))
    mask = np.asarray(mask)
    big = F32(1e6)
    best = np.full(d.shape[:-1], big, F32)
    best = np.where((mask & 1) != 0, np.minimum(best, d[..., 2]), best)
    best = np.where((mask & 2) != 0, np.minimum(best, d[..., 0]), best)
    best = np.where((mask & 4) != 0, np.minimum(best, d[..., 1]), best)
    return best


def baker_wireframe(bary, bary_slope, mask, width_px, halo_px) -> np.ndarray:
    d = baker_wireframe_distance(bary, bary_slope, mask)
    line = np.clip(F32(0.5) * F32(width_px) - d + F32(0.5), 0, 1)
    halo = np.clip(F32(0.5) * F32(width_px) + F32(halo_px) - d + F32(0.5), 0, 1)
    return np.stack([line, halo], axis=-1).astype(F32)
