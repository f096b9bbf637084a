"""numpy twins of ``runtime-shaders/baker_caustics.glsl``, in float32, one per GLSL function.

Frames are sampled as the GL spec says (LINEAR on texel centres, REPEAT), with the sampler of the hatching twins.
"""
from __future__ import annotations

import numpy as np

from .twins_hatching import sample_linear

F32 = np.float32


def _f(x) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def baker_caustics_frame(time, period, frame_count):
    t = _f(time) / F32(period)
    f = (t - np.floor(t)) * F32(frame_count)
    first = np.minimum(np.floor(f), F32(frame_count) - 1)
    following = np.where(first + 1 >= F32(frame_count), F32(0), first + 1)
    return np.stack([first, f - first, following], -1).astype(F32)


def baker_caustics_depth(world_position, water_level):
    return (F32(water_level) - _f(world_position)[..., 1]).astype(F32)


def baker_caustics_uv(world_position, projection_direction, water_level, depth, tile_size):
    p, d = _f(world_position), _f(projection_direction)
    below = F32(depth) - baker_caustics_depth(p, water_level)
    on_floor = p - d * (below / d[..., 1])[..., None]
    return (np.stack([on_floor[..., 0], -on_floor[..., 2]], -1) / F32(tile_size)).astype(F32)


def baker_caustics_fade(point_depth, depth, fade_distance):
    d = _f(point_depth)
    value = np.clip(F32(1) - np.abs(d - F32(depth)) / max(F32(fade_distance), F32(1e-6)), 0, 1)
    return np.where(d <= 0, F32(0), value).astype(F32)


def baker_caustics_irradiance(first: np.ndarray, following: np.ndarray, uv, blend, intensity_scale, rgb):
    """``first``, ``following`` (H, W, C) float frames; REPEAT, LINEAR."""
    a = sample_linear(first, _f(uv))
    b = sample_linear(following, _f(uv))
    a = a[..., :3] if a.shape[-1] >= 3 else np.repeat(a[..., :1], 3, -1)
    b = b[..., :3] if b.shape[-1] >= 3 else np.repeat(b[..., :1], 3, -1)
    w = _f(blend)[..., None]
    e = (a * (1 - w) + b * w) * F32(intensity_scale)
    return (e if rgb > 0.5 else np.repeat(e[..., :1], 3, -1)).astype(F32)


def baker_caustics_apply(lit_color, sun_lit, irradiance, strength, fade):
    k = (F32(strength) * _f(fade))[..., None]
    return np.maximum(_f(lit_color) + _f(sun_lit) * (_f(irradiance) - 1) * k, 0).astype(F32)


def baker_caustics_headroom(before, after, other):
    room = np.maximum(1 - _f(before) - _f(other), 0)
    added = np.maximum(_f(after) - _f(before), 0)
    return (np.minimum(_f(after), _f(before)) + room * added / np.maximum(room + added, F32(1e-6))).astype(F32)
