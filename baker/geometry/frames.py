"""Tangent frames."""
from __future__ import annotations

import numpy as np


def orthonormal_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents completing each unit normal to a right-handed frame (Duff et al. 2017, branchless);
    the vectorized twin of
    :func:`baker.techniques.thickness.kernel._frame` (which runs inside numba loops)."""
    sign = np.where(n[:, 2] >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + n[:, 2])
    b = n[:, 0] * n[:, 1] * a
    t = np.stack([1.0 + sign * n[:, 0] ** 2 * a, sign * b, -sign * n[:, 0]], axis=1)
    bt = np.stack([b, sign + n[:, 1] ** 2 * a, -n[:, 1]], axis=1)
    return t, bt
