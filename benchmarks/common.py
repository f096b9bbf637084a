"""Shared by the benchmark scripts."""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def best_of(repeat: int, fn):
    """(fastest wall time in seconds over ``repeat`` calls of ``fn``, the result of the last call)."""
    times, result = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return min(times), result


def cli_env() -> dict:
    """The environment for a child ``python -m baker.cli``: this checkout first on PYTHONPATH."""
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def run_command(argv: list, env: dict | None = None) -> dict:
    """Wall time (process start to exit), CPU seconds, peak RSS in bytes (``wait4``'s ``ru_maxrss``) and stdout of
    one child process: the end-to-end figure of a command a user runs."""
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        proc = subprocess.Popen([str(a) for a in argv], stdout=out, stderr=subprocess.PIPE,
                                env=cli_env() if env is None else env)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        err = proc.stderr.read().decode(errors="replace")
        out.seek(0)
        text = out.read().decode(errors="replace")
    if proc.returncode:
        raise SystemExit(f"{' '.join(map(str, argv))} failed ({proc.returncode}): {err.strip()[-400:]}")
    return {"wall": wall, "peak": usage.ru_maxrss * 1024, "stdout": text,
            "cpu": usage.ru_utime + usage.ru_stime}  # its own and its waited-for children's (a pool's workers)


def baker_cli(*args) -> list:
    """argv of ``baker ARGS...`` run by this interpreter from this checkout."""
    return [sys.executable, "-m", "baker.cli", *args]
