"""End to end at production scale: ``baker bake`` (process start to file written) against a peer, same run.

    python benchmarks/scale.py [--levels 2,3,4] [--bakes edges,curvature,thickness] [--folder /tmp/baker-scale]
                               [--rays 16] [--repeat 5]

The Stanford bunny is subdivided ``level`` times (x4 triangles each: 2 -> 1.1 M, 3 -> 4.4 M, 4 -> 17.8 M) and
written as binary PLY into ``--folder`` (generated once, never committed). For every level and bake, baker's CLI
and its peer run one after the other in fresh processes (interleaved, so both see the same machine load); each row
gives wall time, time per million triangles, peak RSS (``wait4``'s ``ru_maxrss``) and bytes per triangle.

Peers (each reads the same PLY file and computes the same kind of result):
- edges: trimesh ``load(process=False)`` + ``face_adjacency`` + ``face_adjacency_angles`` (the pairs of faces
  sharing an edge and their dihedral angles; baker also welds, classifies, and writes visibility codes, the edge
  list and outline normals into a GLB);
- curvature: pymeshlab ``load_new_mesh`` + ``compute_curvature_principal_directions_per_vertex`` (per-vertex
  principal curvatures, the method of ``benchmarks/curvature.py``); trimesh's discrete curvature measures are ball
  queries (minutes at this size) and its ``vertex_defects`` only a Gaussian curvature, not principal curvatures;
- thickness (per vertex, ``--thickness-per-texel false``): baker's own kernel (``local_thickness`` on the welded
  vertices, in a process that loaded the mesh first, timed around the kernel only), as rays/s: the share of the
  kernel's throughput the command keeps. pymeshlab's shape-diameter function is the kernel benchmark's peer
  (``benchmarks/thickness.py``).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

from common import run_command as run

ROOT = Path(__file__).resolve().parents[1]
# the shared assets sit beside the checkout (/work/main) or two levels up (a worktree /work/wt/N)
BUNNY = next((p / "shared" / "assets" / "meshes" for p in ROOT.parents if (p / "shared" / "assets").is_dir()),
             ROOT.parent / "shared" / "assets" / "meshes") / "stanford-bunny.obj"

PEERS = {
    "edges": r'''
import sys, trimesh
m = trimesh.load(sys.argv[1], process=False)
m.face_adjacency, m.face_adjacency_angles
''',
    "curvature": r'''
import sys, pymeshlab
ms = pymeshlab.MeshSet()
ms.load_new_mesh(sys.argv[1])
ms.compute_curvature_principal_directions_per_vertex()
ms.current_mesh().vertex_scalar_array()
''',
    "thickness": r'''
import json, sys, time
import numpy as np
from baker import readers
from baker.geometry.normals import vertex_normals
from baker.geometry.raycast import RayScene
from baker.techniques.thickness.kernel import default_max_distance, local_thickness
asset = readers.read(sys.argv[1])
mesh = asset.welded(0, asset.triangle_primitives(0))
normals = vertex_normals(mesh.positions, mesh.faces)
diag = default_max_distance(mesh.positions)
rays = int(sys.argv[2])
start = time.perf_counter()
scene = RayScene(mesh.positions, mesh.faces)
local_thickness(scene, mesh.positions, normals, rays=rays, max_distance=diag, bias=1e-5 * diag, seed=0)
print(json.dumps({"kernel": time.perf_counter() - start, "rays": len(mesh.positions) * rays}))
''',
}


def subdivided(level: int, folder: Path) -> Path:
    out = folder / f"bunny{level}.ply"
    if not out.is_file():
        import trimesh

        mesh = trimesh.load(BUNNY, force="mesh")  # merged vertices
        for _ in range(level):
            mesh = mesh.subdivide()
        mesh.export(out)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", default="2,3,4")
    ap.add_argument("--bakes", default="edges,curvature,thickness")
    ap.add_argument("--folder", default=os.path.join(tempfile.gettempdir(), "baker-scale"))
    ap.add_argument("--rays", type=int, default=64, help="thickness rays per vertex")
    ap.add_argument("--json", help="also write the rows here")
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds of each baker/peer pair (interleaved); the table gives the median of each column")
    args = ap.parse_args(argv)
    folder = Path(args.folder)
    folder.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    python = sys.executable
    rows = []
    # compile/load numba caches once outside the timings (a user's second run; the first run pays the JIT)
    tiny = folder / "warm.ply"
    if not tiny.is_file():
        import trimesh

        trimesh.creation.icosphere(2).export(tiny)
    run([python, "-m", "baker.cli", "bake", tiny, "-o", folder / "warm.glb", "-q", "--bakes", args.bakes,
         "--thickness-per-texel", "false"], env)
    for level in [int(x) for x in args.levels.split(",")]:
        mesh = subdivided(level, folder)
        header = mesh.read_bytes()[:400].decode(errors="replace")
        triangles = int(header.split("element face ")[1].split()[0])
        for bake in args.bakes.split(","):
            out = folder / f"out{level}_{bake}.glb"
            cli = [python, "-m", "baker.cli", "bake", mesh, "-o", out, "-q", "--bakes", bake,
                   "--thickness-rays", str(args.rays)]
            if bake == "thickness":
                cli += ["--thickness-per-texel", "false"]
            peer_argv = [python, "-c", PEERS[bake], mesh] + ([str(args.rays)] if bake == "thickness" else [])
            rounds = []
            for _ in range(max(1, args.repeat)):  # a pair per round: both see the same moment of a noisy machine
                baker = run(cli, env)
                peer = run(peer_argv, env)
                one = {"baker_wall": baker["wall"], "baker_peak": baker["peak"], "peer_wall": peer["wall"],
                       "peer_peak": peer["peak"]}
                if bake == "thickness":
                    kernel = json.loads(peer["stdout"].strip().splitlines()[-1])
                    one.update(kernel_wall=kernel["kernel"], rays=kernel["rays"],
                               cli_over_kernel=kernel["kernel"] / baker["wall"])
                rounds.append(one)
            row = {"level": level, "triangles": triangles, "bake": bake, "output_bytes": out.stat().st_size,
                   **{key: statistics.median(r[key] for r in rounds) for key in rounds[0]}}
            if len(rounds) > 1:
                row["rounds"] = rounds
            rows.append(row)
            out.unlink()
            print(json.dumps(row), file=sys.stderr, flush=True)
    print_table(rows)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


def print_table(rows: list) -> None:
    repeats = max(len(r.get("rounds", [])) or 1 for r in rows) if rows else 1
    print(f"{os.cpu_count()} cores; " + (f"median of {repeats} rounds" if repeats > 1 else "one run each") +
          ", baker and peer interleaved; peak RSS from wait4")
    print()
    print("| bake | triangles | baker (s) | peer (s) | baker / peer time | baker s/Mtri | peer s/Mtri | baker B/tri "
          "| peer B/tri | baker / peer RSS | s/Mtri vs smallest |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    smallest = {}
    for r in rows:
        mtri = r["triangles"] / 1e6
        per = r["baker_wall"] / mtri
        smallest.setdefault(r["bake"], per)
        print(f"| {r['bake']} | {r['triangles']:,} | {r['baker_wall']:.1f} | {r['peer_wall']:.1f} | "
              f"{r['baker_wall'] / r['peer_wall']:.2f} | {per:.2f} | {r['peer_wall'] / mtri:.2f} | "
              f"{r['baker_peak'] / r['triangles']:.0f} | {r['peer_peak'] / r['triangles']:.0f} | "
              f"{r['baker_peak'] / r['peer_peak']:.2f} | {per / smallest[r['bake']]:.2f} |")
    thick = [r for r in rows if r["bake"] == "thickness"]
    if thick:
        print()
        print("| thickness triangles | rays | CLI Mrays/s (process start to file) | kernel Mrays/s | CLI / kernel "
              "(median of the rounds' ratios) | per round |")
        print("|---:|---:|---:|---:|---:|---|")
        for r in thick:
            cli, kernel = r["rays"] / r["baker_wall"] / 1e6, r["rays"] / r["kernel_wall"] / 1e6
            per_round = ", ".join(f"{x['cli_over_kernel']:.0%}" for x in r.get("rounds", []))
            print(f"| {r['triangles']:,} | {r['rays']:,} | {cli:.2f} | {kernel:.2f} | {r['cli_over_kernel']:.0%} | "
                  f"{per_round or '-'} |")


def _spawned(argv: list, env: dict) -> dict:
    """:func:`run` from a small spawner process: a child forked from a big parent (a kernel benchmark holding its
    mesh) reports the parent's RSS at fork as its own peak (Linux keeps the pre-exec high-water mark)."""
    code = ("import json, sys; sys.path.insert(0, sys.argv[1]); from scale import run; "
            "print(json.dumps(run(json.loads(sys.argv[2]), None)))")
    out = run([sys.executable, "-c", code, str(Path(__file__).resolve().parent), json.dumps([str(a) for a in argv])],
              env)
    return json.loads(out["stdout"].strip().splitlines()[-1])


def end_to_end(bake: str, mesh: Path, rays: int = 16) -> dict:
    """``baker bake --bakes BAKE`` on ``mesh`` (process start to file written) and then its peer of ``PEERS``, as
    fresh processes back to back: wall times and peak RSS (bytes), for the end-to-end row of a kernel benchmark."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    with tempfile.TemporaryDirectory() as folder:
        cli = [sys.executable, "-m", "baker.cli", "bake", mesh, "-o", Path(folder) / "out.glb", "-q", "--bakes", bake,
               "--thickness-rays", str(rays)] + (["--thickness-per-texel", "false"] if bake == "thickness" else [])
        baker = _spawned(cli, env)
    peer = _spawned([sys.executable, "-c", PEERS[bake], mesh] + ([str(rays)] if bake == "thickness" else []), env)
    return {"command": f"baker bake {Path(mesh).name} --bakes {bake}", "baker_wall": baker["wall"],
            "baker_peak": baker["peak"], "peer_wall": peer["wall"], "peer_peak": peer["peak"]}


def end_to_end_row(row: dict, triangles: int, peer: str) -> str:
    """A markdown table row of an :func:`end_to_end` result (columns: what, time, baker / peer time, peak RSS,
    bytes per triangle, baker / peer RSS)."""
    return (f"| end to end: `{row['command']}` vs {peer} (fresh processes) | {row['baker_wall']:.2f} s vs "
            f"{row['peer_wall']:.2f} s | {row['baker_wall'] / row['peer_wall']:.2f}x | "
            f"{row['baker_peak'] / 1e6:.0f} MB vs {row['peer_peak'] / 1e6:.0f} MB | "
            f"{row['baker_peak'] / triangles:.0f} vs {row['peer_peak'] / triangles:.0f} | "
            f"{row['baker_peak'] / row['peer_peak']:.2f}x |")


if __name__ == "__main__":
    sys.exit(main())
