"""numpy twins of ``runtime-shaders/baker_hatching.glsl`` and ``baker_toon.glsl``, in float32, one per GLSL function.

Arrays broadcast (vectors are (..., 3)); texture sampling follows the GL spec: LINEAR filtering on texel centres
with REPEAT or CLAMP_TO_EDGE wrapping, and LINEAR_MIPMAP_LINEAR between the two levels around the LOD.
"""
from __future__ import annotations

import numpy as np

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _dot(a, b) -> np.ndarray:
    return np.sum(_f(a) * _f(b), axis=-1, dtype=F32)


# ---------------------------------------------------------------------------------------------------------- sampling
def sample_linear(image: np.ndarray, uv: np.ndarray, wrap: str = "repeat") -> np.ndarray:
    """GL LINEAR sampling of ``image`` (H, W, C) float at ``uv`` (..., 2) (u along columns, v along rows)."""
    h, w = image.shape[:2]
    x = _f(uv[..., 0]) * F32(w) - F32(0.5)
    y = _f(uv[..., 1]) * F32(h) - F32(0.5)
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    if wrap == "repeat":
        xs, ys = (x0 % w, (x0 + 1) % w), (y0 % h, (y0 + 1) % h)
    else:
        xs, ys = (np.clip(x0, 0, w - 1), np.clip(x0 + 1, 0, w - 1)), (np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1))
    top = image[ys[0], xs[0]] * (1 - fx) + image[ys[0], xs[1]] * fx
    bottom = image[ys[1], xs[0]] * (1 - fx) + image[ys[1], xs[1]] * fx
    return (top * (1 - fy) + bottom * fy).astype(F32)


def texture_lod(levels: list, uv: np.ndarray, lod: np.ndarray) -> np.ndarray:
    """GL ``textureLod`` with LINEAR_MIPMAP_LINEAR on a custom chain ``levels`` (finest first), REPEAT."""
    lod = np.clip(_f(lod), 0, len(levels) - 1)
    d1 = np.floor(lod).astype(np.int64)
    frac = (lod - d1)[..., None]
    out = np.zeros(uv.shape[:-1] + (levels[0].shape[2],), F32)
    for i in range(len(levels)):
        sel1 = d1 == i
        sel2 = np.minimum(d1 + 1, len(levels) - 1) == i
        if sel1.any() or sel2.any():
            s = sample_linear(levels[i], uv)
            out += np.where(sel1[..., None], s * (1 - frac), 0) + np.where(sel2[..., None], s * frac, 0)
    return out.astype(F32)


# ---------------------------------------------------------------------------------------------------------- hatching
def baker_tam_coord(uv, scale, finest_size):
    return _f(uv) * (F32(scale) / F32(finest_size))


def baker_tam_lod(d_tile_dx, d_tile_dy, finest_size, level_count):
    dx, dy = _f(d_tile_dx) * F32(finest_size), _f(d_tile_dy) * F32(finest_size)
    rho2 = np.maximum(_dot(dx, dx), _dot(dy, dy))
    return np.clip(F32(0.5) * np.log2(np.maximum(rho2, F32(1e-20))), 0, F32(level_count) - 1).astype(F32)


def baker_hatching_weights(darkness, tones_a, tones_b):
    """(wA (..., 3), wB (..., 3), wPaper (...))."""
    d = np.clip(_f(darkness), 0, 1)[..., None]
    ta, tb = _f(tones_a), _f(tones_b)
    prev_a, next_a = _f([0.0, ta[0], ta[1]]), _f([ta[1], ta[2], tb[0]])
    prev_b, next_b = _f([ta[2], tb[0], tb[1]]), _f([tb[1], tb[2], 1.0])
    wa = np.maximum(np.minimum((d - prev_a) / (ta - prev_a), (next_a - d) / (next_a - ta)), F32(0))
    wb = np.maximum(np.minimum((d - prev_b) / (tb - prev_b), (next_b - d) / (next_b - tb)), F32(0))
    paper = np.maximum(F32(1) - d[..., 0] / ta[0], F32(0))
    return wa.astype(F32), wb.astype(F32), paper.astype(F32)


def baker_hatching(levels_a, levels_b, tile, lod, darkness, tones_a, tones_b):
    """Brightness; ``levels_a``/``levels_b`` are the chains (finest first) of (R, R, 3+) float textures."""
    wa, wb, paper = baker_hatching_weights(darkness, tones_a, tones_b)
    a = texture_lod(levels_a, tile, lod)[..., :3]
    b = texture_lod(levels_b, tile, lod)[..., :3]
    return (paper + _dot(wa, a) + _dot(wb, b)).astype(F32)


def baker_hatching_darkness(N, L, intensity):
    return np.clip(F32(1) - (F32(0.5) + F32(0.5) * _dot(N, L)) * _f(intensity), 0, 1).astype(F32)


def baker_hatching_volume(layers, tile, lod, darkness, tone_count, darkest):
    """``layers``: chain (finest first) of (tones, R, R) float arrays."""
    d = np.clip(_f(darkness), 0, 1)
    x = d / F32(darkest) * F32(tone_count) - F32(1)
    out = np.empty(d.shape, F32)

    def fetch(layer_index):
        return texture_lod([lv[..., None].transpose(1, 2, 0, 3)[:, :, int(layer_index), :] for lv in layers],
                           tile, lod)[..., 0]

    beyond = x >= tone_count - 1
    last = fetch(tone_count - 1)
    out[beyond] = (last * (F32(1) - (d - F32(darkest)) / (F32(1) - F32(darkest))))[beyond]
    i0 = np.floor(x)
    f = x - i0
    for i in range(-1, tone_count - 1):
        sel = (~beyond) & (i0 == i)
        if sel.any():
            lower = np.ones(d.shape, F32) if i < 0 else fetch(i)
            upper = fetch(i + 1)
            out[sel] = (lower * (1 - f) + upper * f)[sel]
    return out


# ---------------------------------------------------------------------------------------------------------- toon
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
