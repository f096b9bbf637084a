"""Run inside Blender's Python (the bpy venv): import each glTF given after ``--`` with Blender's stock importer
(or with the baker add-on when ``--addon`` is given) and write a JSON report of what came in.

Usage: python import_report.py [--addon DIR] --out REPORT.json -- FILE.glb [FILE.glb ...]
The report has, per file: ``error`` (the importer's message, or None), and per object its type, and for meshes
every attribute (name, domain, data type, values as lists) and the vertex positions in glTF axes (Y up)."""
import json
import sys

import bpy
import numpy as np

COMPONENTS = {"FLOAT": 1, "INT": 1, "BOOLEAN": 1, "FLOAT2": 2, "FLOAT_VECTOR": 3, "FLOAT_COLOR": 4, "BYTE_COLOR": 4,
              "INT32_2D": 2, "INT8": 1, "QUATERNION": 4, "FLOAT4X4": 16}
FIELD = {"FLOAT_VECTOR": "vector", "FLOAT2": "vector", "FLOAT_COLOR": "color", "BYTE_COLOR": "color",
         "QUATERNION": "value", "FLOAT4X4": "value"}


def attribute_values(attribute) -> list:
    n = len(attribute.data)
    width = COMPONENTS.get(attribute.data_type, 1)
    if attribute.data_type == "BOOLEAN":  # foreach_get of booleans wants a Python sequence
        return [[bool(d.value)] for d in attribute.data]
    dtype = np.float32 if attribute.data_type.startswith("FLOAT") or "COLOR" in attribute.data_type else np.int32
    values = np.zeros(n * width, dtype)
    attribute.data.foreach_get(FIELD.get(attribute.data_type, "value"), values)
    return values.reshape(n, width).tolist()


def blender_to_gltf(points: np.ndarray) -> np.ndarray:
    """Blender Z up -> glTF Y up (the importer's conversion, inverted): (x, y, z) -> (x, z, -y)."""
    return np.stack([points[:, 0], points[:, 2], -points[:, 1]], axis=1)


def describe(obj) -> dict:
    row = {"name": obj.name, "type": obj.type, "properties": {k: str(obj[k])[:200] for k in obj.keys()}}
    if obj.type == "MESH":
        mesh = obj.data
        co = np.zeros(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", co)
        row["mesh"] = mesh.name
        row["positions"] = blender_to_gltf(co.reshape(-1, 3)).tolist()
        row["edges"] = [list(e.vertices) for e in mesh.edges]
        row["attributes"] = {a.name: {"domain": a.domain, "data_type": a.data_type, "values": attribute_values(a)}
                             for a in mesh.attributes if not a.name.startswith(".") and a.data_type in COMPONENTS}
        row["materials"] = [m.name if m else None for m in mesh.materials]
        if hasattr(mesh.edges, "foreach_get") and bpy.app.version < (5, 0, 0):  # 5.0: the freestyle_edge attribute
            marks = np.zeros(len(mesh.edges), bool)
            mesh.edges.foreach_get("use_freestyle_mark", marks)
            row["freestyle_marks"] = int(marks.sum())
    elif obj.type == "CURVES":
        curves = obj.data
        co = np.zeros(len(curves.points) * 3, np.float32)
        curves.points.foreach_get("position", co)
        row["positions"] = blender_to_gltf(co.reshape(-1, 3)).tolist()
        row["curve_sizes"] = [c.points_length for c in curves.curves]
        row["attributes"] = {a.name: {"domain": a.domain, "data_type": a.data_type, "values": attribute_values(a)}
                             for a in curves.attributes if not a.name.startswith(".") and a.data_type in COMPONENTS}
    return row


def main(argv: list) -> None:
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    opts = argv[1:argv.index("--")] if "--" in argv else argv[1:]
    out = opts[opts.index("--out") + 1]
    addon = opts[opts.index("--addon") + 1] if "--addon" in opts else None
    if addon:
        sys.path.insert(0, addon)
        import baker_blender
    report = {}
    for path in args:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        if addon:
            baker_blender.enable()
        entry = {"error": None, "objects": []}
        try:
            result = bpy.ops.import_scene.gltf(filepath=path)
            if "FINISHED" not in result:
                entry["error"] = f"importer returned {sorted(result)}"
        except Exception as e:  # the importer reports its failures as RuntimeError
            entry["error"] = str(e).strip().splitlines()[-1] if str(e).strip() else repr(e)
        entry["objects"] = [describe(o) for o in bpy.data.objects]
        report[path] = entry
    with open(out, "w") as f:
        json.dump(report, f)


if __name__ == "__main__":
    main(sys.argv)
