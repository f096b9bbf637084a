"""`baker --version` and `baker --help` against `python3 -c "import numpy"`: process start to exit, median of N.

    python benchmarks/startup.py [--repeat 5]

The CLI builds its parser from every technique's options without importing a kernel, numpy or numba; the target
(issue 13) is at most 2.5x the time of importing numpy. Each command runs as a fresh process, interleaved, so a busy
machine slows all three alike. Also lists which heavy modules `baker --help` imported (should be none).
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("numpy", "numba", "scipy", "trimesh", "pxr", "moderngl", "PIL", "embreex", "OpenImageIO")
COMMANDS = {
    "python3 -c 'import numpy' (peer)": [sys.executable, "-c", "import numpy"],
    "baker --version": [sys.executable, "-m", "baker.cli", "--version"],
    "baker --help": [sys.executable, "-m", "baker.cli", "--help"],
}


def wall(cmd) -> float:
    start = time.perf_counter()
    subprocess.run(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - start


def heavy_imports() -> list[str]:
    probe = ("import sys\nfrom baker import commands\ncommands.build_parser()\n"
             f"print(' '.join(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r}))))")
    out = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, check=True)
    return out.stdout.split()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    for cmd in COMMANDS.values():  # warm the file cache and __pycache__
        wall(cmd)
    times = {name: [] for name in COMMANDS}
    for _ in range(args.repeat):
        for name, cmd in COMMANDS.items():
            times[name].append(wall(cmd))
    peer = statistics.median(next(iter(times.values())))
    print(f"| command | median of {args.repeat} (s) | x numpy import |")
    print("|---|---:|---:|")
    for name, values in times.items():
        median = statistics.median(values)
        print(f"| {name} | {median:.3f} | {median / peer:.2f} |")
    heavy = heavy_imports()
    print(f"\nheavy modules imported by building the parser: {', '.join(heavy) or 'none'}")
    worst = max(statistics.median(v) for v in list(times.values())[1:]) / peer
    return 0 if worst <= 2.5 and not heavy else 1


if __name__ == "__main__":
    sys.exit(main())
