"""Per-vertex curvature: baker vs pymeshlab's compute_curvature_principal_directions_per_vertex, same run; and the
skin LUT generation time.

    python benchmarks/curvature.py [--mesh PATH] [--repeat 3] [--skip-slow]

- time: wall clock on stanford-bunny (welded), best of --repeat (numba kernels compiled before timing);
- error: mean curvature H against the analytic H(v) = (R + 2 r cos v) / (2 r (R + r cos v)) on a torus R = 2,
  r = 0.5 with about the bunny's vertex count (264 x 132 = 34,848 vertices), as median / 95th-percentile relative
  error; and on the same torus with every vertex jittered by a Gaussian of 5% of the mean edge length (seed 0), a
  stand-in for scan noise (the truth is the smooth torus's H at the unjittered vertex). pymeshlab's value is its per-vertex quality with curvcolormethod = mean; MeshLab's "Principal Component
  Analysis" and "Normal Cycles" report other scales (not H) and are left out. baker runs with its defaults
  (adjacent-normal cubic fit, 2 rings, 2 smoothing passes), and its quadric fit for comparison.
- end to end (``--end-to-end``, default on): ``baker bake MESH --bakes curvature`` (process start to GLB written)
  against pymeshlab loading the same file and computing per-vertex principal curvatures in a fresh process
  (``benchmarks/scale.py``'s peer), with peak RSS per triangle;
- LUT: Penner's 256 x 256 diffusion LUT (d'Eon skin, 256 samples per Gaussian and row) and the 128 x 128 penumbra LUT.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry.welding import weld  # noqa: E402
from baker.techniques.curvature.kernel import principal_curvatures  # noqa: E402
from baker.techniques.skin import kernel as skin_lut  # noqa: E402
from common import best_of  # noqa: E402

DEFAULT_MESH = ROOT.parent / "shared" / "assets" / "meshes" / "stanford-bunny.obj"
MESHLAB_METHODS = {0: "Taubin approximation", 3: "Quadric Fitting (default)", 4: "Scale Dependent Quadric Fitting"}


def torus(major=2.0, minor=0.5, sections=(264, 132)):
    import trimesh

    mesh = trimesh.creation.torus(major_radius=major, minor_radius=minor, major_sections=sections[0],
                                  minor_sections=sections[1])
    v = np.asarray(mesh.vertices)
    rho = np.hypot(v[:, 0], v[:, 1])
    tube = np.arctan2(v[:, 2], rho - major)
    truth = (major + 2 * minor * np.cos(tube)) / (2 * minor * (major + minor * np.cos(tube)))
    return v, np.asarray(mesh.faces), truth


def meshlab_mean(vertices, faces, method):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces))
    ms.compute_curvature_principal_directions_per_vertex(method=method, curvcolormethod=0, autoclean=False)
    return ms.current_mesh().vertex_scalar_array().copy()


def errors(values, truth):
    rel = np.abs(values - truth) / np.abs(truth)
    return float(np.median(rel)), float(np.percentile(rel, 95))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default=str(DEFAULT_MESH))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-slow", action="store_true", help="leave out Scale Dependent Quadric Fitting (~20 s)")
    ap.add_argument("--end-to-end", action=argparse.BooleanOptionalAction, default=True,
                    help="also time the CLI on --mesh against pymeshlab in a fresh process")
    args = ap.parse_args(argv)
    if not Path(args.mesh).is_file():
        print(f"mesh not found: {args.mesh}", file=sys.stderr)
        return 2
    import trimesh

    mesh = trimesh.load(args.mesh, process=False)
    welded, inverse = weld(np.asarray(mesh.vertices, np.float64))
    faces = inverse[np.asarray(mesh.faces)]
    faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    tv, tf, truth = torus()
    edge = np.linalg.norm(tv[tf[:, 0]] - tv[tf[:, 1]], axis=1).mean()
    noisy = tv + np.random.default_rng(0).normal(scale=0.05 * edge, size=tv.shape)
    principal_curvatures(tv[:200], tf[:0])  # compile the numba kernels outside the timings
    principal_curvatures(tv, tf)
    principal_curvatures(tv, tf, fit="quadric")

    rows = []
    t_bunny, _ = best_of(args.repeat, lambda: principal_curvatures(welded, faces))
    t_torus, result = best_of(args.repeat, lambda: principal_curvatures(tv, tf))
    rows.append(("baker adjacent-normal cubic fit (default), 2 rings, 2 smoothing passes", t_bunny, t_torus, *errors(result.mean, truth),
                 errors(principal_curvatures(noisy, tf).mean, truth)[0]))
    t_b, _ = best_of(args.repeat, lambda: principal_curvatures(welded, faces, fit="quadric"))
    t_t, result = best_of(args.repeat, lambda: principal_curvatures(tv, tf, fit="quadric"))
    rows.append(("baker quadric fit, 2 rings, 2 smoothing passes", t_b, t_t, *errors(result.mean, truth),
                 errors(principal_curvatures(noisy, tf, fit="quadric").mean, truth)[0]))
    for method, name in MESHLAB_METHODS.items():
        if method == 4 and args.skip_slow:
            continue
        repeat = 1 if method == 4 else args.repeat
        t_b, _ = best_of(repeat, lambda: meshlab_mean(welded, faces, method))
        t_t, values = best_of(repeat, lambda: meshlab_mean(tv, tf, method))
        rows.append((f"pymeshlab {name}", t_b, t_t, *errors(values, truth),
                     errors(meshlab_mean(noisy, tf, method), truth)[0]))

    print(f"Curvature: bunny {len(welded)} vertices / {len(faces)} triangles; torus R=2 r=0.5 {len(tv)} vertices\n")
    print("| method | bunny time (s) | vs baker | torus time (s) | torus H median rel. error | torus H p95 rel. error |"
          " error vs baker | noisy torus H median rel. error | noisy error vs baker |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    base_t, base_e, base_noisy = rows[0][1], rows[0][3], rows[0][5]
    for name, tb, tt, med, p95, noisy_med in rows:
        print(f"| {name} | {tb:.3f} | {tb / base_t:.2f}x | {tt:.3f} | {med * 100:.3f}% | {p95 * 100:.3f}% | "
              f"{med / base_e:.2f}x | {noisy_med * 100:.2f}% | {noisy_med / base_noisy:.1f}x |")

    if args.end_to_end:
        from scale import end_to_end, end_to_end_row

        row = end_to_end("curvature", Path(args.mesh))
        print()
        print("| end to end | baker vs peer | baker / peer time | peak RSS | bytes / triangle | baker / peer RSS |")
        print("|---|---:|---:|---:|---:|---:|")
        print(end_to_end_row(row, len(faces), "pymeshlab load + compute_curvature_principal_directions_per_vertex"))

    t_lut, (lut, _) = best_of(args.repeat, lambda: skin_lut.diffusion_lut(256, 256))
    t_pen, _ = best_of(args.repeat, lambda: skin_lut.penumbra_lut(128))
    t_ker, _ = best_of(args.repeat, lambda: skin_lut.jimenez_kernel(25))
    print("\nSkin LUTs (d'Eon skin profile, 6 Gaussians)\n")
    print("| table | size | time (s) |")
    print("|---|---|---:|")
    print(f"| Penner diffusion LUT, 256 samples per Gaussian and row | 256 x 256 | {t_lut:.3f} |")
    print(f"| penumbra LUT (closed form) | 128 x 128 | {t_pen:.4f} |")
    print(f"| Jimenez separable kernel | 25 taps | {t_ker:.5f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
