"""AMD TressFX 4 ``.tfx`` strands in: the header and every block checked against the file length before a strand
is read (the writer is :mod:`baker.techniques.hair.tfx`).

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

Offsets are bytes from the start of the file, 8-byte aligned.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from baker.errors import BakerError
from baker.readers.groom import Groom

HEADER = struct.Struct("<f7I32I")
VERSION = 4.0


@dataclass
class TfxFile:
    version: float
    positions: np.ndarray  # (s, v, 4) float32, w = inverse mass
    strand_uv: np.ndarray | None  # (s, 2) float32
    thickness: np.ndarray | None  # (s,) float32
    offsets: tuple  # (position, strandUV, vertexUV, thickness, color) as stored


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


def read_groom(path) -> Groom:
    """TressFX strands as a groom; the per-strand thickness becomes a constant per-vertex width."""
    try:
        tfx = decode_tfx(Path(path).read_bytes())
    except ValueError as exc:
        raise BakerError(path, str(exc)) from None
    s, v = tfx.positions.shape[:2]
    widths = np.repeat(tfx.thickness.astype(np.float64), v) if tfx.thickness is not None else None
    return Groom(tfx.positions[..., :3].reshape(-1, 3).astype(np.float64), np.full(s, v, np.int64), widths)
