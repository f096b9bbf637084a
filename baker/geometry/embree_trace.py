"""The compiled loops around Embree's ``rtcIntersect1`` (the scene itself is built in :mod:`.embree`, without numba).

Compiled code calls rtcIntersect1 by *name*, resolved through LLVM's symbol table, rather than through a ctypes
function whose address numba would bake into the machine code: code holding an address cannot go to numba's
on-disk cache (the address changes every process), so every process, and every `baker build --jobs` worker, used
to re-JIT the thickness kernel (~1.5 s). The symbol is registered when this module is imported, before any cached
code that calls :func:`trace_one` is linked, so ``cache=True`` works for all of them.
"""
from __future__ import annotations

import numba
import numpy as np
from llvmlite import binding as llvm_binding

from baker.geometry.embree import AVAILABLE, INTERSECT1_ADDRESS, INVALID_ID, MISS

INTERSECT1_SYMBOL = "rtcIntersect1"
if AVAILABLE:
    llvm_binding.add_symbol(INTERSECT1_SYMBOL, INTERSECT1_ADDRESS)

# rtcIntersect1(RTCScene, RTCRayHit*, RTCIntersectArguments*): pointers passed as intp (the same register on the
# 64-bit ABIs Embree supports), so callers pass the scene handle and ``array.ctypes.data`` unchanged
_intersect1 = numba.types.ExternalFunction(
    INTERSECT1_SYMBOL, numba.types.void(numba.types.intp, numba.types.intp, numba.types.intp))


def new_rayhit() -> np.ndarray:
    """A zeroed, 16-byte aligned 128-byte block for one ``RTCRayHit`` (room for any trailing hit fields)."""
    raw = np.zeros(48, np.uint32)
    offset = (-raw.ctypes.data % 16) // 4
    return raw[offset: offset + 32]


@numba.njit(cache=True, nogil=True, inline="always")
def trace_one(scene, rayhit, ox, oy, oz, dx, dy, dz):
    """First-hit distance of one ray (``MISS`` when nothing is hit)."""
    f = rayhit.view(np.float32)
    f[0], f[1], f[2], f[3] = ox, oy, oz, 0.0
    f[4], f[5], f[6], f[7] = dx, dy, dz, 0.0
    f[8] = MISS
    rayhit[9] = INVALID_ID  # mask: all
    rayhit[10] = 0  # id
    rayhit[11] = 0  # flags
    rayhit[17] = INVALID_ID  # hit.primID
    rayhit[18] = INVALID_ID  # hit.geomID
    rayhit[19] = INVALID_ID  # hit.instID[0]
    _intersect1(scene, rayhit.ctypes.data, 0)
    return f[8]


@numba.njit(cache=True, nogil=True)
def trace_rays(scene, origins, directions, out, rayhit):
    for r in range(origins.shape[0]):
        out[r] = trace_one(scene, rayhit, origins[r, 0], origins[r, 1], origins[r, 2],
                           directions[r, 0], directions[r, 1], directions[r, 2])


@numba.njit(cache=True, nogil=True)
def trace_hits(scene, origins, directions, distance, face, u, v, rayhit):
    """First hits with the triangle and its barycentric (u, v): ``face`` -1 on a miss."""
    f = rayhit.view(np.float32)
    for r in range(origins.shape[0]):
        distance[r] = trace_one(scene, rayhit, origins[r, 0], origins[r, 1], origins[r, 2],
                                directions[r, 0], directions[r, 1], directions[r, 2])
        face[r] = -1 if rayhit[17] == INVALID_ID else np.int64(rayhit[17])
        u[r], v[r] = f[15], f[16]
