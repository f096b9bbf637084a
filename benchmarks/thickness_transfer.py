"""Thickness of a game mesh from its sculpt (``--bakes thickness --from HIGH``) against the game mesh's own.

The Stanford bunny (69k triangles) decimated by Blender's Decimate modifier (collapse) to ~2,000 triangles is the
game mesh. Truth at each of its vertices: the original's own per-vertex ``_THICKNESS`` (``baker bake HIGH``)
interpolated at the closest point of the original's surface (trimesh's closest point, not baker's rays). Compared:
the decimated mesh's own thickness (``baker bake LOW``) and the thickness moved from the original (``baker bake LOW
--from HIGH``); relative RMS and p90 over the vertices.

Usage: python benchmarks/thickness_transfer.py [--faces 2000]   (BAKER_BPY_PYTHON: Blender's Python)
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.gltf.accessors import to_float  # noqa: E402
from baker.gltf.document import GltfDocument  # noqa: E402
from common import baker_cli, run_command  # noqa: E402
from texel import bpy_python  # noqa: E402

BUNNY = ROOT.parent / "shared" / "assets" / "meshes" / "stanford-bunny.obj"
DECIMATE = """
import sys, bpy
src, faces, out = sys.argv[-3], int(sys.argv[-2]), sys.argv[-1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=src, forward_axis="Y", up_axis="Z")
obj = bpy.context.scene.objects[0]
bpy.context.view_layer.objects.active = obj
modifier = obj.modifiers.new("decimate", "DECIMATE")
modifier.ratio = faces / len(obj.data.polygons)
modifier.use_collapse_triangulate = True
bpy.ops.object.modifier_apply(modifier="decimate")
bpy.ops.wm.obj_export(filepath=out, forward_axis="Y", up_axis="Z", export_uv=False, export_normals=False,
                      export_materials=False, export_selected_objects=False)
"""


def vertex_thickness(path: Path):
    doc = GltfDocument.load(path)
    prim = doc.json["meshes"][0]["primitives"][0]
    values = to_float(doc, prim["attributes"]["_THICKNESS"])
    values = values[:, 0] if values.ndim == 2 else values
    faces = doc.accessor(prim["indices"]).reshape(-1, 3).astype(np.int64)
    return to_float(doc, prim["attributes"]["POSITION"]), faces, values


def main() -> None:
    import trimesh

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, default=2000)
    parser.add_argument("--high", default=str(BUNNY))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        low = tmp / "low.obj"
        script = tmp / "decimate.py"
        script.write_text(DECIMATE)
        subprocess.run([bpy_python(), script, args.high, str(args.faces), low], check=True, capture_output=True)
        runs = {}
        for name, argv in (("high", [args.high]), ("low", [low]), ("from", [low, "--from", args.high])):
            out = tmp / f"{name}.glb"
            runs[name] = run_command(baker_cli("bake", *argv, "--bakes", "thickness", "--thickness-per-texel", "false",
                                               "-o", out, "-q"))
            runs[name]["values"] = vertex_thickness(out)
        high_positions, high_faces, high_values = runs["high"]["values"]
        low_positions, low_faces, _ = runs["low"]["values"]
        mesh = trimesh.Trimesh(high_positions, high_faces, process=False)
        closest, _, triangle = trimesh.proximity.closest_point(mesh, low_positions)
        bary = trimesh.triangles.points_to_barycentric(mesh.triangles[triangle], closest)
        truth = np.einsum("kj,kj->k", bary, high_values[high_faces[triangle]])
        result = {"highTriangles": len(high_faces), "lowTriangles": len(low_faces), "lowVertices": len(low_positions)}
        for name in ("low", "from"):
            relative = np.abs(runs[name]["values"][2] - truth) / truth
            result[name] = {"relativeRms": round(float(np.sqrt(np.mean(relative ** 2))), 4),
                            "relativeP90": round(float(np.percentile(relative, 90)), 4),
                            "wallSeconds": round(runs[name]["wall"], 2), "cpuSeconds": round(runs[name]["cpu"], 2)}
        print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
