"""Run by Blender's Python (bpy 4.5): the peer of benchmarks/normal_transfer.py. Imports the low and the high OBJ
(no axis conversion: Blender's object space is the files' space), and bakes Cycles' Selected-to-Active object-space
normal map of the high onto the low's UVs (``bpy.ops.object.bake(type="NORMAL", use_selected_to_active=True,
cage_extrusion=D, normal_space="OBJECT")``) into a float image on the CPU, 1 render sample; saves it as .npy (rows
top-down, glTF's UV origin) and prints the bake call's own wall and CPU seconds (every thread).

Usage: python normal_transfer_cycles.py LOW.obj HIGH.obj SIZE CAGE_EXTRUSION OUT.npy"""
import sys
import time

import bpy
import numpy as np

low_path, high_path, size, extrusion, out = sys.argv[1:6]
size, extrusion = int(size), float(extrusion)

bpy.ops.wm.read_factory_settings(use_empty=True)
objects = []
for path in (low_path, high_path):
    before = set(bpy.context.scene.objects)
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    objects.append(next(o for o in bpy.context.scene.objects if o not in before))
low, high = objects
for obj in objects:  # smooth shading: both bakers interpolate vertex normals
    for polygon in obj.data.polygons:
        polygon.use_smooth = True
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.render.threads_mode = "AUTO"

material = bpy.data.materials.new("bake_target")
material.use_nodes = True
image = bpy.data.images.new("bake", size, size, alpha=False, float_buffer=True)
target = material.node_tree.nodes.new("ShaderNodeTexImage")
target.image = image
material.node_tree.nodes.active = target
low.data.materials.clear()
low.data.materials.append(material)
bpy.ops.object.select_all(action="DESELECT")
high.select_set(True)
low.select_set(True)
bpy.context.view_layer.objects.active = low
start, cpu_start = time.perf_counter(), time.process_time()
bpy.ops.object.bake(type="NORMAL", use_selected_to_active=True, cage_extrusion=extrusion, normal_space="OBJECT",
                    margin=16, use_clear=True)
print(f"BAKE_SECONDS {time.perf_counter() - start:.3f} {time.process_time() - cpu_start:.3f}")
pixels = np.empty(size * size * 4, np.float32)
image.pixels.foreach_get(pixels)
np.save(out, np.flipud(pixels.reshape(size, size, 4)[..., :3]))
