"""AMD TressFX 4 ``.tfx`` strands out; :mod:`baker.readers.tfx` reads them and describes the layout (TressFX 4's
``TressFXTFXFileHeader`` and its blocks). TressFX wants a power-of-two vertex count, so strands whose count is not
one are resampled at equal arc-length steps to the nearest power of two in 4..64.
"""
from __future__ import annotations

import numpy as np

from baker.gltf.atomic import write_bytes_atomic
from baker.readers.tfx import HEADER, VERSION


def tfx_vertex_count(vertices: int) -> int:
    """The power of two in 4..64 nearest to ``vertices`` (ties go up)."""
    candidates = [1 << k for k in range(2, 7)]
    return min(candidates, key=lambda c: (abs(c - vertices), -c))


def resample_strands(positions: np.ndarray, count: int) -> np.ndarray:
    """Resample (s, v, 3) polylines at ``count`` equal arc-length steps (root and tip kept)."""
    s, v, _ = positions.shape
    if v == count:
        return positions.copy()
    seg = np.linalg.norm(np.diff(positions, axis=1), axis=-1)
    arc = np.concatenate([np.zeros((s, 1)), np.cumsum(seg, axis=1)], axis=1)
    target = arc[:, -1:] * np.linspace(0.0, 1.0, count)[None, :]
    # per strand: the segment each target falls in (vectorized searchsorted via offsets)
    k = np.clip((arc[:, None, :] <= target[:, :, None]).sum(axis=2) - 1, 0, v - 2)
    rows = np.arange(s)[:, None]
    a0, a1 = arc[rows, k], arc[rows, k + 1]
    f = np.where(a1 > a0, (target - a0) / np.maximum(a1 - a0, 1e-300), 0.0)
    return positions[rows, k] * (1 - f)[..., None] + positions[rows, k + 1] * f[..., None]


def encode_tfx(positions: np.ndarray, thickness: np.ndarray | None = None, strand_uv: np.ndarray | None = None,
               pinned: int = 1) -> bytes:
    """Bytes of a .tfx file for strands (s, v, 3) root first; the first ``pinned`` vertices get w = 0."""
    s = positions.shape[0]
    v = tfx_vertex_count(positions.shape[1])
    pts = resample_strands(np.asarray(positions, np.float64), v)
    xyzw = np.ones((s, v, 4), np.float32)
    xyzw[..., :3] = pts
    xyzw[:, :pinned, 3] = 0.0
    chunks = [xyzw.astype("<f4").tobytes()]
    offset = HEADER.size
    pos_off = offset
    offset += len(chunks[0])

    def align8(n):
        return (n + 7) // 8 * 8

    uv_off = th_off = 0
    blobs = []
    if strand_uv is not None:
        offset = align8(offset)
        uv_off = offset
        data = np.asarray(strand_uv, "<f4").reshape(s, 2).tobytes()
        blobs.append((uv_off, data))
        offset += len(data)
    if thickness is not None:
        offset = align8(offset)
        th_off = offset
        data = np.asarray(thickness, "<f4").reshape(s).tobytes()
        blobs.append((th_off, data))
        offset += len(data)
    out = bytearray(offset)
    out[:HEADER.size] = HEADER.pack(VERSION, s, v, pos_off, uv_off, 0, th_off, 0, *([0] * 32))
    out[pos_off:pos_off + len(chunks[0])] = chunks[0]
    for off, data in blobs:
        out[off:off + len(data)] = data
    return bytes(out)


def write_tfx(path, positions, thickness=None, strand_uv=None) -> None:
    write_bytes_atomic(path, encode_tfx(positions, thickness, strand_uv))
