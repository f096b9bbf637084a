"""numpy twins of ``runtime-shaders/baker_skin.glsl``: the same math in float32, one function per GLSL one.

Textures are (H, W, C) float32 arrays sampled like GLSL ``texture()`` with LINEAR filtering and CLAMP_TO_EDGE, row 0
at t = 0. Vectors are (..., 3), scalars (...) or floats. Keep each body a transcription of its GLSL function.
"""
from __future__ import annotations

import numpy as np

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a, b) -> np.ndarray:
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


def normalize(v) -> np.ndarray:
    v = _f(v)
    return v / np.sqrt(_dot(v, v))[..., None]


def mix(a, b, t):
    return _f(a) * (F32(1.0) - _f(t)) + _f(b) * _f(t)


def smoothstep(e0, e1, x):
    t = np.clip((_f(x) - _f(e0)) / (_f(e1) - _f(e0)), F32(0.0), F32(1.0))
    return t * t * (F32(3.0) - F32(2.0) * t)


def texture_linear(image: np.ndarray, uv) -> np.ndarray:
    """GLSL texture() of a (H, W, C) image with LINEAR min/mag filter and CLAMP_TO_EDGE; uv (..., 2)."""
    image = _f(image)
    h, w = image.shape[:2]
    uv = _f(uv)
    s = uv[..., 0] * F32(w) - F32(0.5)
    t = uv[..., 1] * F32(h) - F32(0.5)
    x0, y0 = np.floor(s), np.floor(t)
    fx, fy = (s - x0)[..., None], (t - y0)[..., None]
    x0i, y0i = x0.astype(np.int64), y0.astype(np.int64)
    xa, xb = np.clip(x0i, 0, w - 1), np.clip(x0i + 1, 0, w - 1)
    ya, yb = np.clip(y0i, 0, h - 1), np.clip(y0i + 1, 0, h - 1)
    top = image[ya, xa] * (F32(1) - fx) + image[ya, xb] * fx
    bottom = image[yb, xa] * (F32(1) - fx) + image[yb, xb] * fx
    return top * (F32(1) - fy) + bottom * fy


def baker_skin_lut_coord(t, size):
    return (np.clip(_f(t), F32(0.0), F32(1.0)) * (_f(size) - F32(1.0)) + F32(0.5)) / _f(size)


def baker_skin_curvature(mesh_curvature, curvature_scale):
    return np.maximum(_f(mesh_curvature), F32(0.0)) * _f(curvature_scale)


def baker_skin_curvature_from_derivatives(fwidth_n, fwidth_p):
    return np.sqrt(_dot(fwidth_n, fwidth_n)) / np.maximum(np.sqrt(_dot(fwidth_p, fwidth_p)), F32(1e-20))


def baker_skin_curvature_along_light(principal, direction, N, L):
    N, L, direction, principal = _f(N), _f(L), _f(direction), _f(principal)
    t = L - N * _dot(N, L)[..., None]
    d1 = direction - N * _dot(N, direction)[..., None]
    d2 = np.cross(N, d1).astype(F32)
    c = _dot(t, d1)
    s = _dot(t, d2)
    cos2a = (c * c - s * s) / np.maximum(_dot(t, t), F32(1e-6))
    k1, k2 = principal[..., 0], principal[..., 1]
    return F32(0.5) * (k1 + k2) + F32(0.5) * (k1 - k2) * cos2a


def baker_skin_direction_to(linear, direction):
    direction = _f(direction)
    d = direction @ _f(linear).T
    return d * (np.sqrt(_dot(direction, direction)) / np.maximum(np.sqrt(_dot(d, d)), F32(1e-20)))[..., None]


def baker_skin_lut_uv(ndotl, curvature, curvature_range, lut_size):
    u = _f(ndotl) * F32(0.5) + F32(0.5)
    lo, hi = _f(curvature_range[0]), _f(curvature_range[1])
    v = (_f(curvature) - lo) / (hi - lo)
    return np.stack([baker_skin_lut_coord(u, lut_size[0]), baker_skin_lut_coord(v, lut_size[1])], axis=-1)


def baker_skin_lut(lut: np.ndarray, ndotl, curvature, curvature_range):
    size = (lut.shape[1], lut.shape[0])
    return texture_linear(lut, baker_skin_lut_uv(ndotl, curvature, curvature_range, size))[..., :3]


def baker_skin_blended_ndotl(n_smooth, n_detail, L, normal_blend):
    out = [_dot(normalize(mix(n_detail, n_smooth, F32(normal_blend[c]))), L) for c in range(3)]
    return np.stack(out, axis=-1)


def baker_skin_lut_rgb(lut, ndotl, curvature, curvature_range):
    return np.stack([baker_skin_lut(lut, ndotl[..., c], curvature, curvature_range)[..., c] for c in range(3)],
                    axis=-1)


def baker_skin_penumbra(penumbra_lut, shadow, penumbra_width, width_range):
    size = (penumbra_lut.shape[1], penumbra_lut.shape[0])
    lo, hi = _f(width_range[0]), _f(width_range[1])
    v = (F32(1.0) / np.maximum(_f(penumbra_width), F32(1e-20)) - lo) / (hi - lo)
    uv = np.stack(np.broadcast_arrays(baker_skin_lut_coord(shadow, size[0]), baker_skin_lut_coord(v, size[1])), -1)
    return texture_linear(penumbra_lut, uv)[..., :3]


def baker_skin_wrap(ndotl, wrap, scatter_width, scatter_color):
    diffuse = np.maximum((_f(ndotl) + _f(wrap)) / (F32(1.0) + _f(wrap)), F32(0.0))
    w = _f(scatter_width)
    scatter = smoothstep(F32(0.0), w, diffuse) * (F32(1.0) - smoothstep(w, F32(2.0) * w, diffuse))
    return diffuse[..., None] + scatter[..., None] * _f(scatter_color)


def baker_skin_diffuse(params: dict, lut, n_smooth, n_detail, L, mesh_curvature):
    ndotl = baker_skin_blended_ndotl(n_smooth, n_detail, L, params["normalBlend"])
    curvature = baker_skin_curvature(mesh_curvature, params["curvatureScale"])
    return baker_skin_lut_rgb(lut, ndotl, curvature, params["curvatureRange"])


def baker_skin_diffuse_normals(params: dict, lut, ndotl, mesh_curvature):
    curvature = baker_skin_curvature(mesh_curvature, params["curvatureScale"])
    return baker_skin_lut_rgb(lut, ndotl, curvature, params["curvatureRange"])
