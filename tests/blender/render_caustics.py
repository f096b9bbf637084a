"""Run inside Blender's Python: import a caustics-baked floor (.glb) with the baker add-on and render it from straight
above (orthographic, the 4 m floor filling the frame) with Cycles CPU at pixel centres (a tiny filter): the imported
material under a sun straight down (lit), the same with the caustic emission unplugged from the add-on's Add Shader
(control), then the BAKER Caustics group's Irradiance output as emission.

Usage: python render_caustics.py ADDON_DIR IN.glb OUT.npz"""
import sys

import bpy
import numpy as np

from blender_scene import add_sun, cycles_exr, flat_world, render_pixels

addon, source, out = sys.argv[1:4]
sys.path.insert(0, addon)
import baker_blender  # noqa: E402
from baker_blender.nodes import CAUSTICS_ADD  # noqa: E402

RESOLUTION = 64
bpy.ops.wm.read_factory_settings(use_empty=True)
baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
obj = next(o for o in scene.objects if o.type == "MESH")
tree = obj.data.materials[0].node_tree
group, add = tree.nodes["BAKER Caustics"], tree.nodes[CAUSTICS_ADD]
output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output)
surface_is_add = output.inputs["Surface"].links[0].from_node == add

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.data.type = "ORTHO"
camera.data.ortho_scale = 4.0
camera.location = (0.0, 0.0, 5.0)  # looks down -Z, image up = +Y
scene.camera = camera
sun = add_sun(scene, (0.0, 0.0, 0.0))  # light travels along -Z
sun.data.energy = 3.0
flat_world(scene, "black", (0.0, 0.0, 0.0))
cycles_exr(scene, samples=16, resolution=RESOLUTION)
scene.view_settings.view_transform = "Standard"
scene.cycles.filter_width = 0.01  # pixel centres: comparable with values computed at them
lit = render_pixels(scene, out + ".lit.exr")
tree.links.remove(add.inputs[1].links[0])
control = render_pixels(scene, out + ".control.exr")
emission = tree.nodes.new("ShaderNodeEmission")
tree.links.new(group.outputs["Irradiance"], emission.inputs["Color"])
tree.links.new(emission.outputs[0], output.inputs["Surface"])
scene.cycles.samples = 1
irradiance = render_pixels(scene, out + ".irradiance.exr")
np.savez(out, lit=lit, control=control, irradiance=irradiance, surface_is_add=surface_is_add,
         image=group.inputs["Color"].links[0].from_node.image.name)
