"""Run inside Blender's Python: render an imported .glb (Cycles CPU, tiny frame, fixed seed) with or without the baker
add-on, to show that the add-on's node groups leave the untouched material's look unchanged.

Usage: python render_look.py ADDON_DIR|- IN.glb OUT.npy"""
import math
import sys

import bpy
import numpy as np

from blender_scene import add_sun, camera_in_front, cycles_exr, flat_world, render_pixels

addon, source, out = sys.argv[1:4]
bpy.ops.wm.read_factory_settings(use_empty=True)
if addon != "-":
    sys.path.insert(0, addon)
    import baker_blender
    baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
obj = next(o for o in scene.objects if o.type == "MESH" and not o.hide_render)
camera_in_front(scene, obj)
add_sun(scene, (math.radians(50), 0.0, math.radians(30)))
flat_world(scene, "grey", (0.05, 0.05, 0.05))
cycles_exr(scene, samples=4, resolution=48)
scene.cycles.seed = 1
np.save(out, render_pixels(scene, out + ".exr"))
