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
