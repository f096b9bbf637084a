"""Peak memory of each bake against mesh size: the figures behind baker.memory's estimate.

``python benchmarks/bake_memory.py [--levels 0,1,2,3] [--bakes thickness,curvature,...]`` subdivides Spot (5,856
triangles) ``level`` times (x4 triangles each), runs each bake alone in a fresh process and prints the peak resident
set size (ru_maxrss) above a process that only loads the same mesh, per triangle, with the slope between the
smallest and the largest mesh (the per-triangle figure; the intercept is the bake's fixed cost: textures, kernels).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).parents[1]
CHILD = r'''
import json, resource, sys
from baker import readers
asset = readers.read(sys.argv[1])
bakes = [b for b in sys.argv[2].split(",") if b]
if bakes:
    from baker.pipeline import bake
    bake(asset, bakes=bakes)
tris = sum(len(asset.primitive(m, p).faces) for m in range(len(asset.meshes())) for p in asset.triangle_primitives(m))
print(json.dumps({"peak": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, "triangles": tris}))
'''


def subdivided(level: int, folder: Path) -> Path:
    import trimesh

    mesh = trimesh.load(REPO / "examples/spot/spot.obj", process=False)
    vertices, faces = mesh.vertices, mesh.faces
    uv = mesh.visual.uv
    for _ in range(level):
        vertices, faces, uv = _subdivide(vertices, faces, uv)
    out = folder / f"spot{level}.obj"
    lines = [f"v {x:.7g} {y:.7g} {z:.7g}" for x, y, z in vertices]
    lines += [f"vt {u:.7g} {v:.7g}" for u, v in uv]
    lines += [f"f {a}/{a} {b}/{b} {c}/{c}" for a, b, c in faces + 1]
    out.write_text("\n".join(lines) + "\n")
    return out


def _subdivide(vertices, faces, uv):
    import trimesh

    v, f, attrs = trimesh.remesh.subdivide(vertices, faces, vertex_attributes={"uv": uv}, return_index=False)
    return v, f, attrs["uv"]


def run(path: Path, bakes: str) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(path), bakes], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(REPO)})
    if out.returncode:
        raise SystemExit(f"{path.name} {bakes}: {out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--levels", default="0,1,2,3")
    parser.add_argument("--bakes", default="thickness,curvature,edges,skin,tam,toon,fur")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as d:
        meshes = {lvl: subdivided(lvl, Path(d)) for lvl in (int(x) for x in args.levels.split(","))}
        base = {lvl: run(p, "") for lvl, p in meshes.items()}
        print("bake        triangles   peak MiB   above load MiB   bytes/triangle")
        table = {}
        for bake in args.bakes.split(","):
            rows = []
            for lvl, p in meshes.items():
                r = run(p, bake)
                extra = r["peak"] - base[lvl]["peak"]
                rows.append((r["triangles"], extra))
                print(f"{bake:10s} {r['triangles']:10d} {r['peak'] / 2**20:10.0f} {extra / 2**20:16.1f} "
                      f"{extra / r['triangles']:16.0f}", flush=True)
            (t0, e0), (t1, e1) = rows[0], rows[-1]
            slope = (e1 - e0) / max(t1 - t0, 1)
            table[bake] = {"bytes_per_triangle": round(slope), "fixed_bytes": round(e0 - slope * t0)}
            print(f"{bake:10s} slope {slope:.0f} B/triangle, fixed {(e0 - slope * t0) / 2**20:.0f} MiB", flush=True)
        load = [(base[lvl]["triangles"], base[lvl]["peak"]) for lvl in meshes]
        (t0, p0), (t1, p1) = load[0], load[-1]
        print(f"load       slope {(p1 - p0) / max(t1 - t0, 1):.0f} B/triangle, base {p0 / 2**20:.0f} MiB")
        print(json.dumps(table))


if __name__ == "__main__":
    main()
