"""Run inside Blender's Python: enable the baker add-on, import a baked .glb, export it again (glTF Binary), and
write a JSON report of what the add-on made in Blender.

Usage: python round_trip.py ADDON_DIR IN.glb OUT.glb REPORT.json"""
import json
import sys

import bpy
import numpy as np

addon, source, target, report_path = sys.argv[1:5]
sys.path.insert(0, addon)
import baker_blender  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
report = {"objects": {}, "materials": {}, "node_groups": sorted(g.name for g in bpy.data.node_groups)}
for obj in bpy.data.objects:
    row = {"type": obj.type, "hidden": obj.hide_render, "properties": sorted(obj.keys())}
    if obj.type == "MESH":
        mesh = obj.data
        row["mesh_properties"] = sorted(mesh.keys())
        count = len(mesh.edges)
        co = np.zeros(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        co = np.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1)  # back to glTF axes (Y up)
        pairs = np.zeros(count * 2, np.int32)
        mesh.edges.foreach_get("vertices", pairs)
        pairs = pairs.reshape(-1, 2)
        for name in ("sharp_edge", "freestyle_edge"):
            values = np.zeros(count, bool)
            if name == "freestyle_edge" and bpy.app.version < (5, 0, 0):
                # what Freestyle and Line Art read before Blender 5.0 (a generic attribute of that name is ignored)
                mesh.edges.foreach_get("use_freestyle_mark", values)
                generic = np.zeros(count, bool)
                if name in mesh.attributes:
                    mesh.attributes[name].data.foreach_get("value", generic)
                row["freestyle_edge_attribute"] = int(generic.sum())
            elif name in mesh.attributes:
                mesh.attributes[name].data.foreach_get("value", values)
            row[name] = int(values.sum())
            row[name + "_positions"] = [co[list(pair)].tolist() for pair in pairs[values]]
        row["edges"] = count
        row["attributes"] = {a.name: a.data_type for a in mesh.attributes if a.name.startswith("_")}
        row["uv_layers"] = [layer.name for layer in mesh.uv_layers]
    if obj.type == "CURVES":
        row["curves"] = len(obj.data.curves)
        row["points"] = len(obj.data.points)
        row["attributes"] = {a.name: a.data_type for a in obj.data.attributes if a.name.startswith("_")}
    report["objects"][obj.name] = row
for mat in bpy.data.materials:
    tree = mat.node_tree
    groups = sorted(n.node_tree.name for n in tree.nodes if n.type == "GROUP") if tree else []
    mixes = {n.name: n.inputs["Fac"].default_value for n in tree.nodes if n.type == "MIX_SHADER"} if tree else {}
    uv_maps = {n.name: n.uv_map for n in tree.nodes if n.type == "UVMAP"} if tree else {}
    report["materials"][mat.name] = {"groups": groups, "mixes": mixes, "payload": "baker_gltf" in mat,
                                     "uv_maps": uv_maps}
bpy.ops.export_scene.gltf(filepath=target, export_format="GLB")
with open(report_path, "w") as f:
    json.dump(report, f, indent=1)
