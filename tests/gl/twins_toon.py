"""numpy twins of ``runtime-shaders/baker_toon.glsl``, in float32, one per GLSL function.

Arrays broadcast (vectors are (..., 3)); ramps are sampled as the GL spec says (LINEAR on texel centres,
CLAMP_TO_EDGE), with the sampler of the hatching twins.
"""
from __future__ import annotations

import numpy as np

from .twins_hatching import sample_linear

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a, b) -> np.ndarray:
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


def baker_toon_u(n_dot_l):
    return (F32(0.5) + F32(0.5) * np.clip(_f(n_dot_l), -1, 1)).astype(F32)


def baker_toon_ramp(ramp: np.ndarray, n_dot_l):
    """``ramp`` (1, W, C) float; LINEAR, CLAMP_TO_EDGE, sampled at (u, 0.5)."""
    u = baker_toon_u(n_dot_l)
    return sample_linear(ramp, np.stack([u, np.full_like(u, 0.5)], -1), wrap="clamp")[..., 0]


def baker_toon_bands(u, bands, softness, shadow):
    x = np.clip(_f(u), 0, 1) * F32(bands)
    if softness <= 0:
        level = np.minimum(np.floor(x), F32(bands) - 1)
    else:
        level = np.zeros(x.shape, F32)
        for k in range(1, int(bands)):
            t = np.clip((x - F32(k) + F32(0.5) * F32(softness)) / F32(softness), 0, 1)
            level += t * t * (F32(3) - F32(2) * t)
    return (F32(shadow) + (F32(1) - F32(shadow)) * level / (F32(bands) - 1)).astype(F32)


def baker_xtoon_detail_depth(z, z_min, z_max):
    return np.clip(F32(1) - np.log(_f(z) / F32(z_min)) / np.log(F32(z_max) / F32(z_min)), 0, 1).astype(F32)


def baker_xtoon_detail_orientation(N, V, r):
    return np.power(np.abs(_dot(N, V)), F32(r)).astype(F32)


def baker_xtoon(xmap: np.ndarray, n_dot_l, detail):
    u = baker_toon_u(n_dot_l)
    v = F32(1) - np.clip(_f(detail), 0, 1)
    return sample_linear(xmap, np.stack([u, v], -1), wrap="clamp")[..., 0]


def baker_rgb_to_hsv(c):
    c = _f(c)
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    mx, mn = np.maximum(np.maximum(r, g), b), np.minimum(np.minimum(r, g), b)
    delta = mx - mn
    safe = np.where(delta > 0, delta, F32(1))
    h = np.where(mx == r, (g - b) / safe, np.where(mx == g, F32(2) + (b - r) / safe, F32(4) + (r - g) / safe))
    h = np.where(delta > 0, h / F32(6), F32(0))
    h = h - np.floor(h)
    s = np.where(mx > 0, delta / np.where(mx > 0, mx, F32(1)), F32(0))
    return np.stack([h, s, mx], -1).astype(F32)


def baker_hsv_to_rgb(c):
    """f(n) = v - v s clamp(min(k, 4 - k), 0, 1), k = (n + 6 h) mod 6, n = 5, 3, 1 for r, g, b."""
    c = _f(c)
    h, s, v = c[..., 0:1], c[..., 1:2], c[..., 2:3]
    k = np.mod(_f([5.0, 3.0, 1.0]) + h * F32(6), F32(6))
    return (v - v * s * np.clip(np.minimum(k, F32(4) - k), 0, 1)).astype(F32)


def baker_quantize(x, levels):
    return (np.minimum(np.floor(_f(x) * F32(levels)), F32(levels) - 1) / (F32(levels) - 1)).astype(F32)


def baker_posterize_hsv(rgb, levels):
    hsv = baker_rgb_to_hsv(rgb)
    hsv[..., 2] = baker_quantize(hsv[..., 2], levels)
    return baker_hsv_to_rgb(hsv)


YCBCR = _f([[0.299, 0.587, 0.114], [-0.168736, -0.331264, 0.5], [0.5, -0.418688, -0.081312]])
RGB_FROM_YCBCR = _f([[1.0, 0.0, 1.402], [1.0, -0.344136, -0.714136], [1.0, 1.772, 0.0]])


def baker_posterize_ycbcr(rgb, levels):
    ycc = np.einsum("ij,...j->...i", YCBCR, _f(rgb)).astype(F32)
    ycc[..., 0] = baker_quantize(ycc[..., 0], levels)
    return np.clip(np.einsum("ij,...j->...i", RGB_FROM_YCBCR, ycc), 0, 1).astype(F32)
