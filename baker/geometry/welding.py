"""Welding: one vertex per position, so split copies (UV, normal or primitive seams) agree."""
from __future__ import annotations

import numpy as np


def weld(positions: np.ndarray, tolerance: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices closer than ``tolerance`` x the bounding-box diagonal.

    Returns (welded positions, inverse) with ``welded[inverse] ~= positions``. Deterministic: welded vertices are
    ordered by first occurrence.
    """
    if len(positions) == 0:
        return positions.copy(), np.zeros(0, np.int64)
    diag = float(np.linalg.norm(positions.max(0) - positions.min(0))) or 1.0
    keys = np.round(positions / (diag * tolerance)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # renumber by first occurrence so the order does not depend on coordinates' sort order
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return positions[first[order]], rank[inverse]
