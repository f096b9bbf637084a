"""Start numba's runtime on a thread while the main thread reads the input.

The first call of any compiled function in a process initialises numba's CPU target: about 1 s here (0.8-1.5 s),
nearly all of it Python (typing and lowering registries; ``numba.np.arraymath`` imports ``scipy.linalg`` to find a
BLAS). A bake's first compiled call comes after the input is read, and reading a large mesh is mostly GIL-free (file
I/O, numpy copies and casts), so making that first call on a thread at the start of the command hides most of the
initialisation behind the read. The outputs do not depend on it: the thread only calls a trivial cached function.
"""
from __future__ import annotations

import threading


_started: list = []


def start() -> threading.Thread:
    """Begin initialising numba in a daemon thread."""
    thread = threading.Thread(target=_first_call, name="numba-warmup", daemon=True)
    thread.start()
    _started.append(thread)
    return thread


def finish() -> None:
    """Wait for the warm-up before the process exits. A command that fails early (bad input) would otherwise exit
    while the thread is inside LLVM's initialisation, which runs without the GIL and crashes once the interpreter
    and LLVM's static objects are being torn down."""
    while _started:
        _started.pop().join()


def _first_call() -> None:
    try:
        from baker.geometry.welding import position_cells
        import numpy as np

        position_cells(np.zeros((1, 3)), 1.0)  # a cached kernel every mesh bake loads anyway
    except BaseException:  # noqa: BLE001 - a warm-up must never print or fail a command: the real call reports
        pass
