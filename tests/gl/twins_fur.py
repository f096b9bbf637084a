"""numpy twins of ``runtime-shaders/baker_fur.glsl``: the same math in float32, one function per GLSL function,
broadcasting over (..., 3) vectors so a whole image of inputs is shaded at once."""
from __future__ import annotations

import numpy as np

from .twins_hair import mix, normalize, smoothstep

F32 = np.float32


def _f(x):
    return np.asarray(x, dtype=F32)


def _dot(a, b):
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


def baker_fur_shell_height(shell, shell_count):
    return (_f(shell) + F32(0.5)) / F32(shell_count)


def baker_fur_shell_position(position, normal, shell, spacing, count, displacement):
    h = (_f(shell) + F32(1)) / F32(count)
    return _f(position) + _f(normal) * ((_f(shell) + F32(1)) * F32(spacing))[..., None] \
        + _f(displacement) * (h * h)[..., None]


def baker_fur_shell_shade(texel, height, occlusion_at_root):
    texel = _f(texel)
    rgb = texel[..., :3] * mix(occlusion_at_root, 1.0, height)[..., None]
    return np.concatenate([rgb, texel[..., 3:4]], axis=-1)


def baker_fur_fin_face_normals(v0, v1, v2, v3):
    return normalize(np.cross(_f(v1) - _f(v0), _f(v2) - _f(v0))), normalize(np.cross(_f(v0) - _f(v1), _f(v3) - _f(v1)))


def baker_fur_fin_position(v0, v1, normal, corner, fin_length):
    corner = _f(corner)
    base = np.where(((corner < 0.5) | (corner > 2.5))[..., None], _f(v0), _f(v1))
    up = np.where(corner > 1.5, F32(1), F32(0))
    return base + _f(normal) * (F32(fin_length) * up)[..., None]


def baker_fur_fin_weight(n0, n1, V, threshold):
    n = normalize(_f(n0) + _f(n1))
    return F32(1) - smoothstep(0.0, threshold, np.abs(_dot(n, V)))


def baker_fur_shell_uv(uv, tiling):
    return _f(uv) * F32(tiling)
