"""AMD TressFX 4 ``.tfx`` strands: writer and reader.

Layout (``TressFXTFXFileHeader`` of TressFX 4, little-endian, 160 bytes)::

    float version;                 4.0
    uint  numHairStrands;          strands in the file (guide strands: TressFX makes its follow hairs itself)
    uint  numVerticesPerStrand;    a power of two in 4..64, the same for every strand
    uint  offsetVertexPosition;    float4[numHairStrands * numVerticesPerStrand], strand-major, root first;
                                   w = inverse mass: 0 pins the vertex (the root), 1 lets it move
    uint  offsetStrandUV;          float2[numHairStrands] (0 = absent)
    uint  offsetVertexUV;          float2[numHairStrands * numVerticesPerStrand] (0 = absent; baker writes none)
    uint  offsetStrandThickness;   float[numHairStrands], a scale of the engine's fiber radius
    uint  offsetVertexColor;       float4[...] (0 = absent; baker writes none)
    uint  reserved[32];

Offsets are bytes from the start of the file, 8-byte aligned. TressFX wants a power-of-two vertex count, so strands
whose count is not one are resampled at equal arc-length steps to the nearest power of two in 4..64.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np

from baker.gltf.atomic import write_bytes_atomic

HEADER = struct.Struct("<f7I32I")
VERSION = 4.0


@dataclass
class TfxFile:
    version: float
    positions: np.ndarray  # (s, v, 4) float32, w = inverse mass
    strand_uv: np.ndarray | None  # (s, 2) float32
    thickness: np.ndarray | None  # (s,) float32
    offsets: tuple  # (position, strandUV, vertexUV, thickness, color) as stored


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


def decode_tfx(data: bytes) -> TfxFile:
    """Parse .tfx bytes (header + positions + optional strand UVs and thickness)."""
    if len(data) < HEADER.size:
        raise ValueError(f"a .tfx file has a {HEADER.size}-byte header; got {len(data)} bytes")
    fields = HEADER.unpack_from(data)
    version, s, v, pos_off, uv_off, _vuv_off, th_off, _col_off = fields[:8]
    if not np.isfinite(version):
        raise ValueError("header: version is not a number")
    if s < 1 or v < 1:
        raise ValueError(f"header: {s} strands of {v} vertices")
    n = s * v

    def block(name, offset, size):  # every block must lie after the header and inside the file
        if offset < HEADER.size or offset + size > len(data):
            raise ValueError(f"header: {name} ({size} bytes at offset {offset}) runs outside the {len(data)}-byte "
                             "file")

    block("vertex positions", pos_off, 16 * n)
    if uv_off:
        block("strand UVs", uv_off, 8 * s)
    if th_off:
        block("strand thickness", th_off, 4 * s)
    positions = np.frombuffer(data, "<f4", count=4 * n, offset=pos_off).reshape(s, v, 4).copy()
    uv = np.frombuffer(data, "<f4", count=2 * s, offset=uv_off).reshape(s, 2).copy() if uv_off else None
    thickness = np.frombuffer(data, "<f4", count=s, offset=th_off).copy() if th_off else None
    return TfxFile(version, positions, uv, thickness, tuple(fields[3:8]))


def read_tfx(path) -> TfxFile:
    with open(path, "rb") as fh:
        return decode_tfx(fh.read())
