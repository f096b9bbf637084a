"""Edge adjacency + classification: baker vs trimesh's face_adjacency + face_adjacency_angles, same run.

    python benchmarks/edges.py [--mesh PATH] [--subdivide 2] [--repeat 3]

The mesh (the Stanford bunny by default) is subdivided (each level x4 triangles; 2 levels: ~1.1 M triangles).
Rows (best of --repeat, wall clock, numba kernels compiled before timing):
- trimesh: a fresh ``Trimesh(process=False)`` (nothing cached), then ``face_adjacency`` and
  ``face_adjacency_angles`` (which computes the face normals): the pairs of faces sharing an edge and their angles;
- baker core: ``weld_positions`` + ``edge_topology`` + ``classify_edges`` (unique edges with all their faces,
  boundary/non-manifold/winding, signed dihedral angles, crease/ridge/valley/planar flags);
- baker full: ``analyze_mesh`` (the core plus material edges, quad diagonals and angle-weighted outline normals);
- end to end (``--end-to-end``, default on): the same mesh written as binary PLY, then the command a user runs,
  ``baker bake mesh.ply --bakes edges`` (process start to GLB written), against a process that loads the PLY with
  trimesh and computes the two properties above (``benchmarks/scale.py``'s peer), with peak RSS per triangle.
Baker also welds the positions, which trimesh is spared (the subdivided mesh is already welded).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry import edges as E  # noqa: E402
from common import best_of  # noqa: E402

DEFAULT_MESH = ROOT.parent / "shared" / "assets" / "meshes" / "stanford-bunny.obj"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default=str(DEFAULT_MESH))
    ap.add_argument("--subdivide", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--end-to-end", action=argparse.BooleanOptionalAction, default=True,
                    help="also time the CLI on the mesh written as PLY against trimesh in a fresh process")
    args = ap.parse_args(argv)
    if not Path(args.mesh).is_file():
        print(f"mesh not found: {args.mesh}", file=sys.stderr)
        return 2
    import trimesh

    mesh = trimesh.load(args.mesh, force="mesh")  # merged vertices
    for _ in range(args.subdivide):
        mesh = mesh.subdivide()
    vertices, faces = np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64)
    small = trimesh.creation.icosphere(1)
    E.analyze_mesh(small.vertices, small.faces)  # compile the numba kernels outside the timings

    def run_trimesh():
        m = trimesh.Trimesh(vertices, faces, process=False)
        return m.face_adjacency, m.face_adjacency_angles

    def run_core():
        welded, inverse = E.weld_positions(vertices)
        fw = inverse[faces]
        topo = E.edge_topology(fw, len(welded))
        return topo, E.classify_edges(welded, fw, topo, crease_angle=60.0)

    t_tm, (adjacency, angles) = best_of(args.repeat, run_trimesh)
    t_core, (topo, classes) = best_of(args.repeat, run_core)
    t_full, _ = best_of(args.repeat, lambda: E.analyze_mesh(vertices, faces))

    interior = (classes.flags & (E.BOUNDARY | E.NON_MANIFOLD)) == 0
    creases_tm = int(np.count_nonzero(angles > math.radians(60.0)))
    creases_baker = int(np.count_nonzero(classes.flags & E.CREASE))
    print(f"mesh: {Path(args.mesh).name} subdivided {args.subdivide}x: {len(vertices)} vertices, {len(faces)} "
          f"triangles; {os.cpu_count()} cores; best of {args.repeat}")
    print()
    print("| implementation | time (s) | Mtriangles/s | baker speed-up |")
    print("|---|---:|---:|---:|")
    for name, t in (("trimesh face_adjacency + face_adjacency_angles", t_tm), ("baker core (weld + edges + classes)",
                                                                                t_core),
                    ("baker analyze_mesh (+ material, quads, outline normals)", t_full)):
        print(f"| {name} | {t:.3f} | {len(faces) / t / 1e6:.2f} | {t_tm / t:.2f}x |")
    if args.end_to_end:
        import tempfile

        from scale import end_to_end, end_to_end_row

        with tempfile.TemporaryDirectory() as folder:
            ply = Path(folder) / "mesh.ply"
            mesh.export(ply)
            row = end_to_end("edges", ply)
        print()
        print("| end to end | baker vs peer | baker / peer time | peak RSS | bytes / triangle | baker / peer RSS |")
        print("|---|---:|---:|---:|---:|---:|")
        print(end_to_end_row(row, len(faces), "trimesh load + face_adjacency + face_adjacency_angles"))
    print()
    print(f"baker core vs trimesh: {t_tm / t_core:.2f}x faster (goal >= 2x)")
    print(f"interior edges: baker {int(interior.sum())}, trimesh adjacency pairs {len(adjacency)}; "
          f"creases > 60 deg: baker {creases_baker}, trimesh {creases_tm}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
