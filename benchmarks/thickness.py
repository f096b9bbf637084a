"""Per-vertex local thickness: baker vs pymeshlab's shape-diameter function vs a bare Embree call, same run.

    python benchmarks/thickness.py [--mesh PATH] [--rays 64] [--repeat 3] [--markdown]

Rows (best of --repeat, wall clock):
- baker: ``baker.techniques.thickness.kernel.local_thickness`` on every vertex (ray generation, Embree, reduction; 2 threads);
- pymeshlab: ``compute_scalar_by_shape_diameter_function_per_vertex`` with the same rays per vertex and a full
  hemisphere (cone_amplitude 180), which also casts rays along the inverted normal;
- embreex bare, 1 and 2 threads: only ``EmbreeScene.run`` (DISTANCE query) on the exact rays baker casts,
  pre-generated in baker's order.
"baker vs bare per core" divides baker's rays/s by the bare 2-thread rays/s: the share of Embree's throughput
baker keeps once its own work is counted.
"""
from __future__ import annotations

import argparse
import os
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry.normals import vertex_normals
from baker.geometry.welding import weld  # noqa: E402
from baker.geometry.raycast import RayScene
from baker.techniques.thickness.kernel import (SAMPLERS, _make_rays, hemisphere_samples, local_thickness,  # noqa: E402
                                               morton_order)
from common import best_of  # noqa: E402

DEFAULT_MESH = ROOT.parent / "shared" / "assets" / "meshes" / "stanford-bunny.obj"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default=str(DEFAULT_MESH))
    ap.add_argument("--rays", type=int, default=64)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    if not Path(args.mesh).is_file():
        print(f"mesh not found: {args.mesh}", file=sys.stderr)
        return 2

    import pymeshlab
    import trimesh

    mesh = trimesh.load(args.mesh, process=False)
    welded, inverse = weld(np.asarray(mesh.vertices, np.float64))
    faces = inverse[np.asarray(mesh.faces)]
    normals = vertex_normals(welded, faces)
    diag = float(np.linalg.norm(welded.max(0) - welded.min(0)))
    n, rays = len(welded), args.rays
    total = n * rays
    scene = RayScene(welded, faces)
    local_thickness(scene, welded[:64], normals[:64], rays=rays, max_distance=diag)  # compile numba kernels

    rows = []
    t_baker, values = best_of(args.repeat, lambda: local_thickness(scene, welded, normals, rays=rays,
                                                                   max_distance=diag, bias=1e-5 * diag, seed=0))
    rows.append(("baker local_thickness (2 threads)", t_baker))

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=welded, face_matrix=faces))

    def meshlab():
        ms.compute_scalar_by_shape_diameter_function_per_vertex(rays=rays, cone_amplitude=180.0)
        return ms.current_mesh().vertex_scalar_array().copy()

    t_meshlab, sdf = best_of(args.repeat, meshlab)
    rows.append(("pymeshlab shape diameter per vertex", t_meshlab))

    origins = np.empty((total, 3), np.float32)
    directions = np.empty((total, 3), np.float32)
    cos_t = np.empty(total)
    order = morton_order(welded)  # the order baker traces in
    rng = np.random.default_rng(0)  # the per-point numbers local_thickness draws for seed 0
    shifts = rng.random((n, 2))
    seeds = rng.integers(0, 1 << 32, (n, 2), dtype=np.uint64)
    _make_rays(welded[order], -normals[order], SAMPLERS.index("hammersley"), hemisphere_samples(rays, 0), shifts[order],
               seeds[order], True, 1.0, 0.0, 1e-5 * diag, origins, directions, cos_t)
    embreex_scene = RayScene(welded, faces, backend="embreex")
    chunks = [(s, min(total, s + (1 << 19))) for s in range(0, total, 1 << 19)]
    for threads in (1, 2):
        def bare():
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(lambda c: embreex_scene.distances(origins[c[0]:c[1]], directions[c[0]:c[1]]), chunks))
        t_bare, _ = best_of(args.repeat, bare)
        rows.append((f"embreex bare run, {threads} thread{'s' if threads > 1 else ''}", t_bare))

    bare2 = rows[-1][1]
    corr = float(np.corrcoef(values, sdf)[0, 1]) if np.std(sdf) > 0 else float("nan")
    print(f"mesh: {Path(args.mesh).name}, {n} vertices, {len(faces)} triangles; {rays} rays per vertex; "
          f"{os.cpu_count()} cores; best of {args.repeat}")
    print()
    print("| implementation | time (s) | Mrays/s | baker speed-up |")
    print("|---|---:|---:|---:|")
    for name, t in rows:
        print(f"| {name} | {t:.3f} | {total / t / 1e6:.2f} | {t / t_baker:.2f}x |")
    print()
    print(f"baker vs pymeshlab: {t_meshlab / t_baker:.2f}x faster (goal >= 2x)")
    print(f"baker vs bare embreex (2 threads): {bare2 / t_baker * 100:.0f}% of its rays/s (goal >= 80%)")
    print(f"correlation of baker thickness with pymeshlab SDF per vertex: {corr:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
