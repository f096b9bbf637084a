"""Run inside Blender's Python: import a baked .glb with the baker add-on, make its surfaces flat white and render
Freestyle's edge-mark lines (black, nothing else selected) in Cycles twice, with the add-on's marks and with them
cleared; write the number of marked edges and of dark (line) pixels of each render to a JSON file.

Usage: python render_freestyle.py ADDON_DIR IN.glb REPORT.json"""
import json
import sys

import bpy
import numpy as np
from mathutils import Vector

addon, source, report_path = sys.argv[1:4]
sys.path.insert(0, addon)
import baker_blender  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
meshes = [o for o in scene.objects if o.type == "MESH"]
corners = np.array([o.matrix_world @ Vector(c) for o in meshes for c in o.bound_box])
centre, radius = corners.mean(axis=0), float(np.linalg.norm(corners - corners.mean(axis=0), axis=1).max())
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.location = Vector(centre) + Vector((1.0, -1.6, 1.0)).normalized() * radius * 3.2
camera.rotation_euler = (Vector(centre) - camera.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera
scene.render.engine = "CYCLES"
scene.cycles.samples = 1
scene.cycles.device = "CPU"
scene.render.resolution_x = scene.render.resolution_y = 128
scene.render.resolution_percentage = 100
scene.render.film_transparent = True
scene.view_settings.view_transform = "Standard"
white = bpy.data.materials.new("white")  # a flat white surface: every dark pixel is a Freestyle stroke
white.use_nodes = True
white.node_tree.nodes.clear()
emission = white.node_tree.nodes.new("ShaderNodeEmission")
emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
output = white.node_tree.nodes.new("ShaderNodeOutputMaterial")
white.node_tree.links.new(emission.outputs[0], output.inputs["Surface"])
for obj in meshes:
    obj.data.materials.clear()
    obj.data.materials.append(white)
scene.render.use_freestyle = True
scene.render.line_thickness_mode = "ABSOLUTE"
scene.render.line_thickness = 1.5
layer = scene.view_layers[0]
layer.use_freestyle = True
settings = layer.freestyle_settings
settings.mode = "EDITOR"
lineset = settings.linesets[0] if settings.linesets else settings.linesets.new("marks")
lineset.select_by_visibility = False
lineset.select_by_edge_types = True
for flag in ("silhouette", "border", "crease", "ridge_valley", "suggestive_contour", "material_boundary", "contour",
             "external_contour"):
    setattr(lineset, "select_" + flag, False)
lineset.select_edge_mark = True
lineset.linestyle = lineset.linestyle or bpy.data.linestyles.new("marks")
lineset.linestyle.color = (0.0, 0.0, 0.0)


def line_pixels(path) -> int:
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], np.float32).reshape(-1, 4)
    return int(((pixels[:, 3] > 0.5) & (pixels[:, :3].max(axis=1) < 0.5)).sum())


report = {"marked": sum(int(np.count_nonzero([e.use_freestyle_mark for e in o.data.edges])) for o in meshes)}
report["with_marks"] = line_pixels(report_path + ".marked.png")
for obj in meshes:
    obj.data.edges.foreach_set("use_freestyle_mark", np.zeros(len(obj.data.edges), bool))
report["without_marks"] = line_pixels(report_path + ".cleared.png")
with open(report_path, "w") as f:
    json.dump(report, f)
