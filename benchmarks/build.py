"""`baker build` on 30 assets (the shared meshes as scaled/rotated copies): --jobs 1 vs --jobs 2 vs a warm cache.

    python benchmarks/build.py [--bakes thickness,curvature,edges]

Each row is a fresh copy of the same 30 inputs (the warm row re-runs the --jobs 2 project, where every output is
cached). Uses the same asset generator as tests/test_build.py.
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import test_build  # noqa: E402
from baker.commands.build import build, load_recipe  # noqa: E402
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
             "[options.thickness]\nrays = 64\nper_texel = false\n\n[[assets]]\ninputs = [\"assets/*\"]\n"
    rows = []
    with tempfile.TemporaryDirectory() as d:
        source = Path(d) / "source"
        make_thirty(source)
        for jobs in (1, 2):
            project = Path(d) / f"jobs{jobs}"
            shutil.copytree(source, project)
            (project / "baker.toml").write_text(recipe)
            t = time.perf_counter()
            report = build(load_recipe(project / "baker.toml"), jobs=jobs)
            rows.append((f"clean build, --jobs {jobs}", time.perf_counter() - t, len(report["baked"]),
                         len(report["skipped"])))
        t = time.perf_counter()
        report = build(load_recipe(Path(d) / "jobs2" / "baker.toml"), jobs=2)
        rows.append(("warm cache (nothing changed)", time.perf_counter() - t, len(report["baked"]),
                     len(report["skipped"])))
    base = rows[0][1]
    print(f"30 assets ({', '.join(sorted(p.stem for p in SHARED.glob('*.obj')))} x 5 copies); bakes: "
          f"{', '.join(bakes)}; thickness 64 rays per vertex; 2 cores")
    print()
    print("| build | wall time (s) | baked | cached | speed-up vs --jobs 1 |")
    print("|---|---:|---:|---:|---:|")
    for name, seconds, baked, cached in rows:
        print(f"| {name} | {seconds:.2f} | {baked} | {cached} | {base / seconds:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
