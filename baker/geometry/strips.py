"""Triangle strips with restarts (PLY ``tristrips``, the Stanford/Cyberware layout) as triangles."""
from __future__ import annotations

import numpy as np


def triangles_from_strips(indices: np.ndarray, restart: int = -1) -> np.ndarray:
    """Triangles of strips separated by ``restart`` entries, in strip order, each strip wound like its first triangle.

    Triangle k of a strip is (v[k], v[k+1], v[k+2]) for even k and (v[k+1], v[k], v[k+2]) for odd k (the OpenGL and
    glTF rule). Degenerate triangles, which strip exporters use to turn corners, are dropped. Returns (m, 3) int64.
    """
    indices = np.asarray(indices, dtype=np.int64).reshape(-1)
    n = len(indices)
    if n < 3:
        return np.zeros((0, 3), np.int64)
    is_restart = indices == restart
    position = np.arange(n)
    # index of the first entry of the strip each entry belongs to
    last_restart = np.maximum.accumulate(np.where(is_restart, position, -1))
    strip_start = last_restart + 1
    k = position[: n - 2]
    window_ok = ~(is_restart[:-2] | is_restart[1:-1] | is_restart[2:])
    k = k[window_ok]
    odd = ((k - strip_start[k]) % 2) == 1
    a = np.where(odd, indices[k + 1], indices[k])
    b = np.where(odd, indices[k], indices[k + 1])
    c = indices[k + 2]
    faces = np.stack([a, b, c], axis=1)
    keep = (a != b) & (b != c) & (a != c)
    return faces[keep]
