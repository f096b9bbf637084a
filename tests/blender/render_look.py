"""Run inside Blender's Python: render an imported .glb (Cycles CPU, tiny frame, fixed seed) with or without the baker
add-on, to show that the add-on's node groups leave the untouched material's look unchanged.

Usage: python render_look.py ADDON_DIR|- IN.glb OUT.npy"""
import math
import sys

import bpy
import numpy as np
from mathutils import Vector

addon, source, out = sys.argv[1:4]
bpy.ops.wm.read_factory_settings(use_empty=True)
if addon != "-":
    sys.path.insert(0, addon)
    import baker_blender
    baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
obj = next(o for o in scene.objects if o.type == "MESH" and not o.hide_render)
corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
center = sum(corners, Vector()) / 8
size = max((max(c[i] for c in corners) - min(c[i] for c in corners)) for i in range(3))
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.location = center - Vector((0.0, 2.0 * size, 0.0))
camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
scene.camera = camera
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
scene.collection.objects.link(sun)
sun.rotation_euler = (math.radians(50), 0.0, math.radians(30))
world = bpy.data.worlds.new("grey")
world.color = (0.05, 0.05, 0.05)
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 4
scene.cycles.seed = 1
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 48
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out + ".exr"
bpy.ops.render.render(write_still=True)
image = bpy.data.images.load(out + ".exr")
np.save(out, np.array(image.pixels[:], np.float32).reshape(image.size[1], image.size[0], 4))
