"""numpy twins of ``runtime-shaders/baker_translucency.glsl``: the same math, in float32, one function per GLSL one.

Arrays broadcast: vectors are (..., 3), scalars (...) or Python floats, so a twin shades a whole image of pass-1
inputs at once. Keep each body a line-for-line transcription of its GLSL function.
"""
from __future__ import annotations

import numpy as np

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sum(a * b, axis=-1, dtype=F32)


def normalize(v) -> np.ndarray:
    """GLSL ``normalize``."""
    v = _f(v)
    return v / np.sqrt(_dot(v, v))[..., None]


def baker_thickness_from_texture(texel, thickness_factor) -> np.ndarray:
    """Thickness in mesh units from an RGBA texel (..., 4) of KHR_materials_volume.thicknessTexture (green)."""
    return _f(texel)[..., 1] * _f(thickness_factor)


def baker_thickness_transmittance(thickness, attenuation_distance) -> np.ndarray:
    """Beer-Lambert t_ss = exp(-max(thickness, 0) / attenuationDistance)."""
    return np.exp(-np.maximum(_f(thickness), F32(0.0)) / _f(attenuation_distance))


def baker_translucency_rtr(V, L, tss, subsurface_color, power) -> np.ndarray:
    """RTR4 eq. 14.30: tss * c_ss * ((V . -L)^+)^p; returns (..., 3)."""
    forward = np.maximum(_dot(_f(V), -_f(L)), F32(0.0))
    return _f(tss)[..., None] * _f(subsurface_color) * np.power(forward, _f(power))[..., None]


def baker_translucency_gdc(N, V, L, tss, subsurface_color, distortion, power, scale, ambient) -> np.ndarray:
    """GDC 2011: c_ss * (pow(clamp(V . -normalize(L + N d), 0, 1), p) * scale + ambient) * tss; returns (..., 3)."""
    bent = _f(L) + _f(N) * _f(distortion)[..., None]
    lt = bent / np.sqrt(np.maximum(_dot(bent, bent), F32(1e-12)))[..., None]
    back = np.power(np.clip(_dot(_f(V), -lt), F32(0.0), F32(1.0)), _f(power)) * _f(scale)
    return _f(subsurface_color) * ((back + _f(ambient)) * _f(tss))[..., None]


def baker_translucency(params: dict, N, V, L, thickness) -> np.ndarray:
    """The GDC variant with a ``BakerThickness``-shaped dict (the BAKER_thickness extension's field names)."""
    tss = baker_thickness_transmittance(thickness, params["attenuationDistance"])
    return baker_translucency_gdc(N, V, L, tss, params["subsurfaceColor"], params["distortion"], params["power"],
                                  params["scale"], params["ambient"])
