"""`baker build` on 30 assets (the shared meshes as scaled/rotated copies): --jobs 1 vs --jobs 2 vs a warm cache.

    python benchmarks/build.py [--bakes thickness,curvature,edges]

Each row is the command a user runs (``baker build --jobs N``, process start to exit) on a fresh copy of the same 30
inputs (the warm row re-runs the --jobs 2 project, where every output is cached). Uses the same asset generator as
tests/test_build.py. Besides wall time each row reports the CPU time of the command (its process and its workers)
and the cores it kept busy (CPU / wall). The "1 kernel thread" row runs
--jobs 1 with BAKER_THREADS=1, as each --jobs 2 worker does: its CPU time is the single-threaded work W, so
``wall(--jobs 1) / (W / 2)`` bounds what two workers on two cores can gain. The machine's load average is printed,
since other processes on a shared machine change every figure.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import test_build  # noqa: E402
from common import baker_cli, cli_env, run_command  # noqa: E402
from test_build import make_thirty  # noqa: E402

# the shared meshes sit beside the checkout (/work/main) or two levels up (a worktree /work/wt/N)
SHARED = next((p / "shared" / "assets" / "meshes" for p in ROOT.parents if (p / "shared" / "assets").is_dir()),
              test_build.SHARED)
test_build.SHARED = SHARED


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bakes", default="thickness,curvature,edges")
    args = ap.parse_args(argv)
    if not SHARED.is_dir():
        print(f"shared meshes not found: {SHARED}", file=sys.stderr)
        return 2
    bakes = [b.strip() for b in args.bakes.split(",") if b.strip()]
    recipe = "[build]\noutput = \"baked\"\nbakes = [" + ", ".join(f'"{b}"' for b in bakes) + "]\n\n" \
             "[options.thickness]\nrays = 64\nper_texel = false\n\n[[assets]]\ninputs = [\"assets/*.obj\", \"assets/*.glb\"]\n"
    rows = []
    load_before = os.getloadavg()[0]

    def timed(name, project, jobs, threads=None):
        env = cli_env()
        if threads:
            env["BAKER_THREADS"] = threads
        result = run_command(baker_cli("build", "--recipe", project / "baker.toml", "--jobs", jobs, "-q",
                                       "--format", "json"), env)
        report = json.loads(result["stdout"])
        rows.append((name, result["wall"], result["cpu"], len(report["baked"]), len(report["skipped"])))

    with tempfile.TemporaryDirectory() as d:
        source = Path(d) / "source"
        make_thirty(source)
        for name, jobs, threads in (("clean build, --jobs 1", 1, None), ("clean build, --jobs 2", 2, None),
                                    ("clean build, --jobs 1, 1 kernel thread", 1, "1")):
            project = Path(d) / f"{jobs}-{threads}"
            shutil.copytree(source, project)
            (project / "baker.toml").write_text(recipe)
            timed(name, project, jobs, threads)
        timed("warm cache (nothing changed)", Path(d) / "2-None", 2)
    base = rows[0][1]
    print(f"30 assets ({', '.join(sorted(p.stem for p in SHARED.glob('*.obj')))} x 5 copies); bakes: "
          f"{', '.join(bakes)}; thickness 64 rays per vertex; {os.cpu_count()} cores; load average "
          f"{load_before:.2f} before, {os.getloadavg()[0]:.2f} after")
    print()
    print("| build | wall time (s) | CPU time (s) | cores busy | baked | cached | speed-up vs --jobs 1 |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, seconds, cpu, baked, cached in rows:
        print(f"| {name} | {seconds:.2f} | {cpu:.2f} | {cpu / seconds:.2f} | {baked} | {cached} | "
              f"{base / seconds:.2f}x |")
    single = rows[2][2]
    print()
    print(f"bound for --jobs 2 on 2 cores: wall(--jobs 1) / (single-threaded CPU / 2) = {base:.2f} / "
          f"({single:.2f} / 2) = {2 * base / single:.2f}x (an idle machine only: load inflates wall(--jobs 1))")
    return 0


if __name__ == "__main__":
    sys.exit(main())
