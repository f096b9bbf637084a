"""The one line a command prints when numba is about to compile baker's kernels.

A wheel ships them compiled (:mod:`baker.numba_cache`), but an editable or source install, a wheel built without its
seed, or another CPU or numba version compiles each kernel the first time it is used: tens of seconds with nothing
on screen otherwise. The CLI names the command it runs (:func:`expect`); :mod:`baker.numba_cache` listens to numba's
``numba:compile`` event, which numba raises only after a cache miss, and the first compilation of a baker kernel
prints ``baker: note: compiling ...`` once, on stderr, with the time the command's kernels took to compile here
(a warm cache prints nothing). ``BAKER_COMPILE_NOTE=0`` silences it (the test suite, whose expectations of stderr
do not depend on which test happens to compile a kernel first). This module does not import numba.
"""
from __future__ import annotations

import os
import sys
import threading

# seconds to compile the kernels of each command (and of each bake of ``baker bake``) on a cold cache: first run
# minus second run, examples/spot/spot.obj and DejaVu Sans, 2 cores; rounded, as the note gives them
COMMAND_SECONDS = {"glyphs": 28, "text": 25, "hair": 17, "guides": 10, "cards": 15, "lines": 8, "tam": 10,
                   "caustics": 8, "preview": 3, "hair-lut": 7}
BAKE_SECONDS = {"thickness": 9, "curvature": 5, "skin": 3, "edges": 7, "tam": 10, "toon": 2, "fur": 5,
                "caustics": 8, "normal-blur": 8}
DEFAULT_BAKES = ("thickness",)

_lock = threading.Lock()
_pending: list[str] = []


def estimate(argv: list[str]) -> tuple[str, int] | None:
    """(what compiles, seconds) for a command line (without the program name), None for a command without kernels
    of its own (inspect, validate, --help)."""
    if not argv:
        return None
    command = argv[0]
    if command == "bake":
        bakes = list(DEFAULT_BAKES)
        for i, word in enumerate(argv):
            if word == "--bakes" and i + 1 < len(argv):
                bakes = argv[i + 1].split(",")
            elif word.startswith("--bakes="):
                bakes = word.split("=", 1)[1].split(",")
        known = [b for b in bakes if b in BAKE_SECONDS]
        return (", ".join(known) or "bake"), max(3, sum(BAKE_SECONDS[b] for b in known))
    if command in COMMAND_SECONDS:
        return command, COMMAND_SECONDS[command]
    return None


def expect(argv: list[str]) -> None:
    """Arm the note for this command line: printed by the first compilation of a baker kernel, if any."""
    found = estimate(argv)
    with _lock:
        _pending.clear()
        if found is not None and os.environ.get("BAKER_COMPILE_NOTE", "1") != "0":
            what, seconds = found
            _pending.append(f"baker: note: compiling the numba kernels for {what} once (~{seconds} s; later runs "
                            "reuse them)")


def disarm() -> None:
    with _lock:
        _pending.clear()


def compiling() -> None:
    """Called as numba starts compiling a baker kernel (any thread): print the armed note, once."""
    with _lock:
        if not _pending:
            return
        line = _pending.pop()
    print(line, file=sys.stderr, flush=True)
