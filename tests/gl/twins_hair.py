"""numpy twins of ``runtime-shaders/baker_hair.glsl``: the same math in float32, one function per GLSL function, broadcasting over (..., 3) vectors so a whole image of inputs is shaded at once."""
from __future__ import annotations

import numpy as np

F32 = np.float32
PI = F32(3.14159265358979)


def _f(x):
    return np.asarray(x, dtype=F32)


def _dot(a, b):
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


def normalize(v):
    v = _f(v)
    return v / np.sqrt(_dot(v, v))[..., None]


def smoothstep(e0, e1, x):
    t = np.clip((_f(x) - F32(e0)) / (F32(e1) - F32(e0)), 0, 1)
    return t * t * (F32(3) - F32(2) * t)


def mix(a, b, t):
    return _f(a) * (F32(1) - _f(t)) + _f(b) * _f(t)


# ------------------------------------------------------------------------------------------------ hair geometry
def baker_hair_width(root_width, tip_width, param, width_scale):
    return mix(root_width, tip_width, param) * _f(width_scale)


def baker_hair_pixel_size(view_distance, tan_half_fovy, viewport_height):
    return F32(2) * _f(view_distance) * F32(tan_half_fovy) / F32(viewport_height)


def baker_hair_coverage(width, pixel_size):
    w, p = _f(width), _f(pixel_size)
    return np.stack([np.maximum(w, p), np.clip(w / np.maximum(p, F32(1e-20)), 0, 1)], axis=-1)


def baker_hair_ribbon_side(position, tangent, eye):
    s = np.cross(_f(tangent), _f(eye) - _f(position)).astype(F32)
    length = np.sqrt(_dot(s, s))
    t = _f(tangent)
    alt = np.where((np.abs(t[..., 1]) < 0.9)[..., None], np.array([0, 1, 0], F32), np.array([1, 0, 0], F32))
    s2 = np.cross(t, alt).astype(F32)
    bad = length < 1e-12
    s = np.where(bad[..., None], s2, s)
    length = np.where(bad, np.sqrt(_dot(s2, s2)), length)
    return s / length[..., None]


def baker_hair_offset_child(child_root, weights, guide0, guide_root0, guide1, guide_root1, guide2, guide_root2):
    w = _f(weights)
    return (_f(child_root) + w[..., 0:1] * (_f(guide0) - _f(guide_root0)) + w[..., 1:2] * (_f(guide1) - _f(guide_root1))
            + w[..., 2:3] * (_f(guide2) - _f(guide_root2)))


def baker_hair_lod_index_count(strand_count, vertices_per_strand):
    return np.asarray(strand_count, np.int32) * 6 * (np.asarray(vertices_per_strand, np.int32) - 1)


def baker_hair_lod_width(width, lod_width_scale):
    return _f(width) * _f(lod_width_scale)


def baker_hair_ribbon_position(position, tangent, eye, width, side):
    return _f(position) + baker_hair_ribbon_side(position, tangent, eye) * (_f(width) * (_f(side) - F32(0.5)))[..., None]


# ------------------------------------------------------------------------------------------------ hair shading
def baker_hair_kajiya_kay(T, L, V, diffuse_color, specular_color, exponent):
    tl, tv = _dot(T, L), _dot(T, V)
    sin_tl = np.sqrt(np.maximum(0, F32(1) - tl * tl))
    sin_tv = np.sqrt(np.maximum(0, F32(1) - tv * tv))
    spec = np.power(np.maximum(F32(0), sin_tl * sin_tv - tl * tv), F32(exponent))
    return _f(diffuse_color) * sin_tl[..., None] + _f(specular_color) * spec[..., None]


def baker_hair_shift_tangent(T, N, shift):
    return normalize(_f(T) + F32(shift) * _f(N))


def baker_hair_strand_specular(T, V, L, exponent):
    H = normalize(_f(L) + _f(V))
    th = _dot(T, H)
    sin_th = np.sqrt(np.maximum(0, F32(1) - th * th))
    return smoothstep(-1.0, 0.0, th) * np.power(sin_th, F32(exponent))


def baker_hair_scheuermann(T, N, V, L, base_color, spec1, spec2, shift1, shift2, exp1, exp2, mask):
    t1 = baker_hair_shift_tangent(T, N, shift1)
    t2 = baker_hair_shift_tangent(T, N, shift2)
    diffuse = np.clip(mix(0.25, 1.0, _dot(N, L)), 0, 1)
    spec = _f(spec1) * baker_hair_strand_specular(t1, V, L, exp1)[..., None] \
        + _f(spec2) * (_f(mask) * baker_hair_strand_specular(t2, V, L, exp2))[..., None]
    return _f(base_color) * diffuse[..., None] + spec * diffuse[..., None]


def baker_hair_gaussian(beta, x):
    beta = F32(beta)
    return np.exp(F32(-0.5) * _f(x) * _f(x) / (beta * beta)) / (np.sqrt(F32(2) * PI) * beta)


def baker_hair_fresnel(cos_theta):
    f0 = F32(0.0465)
    m = F32(1) - np.clip(_f(cos_theta), 0, 1)
    return f0 + (F32(1) - f0) * m * m * m * m * m


def baker_hair_marschner(T, V, L, base_color, roughness, shift):
    sin_l = np.clip(_dot(T, L), -1, 1)
    sin_v = np.clip(_dot(T, V), -1, 1)
    cos_td = np.cos(F32(0.5) * np.abs(np.arcsin(sin_v) - np.arcsin(sin_l)))
    lp = _f(L) - sin_l[..., None] * _f(T)
    vp = _f(V) - sin_v[..., None] * _f(T)
    cos_phi = _dot(lp, vp) / np.sqrt(_dot(lp, lp) * _dot(vp, vp) + F32(1e-4))
    cos_half = np.sqrt(np.clip(F32(0.5) + F32(0.5) * cos_phi, 0, 1))
    beta = max(F32(roughness) * F32(roughness), F32(1e-3))
    shift = F32(shift)
    x = sin_l + sin_v
    m_r = baker_hair_gaussian(beta, x + F32(2) * shift)
    n_r = F32(0.25) * cos_half
    a_r = baker_hair_fresnel(np.sqrt(np.clip(F32(0.5) + F32(0.5) * _dot(L, V), 0, 1)))
    m_tt = baker_hair_gaussian(F32(0.5) * beta, x - shift)
    n_tt = np.exp(F32(-3.65) * cos_phi - F32(3.98))
    f_t = baker_hair_fresnel(cos_td * F32(0.5))
    base = _f(base_color)
    absorb_tt = np.power(base, (F32(0.5) / np.maximum(cos_td, F32(0.05)))[..., None])
    m_trt = baker_hair_gaussian(F32(2) * beta, x - F32(4) * shift)
    n_trt = np.exp(F32(17) * cos_phi - F32(16.78))
    absorb_trt = np.power(base, (F32(0.8) / np.maximum(cos_td, F32(0.05)))[..., None])
    return (m_r * n_r * a_r)[..., None] + (m_tt * n_tt * (1 - f_t) * (1 - f_t))[..., None] * absorb_tt \
        + (m_trt * n_trt * (1 - f_t) * (1 - f_t) * f_t)[..., None] * absorb_trt * absorb_trt
