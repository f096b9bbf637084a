"""Welding: one vertex per position, so split copies (UV, normal or primitive seams) agree.

Vertices are merged when they round to the same cell of a grid of ``tolerance`` x the bounding-box diagonal. One
compiled pass over the vertices with an open-addressing hash table of the cells (O(n), no sort): a 17.8M-triangle
scan welds in about a second, where sorting the cells (``np.unique(axis=0)``) took tens. The cells of positions
are computed inside that pass (no (n, 3) quotient, rounded and integer temporaries: at 4.4M triangles they cost more
than the hashing).
"""
from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def _weld_cells(keys, table):
    """Welded id of each row of ``keys`` (n, 3) int64 cells, numbered by first occurrence, and the first row of each
    id. Linear probing in ``table`` (2^k slots filled with -1, at least twice the rows, so probes stay short)."""
    n = keys.shape[0]
    mask = np.uint64(table.shape[0] - 1)
    first = np.empty(n, np.int64)
    inverse = np.empty(n, np.int64)
    count = 0
    for i in range(n):
        a, b, c = keys[i, 0], keys[i, 1], keys[i, 2]
        h = (np.uint64(a) * np.uint64(0x9E3779B97F4A7C15)) ^ (np.uint64(b) * np.uint64(0xC2B2AE3D27D4EB4F)) \
            ^ (np.uint64(c) * np.uint64(0x165667B19E3779F9))
        slot = (h ^ (h >> np.uint64(29))) & mask
        while True:
            w = table[slot]
            if w < 0:
                table[slot] = count
                first[count] = i
                inverse[i] = count
                count += 1
                break
            j = first[w]
            if keys[j, 0] == a and keys[j, 1] == b and keys[j, 2] == c:
                inverse[i] = w
                break
            slot = (slot + np.uint64(1)) & mask
    return first[:count].copy(), inverse


def weld_cells(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first row of each distinct row of ``keys``, id of each row), ids numbered by first occurrence."""
    keys = np.ascontiguousarray(keys, np.int64)
    slots = 1 << max(4, int(2 * len(keys)).bit_length())
    table = np.full(slots, -1, np.int32 if len(keys) < 2**31 - 1 else np.int64)
    return _weld_cells(keys, table)


_INT64_LIMIT = 9.223372036854775808e18  # 2^63


@numba.njit(cache=True, nogil=True)
def position_cells(positions, cell):
    """``np.round(positions / cell).astype(np.int64)`` in one pass, with the same values: round half to even, and a
    quotient outside int64 becomes -2^63 as numpy's cast gives it on x86 (all such vertices share that cell)."""
    n = positions.shape[0]
    keys = np.empty((n, 3), np.int64)
    for i in range(n):
        for k in range(3):
            q = np.rint(positions[i, k] / cell)
            keys[i, k] = np.int64(q) if -_INT64_LIMIT <= q < _INT64_LIMIT else np.int64(-(2**63))
    return keys


def weld(positions: np.ndarray, tolerance: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices closer than ``tolerance`` x the bounding-box diagonal.

    Returns (welded positions, inverse) with ``welded[inverse] ~= positions``. Deterministic: welded vertices are
    ordered by first occurrence. When nothing merges, ``inverse`` is the identity and ``positions`` itself (not a
    copy) is returned.
    """
    if len(positions) == 0:
        return positions.copy(), np.zeros(0, np.int64)
    # column by column: numpy reduces a (n, 3) array along axis 0 several times slower than three contiguous passes
    diag = float(np.linalg.norm([positions[:, k].max() - positions[:, k].min() for k in range(3)])) or 1.0
    keys = position_cells(np.ascontiguousarray(positions, np.float64), diag * tolerance)
    first, inverse = weld_cells(keys)
    if len(first) == len(positions):  # ids count first occurrences, so no merge means first == inverse == arange
        return positions, inverse
    return positions[first], inverse
