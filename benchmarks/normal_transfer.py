"""The normal bake from a high mesh (``baker bake LOW --from HIGH --bakes normal``) against Blender Cycles'
Selected-to-Active bake of the same pair at the same size (issue 50's acceptance figure).

The pair: a geodesic sphere of ~300k triangles displaced by an analytic height field (tests/techniques/
displaced_sphere.py) and a 2k-triangle UV sphere. Both bakers write object-space maps (Cycles: ``normal_space=
"OBJECT"``, cage extrusion = the cage distance baker chose, 1 sample; baker: ``--normal-space object``), and each is
scored against the analytic normal where each texel's (radial) ray meets the displaced sphere: RMS and p99 angle
over the texel centres inside the low's triangles. Time: baker's whole command (process start to exit: reading both
OBJs, BVH, tracing, PNG) against Cycles' ``bpy.ops.object.bake`` call alone (its own clock; Blender's start-up and
import not counted) and its whole process; peak RSS of each process.

Usage: python benchmarks/normal_transfer.py [--size 1024] [--frequency 122]   (BAKER_BPY_PYTHON: Blender's Python)
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "techniques"))

import displaced_sphere as ds  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
from baker.gltf.images import decode_image  # noqa: E402
from baker.texels.texture_space import rasterize_uv  # noqa: E402
from common import baker_cli, run_command  # noqa: E402
from texel import bpy_python  # noqa: E402

CYCLES_SCRIPT = Path(__file__).with_name("normal_transfer_cycles.py")


def score(normals: np.ndarray, low_positions, low_uv, low_faces, size: int) -> tuple[float, float, int]:
    """(RMS, p99 angle in degrees, texels) of an object-space map (rows top-down) against the analytic normal."""
    texels = rasterize_uv(low_uv, low_faces, size, size)
    corners = low_positions[low_faces[texels.triangle]]
    point = np.einsum("kj,kjd->kd", texels.bary, corners)
    u = point / np.linalg.norm(point, axis=1, keepdims=True)
    truth = ds.analytic_normal(ds.surface_point(u))
    baked = normals[texels.rows, texels.cols]
    baked = baked / np.maximum(np.linalg.norm(baked, axis=1, keepdims=True), 1e-30)
    angle = np.degrees(np.arccos(np.clip(np.sum(baked * truth, axis=1), -1.0, 1.0)))
    return float(np.sqrt(np.mean(angle ** 2))), float(np.percentile(angle, 99)), len(angle)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--frequency", type=int, default=122, help="geodesic frequency: 20 f^2 high triangles")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds; the fastest of each is kept")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        high_positions, high_faces = ds.high_mesh(args.frequency)
        ds.write_obj(tmp / "high.obj", high_positions, high_faces)
        low_positions, low_uv, low_faces = ds.uv_sphere(32, 32)
        ds.write_obj(tmp / "low.obj", low_positions, low_faces, low_uv)
        out, npy = tmp / "baked.glb", tmp / "cycles.npy"
        ours, theirs, cycles_bake = [], [], []
        for _ in range(args.rounds):  # interleaved, so both see the same machine load
            ours.append(run_command(baker_cli("bake", tmp / "low.obj", "--from", tmp / "high.obj", "--bakes",
                                              "normal", "--normal-space", "object", "--normal-texture-size",
                                              args.size, "-o", out, "-q")))
            doc = GltfDocument.load(out)
            cage = doc.json["asset"]["extras"]["baker"]["transfer"]["cageDistance"]
            theirs.append(run_command([bpy_python(), CYCLES_SCRIPT, tmp / "low.obj", tmp / "high.obj", args.size,
                                       cage, npy]))
            cycles_bake.append([float(x) for x in next(line.split()[1:] for line in theirs[-1]["stdout"].splitlines()
                                                       if line.startswith("BAKE_SECONDS"))])
        material = doc.json["materials"][doc.json["meshes"][0]["primitives"][0]["material"]]
        info = material["extras"]["baker"]["objectSpaceNormalTexture"]
        pixels = decode_image(doc.image_bytes(doc.json["textures"][info["index"]]["source"]))
        baker_normals = pixels[..., :3].astype(np.float64) / 65535.0 * 2.0 - 1.0
        cycles_normals = np.load(npy).astype(np.float64) * 2.0 - 1.0
        result = {"highTriangles": len(high_faces), "lowTriangles": len(low_faces), "size": args.size,
                  "cageDistance": cage, "rounds": args.rounds}
        for name, normals, runs in (("baker", baker_normals, ours), ("cycles", cycles_normals, theirs)):
            rms, p99, count = score(normals, low_positions, low_uv, low_faces, args.size)
            result[name] = {"rmsDegrees": round(rms, 4), "p99Degrees": round(p99, 4), "texels": count,
                            "wallSeconds": round(min(r["wall"] for r in runs), 2),
                            "cpuSeconds": round(min(r["cpu"] for r in runs), 2),
                            "peakMiB": round(max(r["peak"] for r in runs) / 2 ** 20)}
        result["cycles"]["bakeCallWallSeconds"] = round(min(c[0] for c in cycles_bake), 2)
        result["cycles"]["bakeCallCpuSeconds"] = round(min(c[1] for c in cycles_bake), 2)
        print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
