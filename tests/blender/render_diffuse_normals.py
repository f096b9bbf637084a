"""Run inside Blender's Python: import a normal-blur-baked .glb with the baker add-on, switch its material to the
BAKER Diffuse Normals group (the add-on's Mix Shader factor to 1), light it with a sun from the front left, render a
small Cycles CPU frame; again with the three Normal Map nodes fed the material's own (sharp) normal map instead of
the blurred maps (the control: the same group, unblurred).

Usage: python render_diffuse_normals.py ADDON_DIR IN.glb OUT.npz"""
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
mat = obj.data.materials[0]
tree = mat.node_tree
tree.nodes["BAKER mix diffuse normals"].inputs["Fac"].default_value = 1.0
camera = camera_in_front(scene, obj)
camera.data.lens = 50
sun = add_sun(scene, (1.1, 0.0, -0.6))
sun.data.energy = 4.0
flat_world(scene, "black", (0.0, 0.0, 0.0))
cycles_exr(scene, samples=32, resolution=128)
scene.cycles.seed = 1
scene.render.film_transparent = True
scene.view_settings.view_transform = "Standard"
blurred = render_pixels(scene, out + ".blurred.exr")
# control: the material's own normal map (the image the importer put on its Normal Map node) into all three channels
own = next(n for n in tree.nodes if n.type == "NORMAL_MAP" and not n.name.startswith("BAKER"))
sharp_image = own.inputs["Color"].links[0].from_node.image
for channel in ("red", "green", "blue"):
    node = tree.nodes[f"BAKER diffuse normal {channel}"]
    node.inputs["Color"].links[0].from_node.image = sharp_image
sharp = render_pixels(scene, out + ".sharp.exr")
np.savez(out, blurred=blurred, sharp=sharp)
