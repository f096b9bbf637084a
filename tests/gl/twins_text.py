"""numpy twins of ``runtime-shaders/baker_text.glsl``: the same math in float32, one function per GLSL one.

Texels are (..., 4) arrays, scalars broadcast. Keep each body a line-for-line transcription of its GLSL function.
"""
from __future__ import annotations

import numpy as np

F32 = np.float32
SDF, PSDF, MSDF, MTSDF = 0, 1, 2, 3


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def smoothstep(e0, e1, x):
    t = np.clip((_f(x) - _f(e0)) / (_f(e1) - _f(e0)), F32(0), F32(1))
    return t * t * (F32(3) - F32(2) * t)


def baker_text_median(v) -> np.ndarray:
    v = _f(v)
    r, g, b = v[..., 0], v[..., 1], v[..., 2]
    return np.maximum(np.minimum(r, g), np.minimum(np.maximum(r, g), b))


def baker_text_screen_px_range(distance_range, atlas_size, uv_fwidth) -> np.ndarray:
    unit = _f(distance_range) / _f(atlas_size)
    screen = F32(1) / np.maximum(_f(uv_fwidth), F32(1e-12))
    return np.maximum(F32(0.5) * np.sum(unit * screen, axis=-1, dtype=F32), F32(1))


def baker_text_edge_distance(texel, field_type: int) -> np.ndarray:
    texel = _f(texel)
    v = baker_text_median(texel[..., :3]) if field_type >= MSDF else texel[..., 0]
    return v - F32(0.5)


def baker_text_true_distance(texel, field_type: int) -> np.ndarray:
    if field_type == MTSDF:
        return _f(texel)[..., 3] - F32(0.5)
    return baker_text_edge_distance(texel, field_type)


def baker_text_coverage(signed_distance, screen_px_range) -> np.ndarray:
    return np.clip(_f(signed_distance) * _f(screen_px_range) + F32(0.5), F32(0), F32(1))


def baker_text_msdf_opacity(msd, screen_px_range) -> np.ndarray:
    return baker_text_coverage(baker_text_median(msd) - F32(0.5), screen_px_range)


def baker_text_over(src, dst) -> np.ndarray:
    src, dst = _f(src), _f(dst)
    return src + dst * (F32(1) - src[..., 3:4])


def _layer(color, alpha) -> np.ndarray:
    color = _f(color)
    rgb1 = np.concatenate([color[:3], [F32(1)]]).astype(F32)
    return rgb1 * (color[3] * _f(alpha))[..., None]


def baker_text_shade(style: dict, texel, shadow_texel, field_type: int, distance_range, screen_px_range):
    """``style``: the BakerTextStyle fields by name (colors as 4-sequences)."""
    px_per_texel = _f(screen_px_range) / _f(distance_range)
    ramp = F32(1) + max(F32(style["softness"]), F32(0))
    d = baker_text_edge_distance(texel, field_type) * _f(distance_range)
    dt = baker_text_true_distance(texel, field_type) * _f(distance_range)
    ds = baker_text_true_distance(shadow_texel, field_type) * _f(distance_range)

    fill = np.clip(d * px_per_texel / ramp + F32(0.5), F32(0), F32(1))
    if style["outlineWidth"] > 0:
        outline = np.clip((d + F32(style["outlineWidth"])) * px_per_texel / ramp + F32(0.5), F32(0), F32(1))
    else:
        outline = np.zeros_like(fill)
    glow = F32(1) - smoothstep(F32(0), F32(style["glowWidth"]), -dt) if style["glowWidth"] > 0 else np.zeros_like(fill)
    blur = max(F32(style["shadowSoftness"]), F32(0)) + F32(0.5) / px_per_texel
    shadow = smoothstep(-blur, blur, ds)

    result = _layer(style["shadowColor"], shadow)
    result = baker_text_over(_layer(style["glowColor"], glow), result)
    result = baker_text_over(_layer(style["outlineColor"], outline), result)
    result = baker_text_over(_layer(style["color"], fill), result)
    return result
