"""Thickness error against ray count for each sampler: RMS error of per-vertex thickness against a 4096-ray reference.

    python benchmarks/thickness_sampler.py [--meshes spot,torus,suzanne] [--rays 4,8,16,32,64,128] [--seeds 2]
        [--samplers fibonacci,hammersley,sobol,random]

For every held-in mesh (welded, area-weighted vertex normals as the bake uses), the reference is the mean of two
4096-ray estimates (sobol and hammersley, seed 1000: each sampler's own structure averages out, and at 4096 rays
both are far below the errors measured). Each sampler then runs at each ray count with seeds 0..--seeds-1; the
table gives the RMS over vertices and seeds of (estimate - reference), relative to the mean reference thickness,
and the fewest rays at which each sampler matches the error of 64 ``random`` rays (interpolated on log-log).
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry.normals import vertex_normals  # noqa: E402
from baker.geometry.raycast import RayScene  # noqa: E402
from baker.geometry.welding import weld  # noqa: E402
from baker.techniques.thickness.kernel import SAMPLERS, default_max_distance, local_thickness  # noqa: E402

# the shared assets sit beside the checkout (/work/main) or two levels up (a worktree /work/wt/N)
MESHES = next((p / "shared" / "assets" / "meshes" for p in ROOT.parents if (p / "shared" / "assets").is_dir()),
              ROOT.parent / "shared" / "assets" / "meshes")


def load(name: str):
    import trimesh

    if name == "torus":
        mesh = trimesh.creation.torus(major_radius=2.0, minor_radius=0.5, major_sections=96, minor_sections=48)
    elif name == "spot":
        mesh = trimesh.load(ROOT / "examples" / "spot" / "spot.obj", process=False, force="mesh")
    else:
        mesh = trimesh.load(MESHES / f"{name}.obj", process=False, force="mesh")
    welded, inverse = weld(np.asarray(mesh.vertices, np.float64))
    faces = inverse[np.asarray(mesh.faces)]
    return welded, faces


def rays_at_error(rays: list, errors: list, target: float) -> float:
    """Fewest rays reaching ``target``, interpolated between measured counts on log-log axes."""
    for (r0, e0), (r1, e1) in zip(zip(rays, errors), zip(rays[1:], errors[1:])):
        if e0 <= target:
            return float(r0)
        if e1 <= target:
            t = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(r0) + t * (math.log(r1) - math.log(r0)))
    return float("nan")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--meshes", default="spot,torus,suzanne", help="spot, torus or a shared mesh (stanford-bunny, ...)")
    ap.add_argument("--rays", default="4,8,16,32,64,128")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--samplers", default=",".join(SAMPLERS), help="comma-separated samplers to measure")
    args = ap.parse_args(argv)
    samplers = args.samplers.split(",")
    counts = [int(r) for r in args.rays.split(",")]
    print("RMS error of per-vertex thickness vs a 4096-ray reference, % of the mean thickness "
          f"(RMS over vertices and {args.seeds} seeds)")
    print()
    print("| mesh | vertices | sampler | " + " | ".join(f"{r} rays" for r in counts) + " | rays for random-64 error |")
    print("|---|---:|---|" + "---:|" * len(counts) + "---:|")
    for name in args.meshes.split(","):
        positions, faces = load(name)
        normals = vertex_normals(positions, faces)
        scene = RayScene(positions, faces)
        diag = default_max_distance(positions)
        common = dict(max_distance=diag, bias=1e-5 * diag)
        reference = 0.5 * (local_thickness(scene, positions, normals, rays=4096, seed=1000, sampler="sobol", **common)
                           + local_thickness(scene, positions, normals, rays=4096, seed=1000, sampler="hammersley",
                                             **common))
        scale = float(reference.mean())
        table = {}
        for sampler in dict.fromkeys(samplers + ["random"]):
            table[sampler] = []
            for rays in counts:
                squared = [np.mean((local_thickness(scene, positions, normals, rays=rays, seed=s, sampler=sampler,
                                                    **common) - reference) ** 2) for s in range(args.seeds)]
                table[sampler].append(100.0 * math.sqrt(float(np.mean(squared))) / scale)
        target = table["random"][counts.index(64)] if 64 in counts else float("nan")
        for sampler in table:
            needed = rays_at_error(counts, table[sampler], target)
            print(f"| {name} | {len(positions):,} | {sampler} | " + " | ".join(f"{e:.2f}" for e in table[sampler])
                  + f" | {needed:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
