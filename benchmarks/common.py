"""Shared by the benchmark scripts."""
from __future__ import annotations

import time


def best_of(repeat: int, fn):
    """(fastest wall time in seconds over ``repeat`` calls of ``fn``, the result of the last call)."""
    times, result = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return min(times), result
