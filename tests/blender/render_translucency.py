"""Run inside Blender's Python: import a thickness-baked .glb with the baker add-on, switch its material to the
BAKER Translucency group (the add-on's Mix Shader factor to 1), light it from behind with a sun, render a small
Cycles CPU frame; again with the group's thickness at 0 (the control); then the baked thickness itself (the same
attribute as emission) from the same camera.

Usage: python render_translucency.py ADDON_DIR IN.glb OUT.npz"""
import math
import sys

import bpy
import numpy as np

from blender_scene import add_sun, camera_in_front, cycles_exr, flat_world, render_pixels

addon, source, out = sys.argv[1:4]
sys.path.insert(0, addon)
import baker_blender  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
obj = next(o for o in scene.objects if o.type == "MESH")
obj.visible_shadow = False  # the runtime term has no self-shadowing: the back faces must not occlude the sun
mat = obj.data.materials[0]
tree = mat.node_tree
mix = tree.nodes["BAKER mix translucency"]
mix.inputs["Fac"].default_value = 1.0
group = tree.nodes["BAKER Translucency"]
group.inputs["Ambient"].default_value = 0.0

camera = camera_in_front(scene, obj)
camera.data.lens = 50
sun = add_sun(scene, (-math.pi / 2, 0.0, 0.0))  # light travels along -Y: from behind the object toward the camera
sun.data.energy = 5.0
flat_world(scene, "black", (0.0, 0.0, 0.0))
cycles_exr(scene, samples=16, resolution=64)
scene.render.film_transparent = True
scene.view_settings.view_transform = "Standard"


lit = render_pixels(scene, out + ".lit.exr")
# control: the same light and group with zero thickness (transmittance 1 everywhere): lit / control = exp(-t / d)
for link in list(group.inputs["Thickness"].links):
    tree.links.remove(link)
group.inputs["Thickness"].default_value = 0.0
control = render_pixels(scene, out + ".control.exr")
# the thickness itself, same camera: an emission of the attribute's x
output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output)
attribute = tree.nodes.new("ShaderNodeAttribute")
attribute.attribute_type = "GEOMETRY"
attribute.attribute_name = "_THICKNESS"
emission = tree.nodes.new("ShaderNodeEmission")
tree.links.new(attribute.outputs["Vector"], emission.inputs["Color"])
tree.links.new(emission.outputs[0], output.inputs["Surface"])
scene.cycles.samples = 4
thickness = render_pixels(scene, out + ".thickness.exr")
np.savez(out, lit=lit, control=control, thickness=thickness[..., 0], alpha=thickness[..., 3],
         attenuation=group.inputs["Attenuation Distance"].default_value)
