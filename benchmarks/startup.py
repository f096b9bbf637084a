"""Small commands against `python3 -c "import numpy"`: process start to exit, median of N, in one run.

    python benchmarks/startup.py [--repeat 5]

`baker --version` and `baker --help` build the parser from every technique's options without importing numpy or a
kernel (target: at most 2.5x the time of importing numpy); `baker validate` of a small baked file and `baker
inspect` read it without a numba kernel; a second `baker glyphs` run (DejaVu Sans, ASCII) loads its kernels from
numba's on-disk cache instead of compiling them (the first run, which compiles, is shown too). Each command runs as a
fresh process, interleaved, so a busy machine slows them alike. Also lists the heavy modules the parser imported.
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("numpy", "numba", "scipy", "trimesh", "pxr", "moderngl", "PIL", "embreex", "OpenImageIO")
SPOT = ROOT / "examples" / "spot" / "spot.obj"
FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
BAKER = [sys.executable, "-m", "baker.cli"]


def commands(work: Path) -> dict:
    small = work / "spot_edges.glb"
    subprocess.run([*BAKER, "bake", str(SPOT), "-o", str(small), "--bakes", "edges", "-q"], cwd=ROOT, check=True)
    return {
        "python3 -c 'import numpy' (peer)": [sys.executable, "-c", "import numpy"],
        "baker --version": [*BAKER, "--version"],
        "baker --help": [*BAKER, "--help"],
        f"baker validate --no-khronos (spot, {small.stat().st_size // 1024} KiB)":
            [*BAKER, "validate", str(small), "--no-khronos", "-q"],
        "baker inspect (spot)": [*BAKER, "inspect", str(small)],
        "baker glyphs DejaVu Sans ascii (second run)": [*BAKER, "glyphs", str(FONT), "-o", str(work / "atlas"), "-q"],
    }


def wall(cmd, env=None) -> float:
    start = time.perf_counter()
    subprocess.run(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True, env=env)
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
    with tempfile.TemporaryDirectory() as d:
        work = Path(d)
        # a cold numba cache for the first glyphs run, then the same cache for the measured ones
        env = {**os.environ, "NUMBA_CACHE_DIR": str(work / "numba")}
        cmds = commands(work)
        glyphs = cmds["baker glyphs DejaVu Sans ascii (second run)"]
        first = wall(glyphs, env)
        for cmd in cmds.values():  # warm the file cache and __pycache__
            wall(cmd, env)
        times = {name: [] for name in cmds}
        for _ in range(args.repeat):
            for name, cmd in cmds.items():
                times[name].append(wall(cmd, env))
        shutil.rmtree(work / "numba", ignore_errors=True)
    peer = statistics.median(next(iter(times.values())))
    print(f"| command | median of {args.repeat} (s) | x numpy import |")
    print("|---|---:|---:|")
    for name, values in times.items():
        median = statistics.median(values)
        print(f"| {name} | {median:.3f} | {median / peer:.2f} |")
    print(f"| baker glyphs DejaVu Sans ascii (first run, compiles) | {first:.3f} | {first / peer:.2f} |")
    heavy = heavy_imports()
    print(f"\nheavy modules imported by building the parser: {', '.join(heavy) or 'none'}")
    worst = max(statistics.median(times[name]) for name in list(times)[1:3]) / peer
    return 0 if worst <= 2.5 and not heavy else 1


if __name__ == "__main__":
    sys.exit(main())
