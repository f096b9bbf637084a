"""numpy twins of ``runtime-shaders/baker_hair_cards.glsl``, in float32, one per GLSL function."""
from __future__ import annotations

import numpy as np

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a, b):
    return (_f(a) * _f(b)).sum(-1).astype(F32)


def _normalize(v):
    v = _f(v)
    return (v / np.sqrt(_dot(v, v))[..., None]).astype(F32)


def smoothstep(e0, e1, x):
    t = np.clip((_f(x) - F32(e0)) / F32(e1 - e0), 0, 1)
    return (t * t * (F32(3) - F32(2) * t)).astype(F32)


def baker_hair_cards_cut(alpha, alpha_cutoff):
    return _f(alpha) < F32(alpha_cutoff)


def baker_hair_cards_flow(flow_texel, normal, tangent):
    f = _f(flow_texel) * F32(2) - F32(1)
    n = _normalize(normal)
    tangent = _f(tangent)
    t = _normalize(tangent[..., :3] - n * _dot(n, tangent[..., :3])[..., None])
    b = np.cross(n, t) * tangent[..., 3:4]
    w = f[..., :1] * t + f[..., 1:2] * b + f[..., 2:3] * n
    length = np.sqrt(_dot(w, w))[..., None]
    return np.where(length > 1e-6, w / np.maximum(length, F32(1e-30)), b).astype(F32)


def baker_hair_cards_frame(N, dpdx, dpdy, duvdx, duvdy):
    N, dpdx, dpdy, duvdx, duvdy = (_f(x) for x in (N, dpdx, dpdy, duvdx, duvdy))
    dp2perp = np.cross(dpdy, N)
    dp1perp = np.cross(N, dpdx)
    facing = np.where(_dot(np.cross(dpdx, dpdy), N) < 0, F32(-1), F32(1))[..., None]
    across = (dp2perp * duvdx[..., :1] + dp1perp * duvdy[..., :1]) * facing
    along = (dp2perp * duvdx[..., 1:2] + dp1perp * duvdy[..., 1:2]) * facing
    length = np.sqrt(_dot(across, across))[..., None]
    t = np.where(length > 0, across / np.maximum(length, F32(1e-38)), np.array([1, 0, 0], F32))
    w = np.where(_dot(np.cross(N, across), along) < 0, F32(-1), F32(1))[..., None]
    return np.concatenate([t, w], -1).astype(F32)


def baker_hair_cards_depth(depth_texel, depth_range):
    return ((_f(depth_texel) * F32(2) - F32(1)) * F32(depth_range)).astype(F32)


def baker_hair_cards_displace(position, normal, depth_texel, depth_range):
    return (_f(position) + _normalize(normal) * baker_hair_cards_depth(depth_texel, depth_range)[..., None]).astype(F32)


def baker_hair_cards_shade(base_color, T, N, L, V, light_color, root_to_tip, strand_random, exponent, shift,
                           root_shade):
    T, r = _f(T), _f(strand_random)
    t = _normalize(T + (F32(shift) + (r - F32(0.5)) * F32(0.2))[..., None] * _normalize(N))
    tl = _dot(T, L)
    sin_tl = np.sqrt(np.maximum(0, F32(1) - tl * tl))
    H = _normalize(_f(L) + _f(V))
    th = _dot(t, H)
    sin_th = np.sqrt(np.maximum(0, F32(1) - th * th))
    spec = smoothstep(-1.0, 0.0, th) * np.power(sin_th, F32(exponent))
    occlusion = F32(root_shade) + (F32(1) - F32(root_shade)) * np.clip(_f(root_to_tip), 0, 1)
    return (_f(light_color) * occlusion[..., None] * (_f(base_color) * sin_tl[..., None] + F32(0.25) *
            (spec * (F32(0.5) + r))[..., None])).astype(F32)
