"""numpy twins of ``runtime-shaders/baker_normal_blur.glsl``: the same math in float32, one function per GLSL one.

Textures are (H, W, C) float32 arrays sampled like GLSL ``texture()`` with LINEAR filtering and CLAMP_TO_EDGE, row 0
at t = 0 (:func:`tests.gl.twins_skin.texture_linear`). Vectors are (..., 3); ``tbn`` a (3, 3) matrix whose columns
are T, B, N. Keep each body a transcription of its GLSL function.
"""
from __future__ import annotations

import numpy as np

from .twins_skin import F32, _dot, _f, mix, normalize, texture_linear


def _times(tbn, v):
    """tbn (3, 3) or (..., 3, 3), columns T, B, N, times v (..., 3)."""
    return np.einsum("...ij,...j->...i", _f(tbn), _f(v)).astype(F32)


def baker_normal_blur_decode(texel, flip_y):
    n = _f(texel) * F32(2.0) - F32(1.0)
    n = n.copy()
    n[..., 1] *= F32(flip_y)
    return normalize(n)


def baker_normal_blur_derivative_frame(N, dPdx, dPdy, dUVdx, dUVdy):
    """(..., 3, 3) matrices whose columns are T, B, N (as GLSL's mat3 of three columns)."""
    N, dPdx, dPdy, dUVdx, dUVdy = map(_f, (N, dPdx, dPdy, dUVdx, dUVdy))
    dp2perp = np.cross(dPdy, N).astype(F32)
    dp1perp = np.cross(N, dPdx).astype(F32)
    T = dp2perp * dUVdx[..., 0:1] + dp1perp * dUVdy[..., 0:1]
    B = dp2perp * dUVdx[..., 1:2] + dp1perp * dUVdy[..., 1:2]
    scale = F32(1.0) / np.sqrt(np.maximum(np.maximum(_dot(T, T), _dot(B, B)), F32(1e-30)))
    return np.stack([T * scale[..., None], -B * scale[..., None], N], axis=-1)


def baker_normal_blur_ndotl(n_red, n_green, n_blue, L):
    return np.stack([_dot(n_red, L), _dot(n_green, L), _dot(n_blue, L)], axis=-1)


def baker_normal_blur_lambert(tbn, texel_red, texel_green, texel_blue, L, flip_y):
    ndotl = baker_normal_blur_ndotl(normalize(_times(tbn, baker_normal_blur_decode(texel_red, flip_y))),
                                    normalize(_times(tbn, baker_normal_blur_decode(texel_green, flip_y))),
                                    normalize(_times(tbn, baker_normal_blur_decode(texel_blue, flip_y))), L)
    return np.clip(ndotl, F32(0.0), F32(1.0))


def baker_normal_blur_blend_ndotl(tbn, texel_smoothed, channel_blend, L, flip_y):
    s = baker_normal_blur_decode(texel_smoothed, flip_y)
    up = _f([0.0, 0.0, 1.0])
    out = [_dot(normalize(_times(tbn, normalize(mix(s, up, F32(t))))), L) for t in channel_blend]
    return np.stack(out, axis=-1)


def baker_normal_blur_stretch(stretch_texture, uv, stretch_scale):
    return texture_linear(stretch_texture, uv)[..., :2] * F32(stretch_scale)


def baker_normal_blur_uv_position(uv):
    uv = _f(uv)
    return np.concatenate([uv * F32(2.0) - F32(1.0), np.zeros(uv.shape[:-1] + (1,), F32),
                           np.ones(uv.shape[:-1] + (1,), F32)], axis=-1)


def baker_normal_blur_tsd_accumulate(total, blurred, weights):
    return _f(total) + _f(weights) * _f(blurred)


TAPS7 = (0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006)


def baker_normal_blur_tsd_step(irradiance, stretch_texture, uv, direction, sigma, stretch_scale):
    stretch = np.maximum(baker_normal_blur_stretch(stretch_texture, uv, stretch_scale), F32(1e-12))
    step = _f(direction) * F32(sigma) / stretch
    total = np.zeros(np.shape(uv)[:-1] + (3,), F32)
    for i, w in enumerate(TAPS7):
        total += F32(w) * texture_linear(irradiance, _f(uv) + F32(i - 3) * step)[..., :3]
    return total
