"""numpy twins of ``runtime-shaders/baker_hatching.glsl``, in float32, one per GLSL function.

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
