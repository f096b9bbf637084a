"""First-hit ray queries over a triangle mesh: Embree called directly, or embreex when its library is missing."""
from __future__ import annotations

import numpy as np

from baker.geometry import embree


class RayScene:
    """A triangle mesh ready for rays: Embree called directly (:mod:`baker.geometry.embree`) or, when its library
    cannot be loaded, embreex's batch API. ``distances`` returns first-hit distances (>= 1e37 on a miss)."""

    MISS = 1e37

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, backend: str = "auto", quality: str = "high",
                 robust: bool = False):
        if backend not in ("auto", "direct", "embreex"):
            raise ValueError(f"unknown ray backend {backend!r}")
        self.direct = None
        if backend in ("auto", "direct") and embree.AVAILABLE:
            self.direct = embree.DirectScene(vertices, faces, quality, robust)
        elif backend == "direct":
            raise RuntimeError("the Embree library is not available")
        else:
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh

            self._scene = rtcore_scene.EmbreeScene()
            TriangleMesh(self._scene, np.ascontiguousarray(vertices, np.float32),
                         np.ascontiguousarray(faces, np.int32))

    def distances(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        if self.direct is not None:
            from baker.geometry.embree_trace import new_rayhit, trace_rays  # numba: not needed to build the scene

            out = np.empty(len(origins), np.float32)
            trace_rays(self.direct.pointer, np.ascontiguousarray(origins, np.float32),
                       np.ascontiguousarray(directions, np.float32), out, new_rayhit())
            return out
        # the DISTANCE query returns tfar alone: no u/v/Ng/primID arrays to allocate per ray
        return self._scene.run(np.ascontiguousarray(origins, np.float32),
                               np.ascontiguousarray(directions, np.float32), query="DISTANCE")

    def first_hits(self, origins: np.ndarray, directions: np.ndarray):
        """(distance, triangle, u, v) of each ray's first hit: the point is (1-u-v) p0 + u p1 + v p2 of the
        triangle; triangle -1 and distance >= 1e37 on a miss."""
        origins = np.ascontiguousarray(origins, np.float32)
        directions = np.ascontiguousarray(directions, np.float32)
        if self.direct is not None:
            from baker.geometry.embree_trace import new_rayhit, trace_hits

            n = len(origins)
            distance, face = np.empty(n, np.float32), np.empty(n, np.int64)
            u, v = np.empty(n, np.float32), np.empty(n, np.float32)
            trace_hits(self.direct.pointer, origins, directions, distance, face, u, v, new_rayhit())
            return distance, face, u, v
        hits = self._scene.run(origins, directions, query="INTERSECT", output=1)
        face = np.asarray(hits["primID"], np.int64)
        face[face >= 2 ** 31 - 1] = -1
        face[face < 0] = -1
        distance = np.where(face >= 0, np.asarray(hits["tfar"], np.float32), np.float32(self.MISS))
        return distance, face, np.asarray(hits["u"], np.float32), np.asarray(hits["v"], np.float32)
