"""Small commands against `python3 -c "import numpy"`: process start to exit, median of N, in one run.

    python benchmarks/startup.py [--repeat 5]

`baker --version` and `baker --help` build the parser from every technique's options without importing numpy or a
kernel (target: at most 2.5x the time of importing numpy); `baker validate` of a small baked file and `baker
inspect` read it without a numba kernel; a second `baker glyphs` run (DejaVu Sans, ASCII) loads its kernels from
numba's on-disk cache instead of compiling them (the first run, which compiles, is shown too). Each command runs as a
fresh process, interleaved, so a busy machine slows them alike. Also lists the heavy modules the parser imported.

First run vs second in a fresh install (issue 35; skip with --no-fresh): the checkout is built into a wheel
(`pip wheel`, which compiles the kernels into the wheel's seed: baker/numba_cache.py) and installed into two new
virtual environments, one left writable and one made read-only (chmod -R a-w; when this runs as root, whom chmod
would not stop, its commands also run in a mount namespace where site-packages is a read-only bind mount); each command then runs twice per environment with an
empty HOME and XDG_CACHE_HOME, first runs and second runs interleaved. Whole processes: wall time and peak memory
(the child's maximum resident set). Target: first run at most 1.5x the second. `--wheel PATH` reuses a built wheel.
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
ALL_BAKES = "thickness,curvature,skin,edges,tam,toon,fur,caustics"


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
    ap.add_argument("--no-fresh", action="store_true", help="skip the first/second runs in a fresh install")
    ap.add_argument("--wheel", type=Path, help="a built baker wheel for the fresh installs (default: build one)")
    ap.add_argument("--no-seed", action="store_true", help="build the wheel without compiled kernels "
                    "(BAKER_NUMBA_SEED=0: numba compiles what each command uses on its first run), for comparison")
    args = ap.parse_args(argv)
    fresh_ok = True if args.no_fresh else fresh_install_runs(args.wheel, seed=not args.no_seed)
    with tempfile.TemporaryDirectory() as d:
        work = Path(d)
        # a cold numba cache for the first glyphs run, then the same cache for the measured ones (baker keeps its
        # kernels under $XDG_CACHE_HOME/baker/numba)
        env = {**os.environ, "XDG_CACHE_HOME": str(work / "xdg")}
        cmds = commands(work)
        glyphs = cmds["baker glyphs DejaVu Sans ascii (second run)"]
        first = wall(glyphs, env)
        for cmd in cmds.values():  # warm the file cache and __pycache__
            wall(cmd, env)
        times = {name: [] for name in cmds}
        for _ in range(args.repeat):
            for name, cmd in cmds.items():
                times[name].append(wall(cmd, env))
        shutil.rmtree(work / "xdg", ignore_errors=True)
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
    return 0 if worst <= 2.5 and not heavy and fresh_ok else 1


def measured(cmd, env, cwd, read_only: Path | None = None) -> tuple[float, float]:
    """Wall seconds and peak resident MiB of one whole process (wait4 reports the child's own maximum); with
    ``read_only`` (as root) the command runs where that folder is a read-only bind mount (the shell execs it)."""
    if read_only is not None:
        cmd = ["unshare", "-m", "sh", "-c", 'mount --bind "$0" "$0" && mount -o remount,bind,ro "$0" && exec "$@"',
               str(read_only), *cmd]
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    elapsed = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(map(str, cmd))} exited {proc.returncode}: {stderr.decode()[-2000:]}")
    return elapsed, usage.ru_maxrss / 1024


def fresh_venv(wheel: Path, root: Path, read_only: bool) -> tuple[Path, Path]:
    """A new virtual environment holding the wheel; the dependencies come from this interpreter's site-packages
    through a .pth file (as tests/test_wheel.py does)."""
    import site
    import sysconfig

    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(root)], check=True)
    python = root / "bin" / "python"
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "-q",
                    str(wheel)], check=True, env=clean)
    purelib = Path(subprocess.check_output([str(python), "-c", "import sysconfig; "
                                            "print(sysconfig.get_paths()['purelib'])"], text=True).strip())
    ours = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"], *site.getsitepackages()}
    (purelib / "zz_dependencies.pth").write_text("\n".join(sorted(p for p in ours if Path(p).is_dir())) + "\n")
    if read_only:
        subprocess.run(["chmod", "-R", "a-w", str(purelib)], check=True)
    return root, purelib


def fresh_install_runs(wheel: Path | None, seed: bool = True) -> bool:
    """Print the first/second-run table of a fresh install; True when every first run is at most 1.5x its second."""
    root_user = os.geteuid() == 0
    with tempfile.TemporaryDirectory() as d:
        work = Path(d)
        if wheel is None:
            began = time.perf_counter()
            subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(work / "wheel"),
                            str(ROOT)], check=True, env={**os.environ, "BAKER_NUMBA_SEED": "1" if seed else "0"})
            [wheel] = (work / "wheel").glob("baker-*.whl")
            print(f"wheel built in {time.perf_counter() - began:.0f} s, {wheel.stat().st_size / 2**20:.1f} MiB")
        (venv, _), (venv_ro, purelib_ro) = fresh_venv(wheel, work / "venv", False), fresh_venv(wheel, work / "venv_ro",
                                                                                               True)
        setups = {"writable": (venv, None),
                  "read-only (mount)" if root_user else "read-only": (venv_ro, purelib_ro if root_user else None)}
        commands = {
            f"baker bake spot.obj --bakes {ALL_BAKES}": ["bake", str(SPOT), "-o", "spot_all.glb", "--bakes", ALL_BAKES,
                                                         "-q"],
            "baker text \"Hello\" --font DejaVuSans.ttf -o label.glb": ["text", "Hello", "--font", str(FONT), "-o",
                                                                        "label.glb", "-q"],
        }
        homes, runs = {}, {}
        for setup, (venv, _) in setups.items():
            homes[setup] = work / f"home_{venv.name}"  # HOME and XDG_CACHE_HOME: empty
            (homes[setup] / "cache").mkdir(parents=True)
        clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "NUMBA_CACHE_DIR")}
        for name, args in commands.items():  # a command's first and second runs close in time, setups interleaved
            for run in ("first", "second"):
                for setup, (venv, read_only) in setups.items():
                    home = homes[setup]
                    env = {**clean, "HOME": str(home), "XDG_CACHE_HOME": str(home / "cache")}
                    runs[name, setup, run] = measured([str(venv / "bin" / "baker"), *args], env, home, read_only)
    print("\n| work (fresh venv from the wheel, empty HOME and XDG_CACHE_HOME) | site-packages | first run (s) | "
          "second run (s) | ratio | peak memory first / second (MiB) |")
    print("|---|---|---:|---:|---:|---:|")
    ok = True
    for name in commands:
        for setup in setups:
            (t1, m1), (t2, m2) = runs[name, setup, "first"], runs[name, setup, "second"]
            ok &= t1 <= 1.5 * t2
            print(f"| `{name}` | {setup} | {t1:.1f} | {t2:.1f} | {t1 / t2:.2f}x | {m1:.0f} / {m2:.0f} |")
    return ok


if __name__ == "__main__":
    sys.exit(main())
