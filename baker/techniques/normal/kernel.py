"""Normals of the high mesh in the low mesh's tangent frames, and their encoding as normal-map pixels.

glTF decodes a tangent-space normal map (spec 3.9.3, normalTexture) as ``n = normalize(x T + y B + z N)`` with the
vertex TANGENT ``T``, ``B = cross(N, T.xyz) * T.w`` and NORMAL ``N`` interpolated over the triangle and each
normalized per pixel (three.js, Babylon.js and Blender's glTF importer with its MikkTSpace-like tangents do the
same). The bake inverts exactly that: ``(x, y, z) = normalize(M^-1 n_high)`` with ``M = [T B N]`` of the texel, so
a viewer decodes the high's normal whether or not the frame is orthogonal.
"""
from __future__ import annotations

import numpy as np


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-30)


def tangent_space(normals: np.ndarray, tangents: np.ndarray, bitangents: np.ndarray,
                  frame_normals: np.ndarray) -> np.ndarray:
    """(n, 3) unit tangent-space vectors (x, y, z) with ``normalize(x T + y B + z N)`` = ``normals``; ``T``, ``B``,
    ``N`` are normalized here. A texel whose frame is degenerate (T along N) gets the projection on an orthonormal
    frame instead."""
    t, b, n = unit(tangents), unit(bitangents), unit(frame_normals)
    frame = np.stack([t, b, n], axis=2)  # columns T, B, N
    det = np.linalg.det(frame)
    usable = np.abs(det) > 1e-6
    out = np.empty_like(normals)
    if usable.any():
        out[usable] = np.linalg.solve(frame[usable], normals[usable][:, :, None])[:, :, 0]
    if (~usable).any():
        projected = np.einsum("kij,ki->kj", frame[~usable], normals[~usable])
        out[~usable] = projected
    out = unit(out)
    # a high normal pointing away from the low's (a ray hit the back of a fold) decodes as it is; a zero vector
    # (no frame at all) is the flat normal
    flat = np.linalg.norm(out, axis=1) < 0.5
    out[flat] = (0.0, 0.0, 1.0)
    return out


def encode_pixels(vectors: np.ndarray, bits: int) -> np.ndarray:
    """(..., 3) unit vectors in [-1, 1] -> RGB pixels ``round((v + 1) / 2 * max)`` of 8 or 16 bits."""
    top = (1 << bits) - 1
    pixels = np.clip(np.rint((np.nan_to_num(vectors) + 1.0) * 0.5 * top), 0, top)
    return pixels.astype(np.uint16 if bits == 16 else np.uint8)


def decode_pixels(pixels: np.ndarray) -> np.ndarray:
    """RGB pixels (8 or 16 bits) -> (..., 3) vectors ``2 p / max - 1`` (not normalized)."""
    top = 65535.0 if pixels.dtype == np.uint16 else 255.0
    return pixels[..., :3].astype(np.float64) / top * 2.0 - 1.0


BANDING_SHARE = 0.05  # of neighbouring covered texel pairs changing by a slow ramp: then 8 bits band
RAMP = (0.05, 0.25)  # a change per texel, in steps of 8 bits, that is a slow ramp: bands of 4 texels and wider


def bits_needed(image: np.ndarray, mask: np.ndarray) -> int:
    """16 when 8 bits would band the (H, W, 3) map of unit vectors over the covered texels ``mask``, else 8: more
    than :data:`BANDING_SHARE` of the horizontally or vertically neighbouring covered texels differ (largest
    channel) by a slow ramp of :data:`RAMP` steps of 8 bits, which rounding to 8 bits turns into flat bands a few
    texels wide with a step between (a smooth sculpt's gentle curvature; a constant region does not band)."""
    steps = (image + 1.0) * 0.5 * 255.0
    ramps, pairs = 0, 0
    for axis in (0, 1):
        change = np.abs(np.diff(steps, axis=axis)).max(axis=2)
        both = mask[1:, :] & mask[:-1, :] if axis == 0 else mask[:, 1:] & mask[:, :-1]
        pairs += int(both.sum())
        ramps += int((both & (change > RAMP[0]) & (change < RAMP[1])).sum())
    return 16 if pairs and ramps > BANDING_SHARE * pairs else 8
