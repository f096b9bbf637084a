"""Embree, called directly: the library and a triangle scene through ctypes (no numba: a bake builds its BVH
while numba is still loading; the compiled loops around ``rtcIntersect1`` are in :mod:`.embree_trace`).

Why not only embreex: its ``EmbreeScene.run`` is a fine batch API, but every call allocates result arrays and
the ray set has to be materialized first (origins + directions, 24 bytes a ray). For local thickness the rays are
generated, traced and averaged per point, so fusing the three in one compiled loop that calls Embree's C API keeps
everything in registers; measured on the Stanford bunny (64 rays per vertex) it casts ~25% more rays per CPU-second
than ``EmbreeScene.run`` on the same rays (see benchmarks/RESULTS.md). We call the very library embreex ships
(``embreex.libs/libembree4*.so``) through ctypes; when it cannot be found, :class:`RayScene` in
:mod:`baker.techniques.thickness.kernel` falls back to embreex's batch API.

Embree 4 ABI used here (``rtcore_ray.h``): ``RTCRayHit`` is ``RTCRay`` (org xyz, tnear, dir xyz, time, tfar, mask,
id, flags: 48 bytes) followed by ``RTCHit`` (Ng xyz, u, v, primID, geomID, instID[1], ...), 16-byte aligned.
"""
from __future__ import annotations

import ctypes
import glob
import os

import numpy as np

MISS = np.float32(1e37)  # tfar is left at its initial value when nothing is hit
INVALID_ID = 0xFFFFFFFF  # Embree's RTC_INVALID_GEOMETRY_ID: mask all, and no hit
_RTC_GEOMETRY_TYPE_TRIANGLE = 0
_RTC_BUFFER_TYPE_INDEX, _RTC_BUFFER_TYPE_VERTEX = 0, 1
_RTC_FORMAT_UINT3, _RTC_FORMAT_FLOAT3 = 0x5003, 0x9003
_RTC_BUILD_QUALITY_MEDIUM, _RTC_BUILD_QUALITY_HIGH = 1, 2
BUILD_QUALITIES = {"medium": _RTC_BUILD_QUALITY_MEDIUM, "high": _RTC_BUILD_QUALITY_HIGH}
_RTC_SCENE_FLAG_ROBUST = 4


def _load_library():
    try:
        import embreex
    except ImportError:
        return None
    root = os.path.dirname(os.path.dirname(embreex.__file__))
    candidates = sorted(glob.glob(os.path.join(root, "embreex.libs", "libembree4*.so*")))
    for path in candidates:
        try:
            lib = ctypes.CDLL(path)
            lib.rtcIntersect1  # noqa: B018 - the symbol we need
            return lib
        except (OSError, AttributeError):
            continue
    return None


_lib = _load_library()
AVAILABLE = _lib is not None
# where compiled code finds rtcIntersect1 (baker.geometry.embree_trace registers it by name with LLVM)
INTERSECT1_ADDRESS = ctypes.cast(_lib.rtcIntersect1, ctypes.c_void_p).value if AVAILABLE else None

if AVAILABLE:
    _P = ctypes.c_void_p
    for name, restype, argtypes in [
        ("rtcNewDevice", _P, [ctypes.c_char_p]),
        ("rtcReleaseDevice", None, [_P]),
        ("rtcGetDeviceError", ctypes.c_int, [_P]),
        ("rtcNewScene", _P, [_P]),
        ("rtcReleaseScene", None, [_P]),
        ("rtcSetSceneBuildQuality", None, [_P, ctypes.c_int]),
        ("rtcSetSceneFlags", None, [_P, ctypes.c_int]),
        ("rtcCommitScene", None, [_P]),
        ("rtcNewGeometry", _P, [_P, ctypes.c_int]),
        ("rtcSetNewGeometryBuffer", _P, [_P, ctypes.c_int, ctypes.c_uint, ctypes.c_int, ctypes.c_size_t, ctypes.c_size_t]),
        ("rtcCommitGeometry", None, [_P]),
        ("rtcAttachGeometry", ctypes.c_uint, [_P, _P]),
        ("rtcReleaseGeometry", None, [_P]),
        ("rtcIntersect1", None, [_P, _P, _P]),
    ]:
        fn = getattr(_lib, name)
        fn.restype, fn.argtypes = restype, argtypes


class DirectScene:
    """A committed Embree triangle scene; ``pointer`` is the ``RTCScene`` handle. ``quality``: "high" (SAH with
    spatial splits: for many rays per triangle) or "medium" (a few rays per triangle: a 300k-triangle sculpt builds
    in 0.16 s of CPU instead of 0.73 and traces 1M rays in the same time). ``robust``: Embree's robust traversal
    and intersection, so a ray through an edge or a vertex shared by triangles never slips between them (about 25%
    more time per ray)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, quality: str = "high", robust: bool = False):
        if not AVAILABLE:
            raise RuntimeError("Embree library not found")
        # BAKER_THREADS (set per `baker build --jobs` worker) also caps Embree's own (TBB) build threads
        threads = int(os.environ.get("BAKER_THREADS", 0) or 0)
        self._device = _lib.rtcNewDevice(f"threads={threads}".encode() if threads > 0 else None)
        if not self._device:
            raise RuntimeError("rtcNewDevice failed")
        self.pointer = _lib.rtcNewScene(self._device)
        # one build, millions of rays: the slower SAH build with spatial splits pays for itself
        _lib.rtcSetSceneBuildQuality(self.pointer, BUILD_QUALITIES[quality])
        if robust:
            _lib.rtcSetSceneFlags(self.pointer, _RTC_SCENE_FLAG_ROBUST)
        geom = _lib.rtcNewGeometry(self._device, _RTC_GEOMETRY_TYPE_TRIANGLE)
        v = np.ascontiguousarray(vertices, np.float32).reshape(-1)
        f = np.ascontiguousarray(faces, np.uint32).reshape(-1)
        vbuf = _lib.rtcSetNewGeometryBuffer(geom, _RTC_BUFFER_TYPE_VERTEX, 0, _RTC_FORMAT_FLOAT3, 12, len(v) // 3)
        ibuf = _lib.rtcSetNewGeometryBuffer(geom, _RTC_BUFFER_TYPE_INDEX, 0, _RTC_FORMAT_UINT3, 12, len(f) // 3)
        ctypes.memmove(vbuf, v.ctypes.data, v.nbytes)
        ctypes.memmove(ibuf, f.ctypes.data, f.nbytes)
        _lib.rtcCommitGeometry(geom)
        _lib.rtcAttachGeometry(self.pointer, geom)
        _lib.rtcReleaseGeometry(geom)
        _lib.rtcCommitScene(self.pointer)
        error = _lib.rtcGetDeviceError(self._device)
        if error:
            raise RuntimeError(f"Embree error {error} while building the scene")

    def __del__(self):
        if getattr(self, "pointer", None):
            _lib.rtcReleaseScene(self.pointer)
            self.pointer = None
        if getattr(self, "_device", None):
            _lib.rtcReleaseDevice(self._device)
            self._device = None
