"""Run inside Blender's Python: import baker hair cards (.glb) with the stock importer (or with the baker add-on when
ADDON_DIR is not "-"), and render them orthographically along -Y (Blender; glTF +Z towards the camera) with Cycles
at pixel centres on a transparent film: the alpha channel is the cards' coverage after the material's alpha clip.

Usage: python render_cards.py ADDON_DIR|- IN.glb OUT.npz CENTER_X CENTER_Z HALF_SIZE RESOLUTION"""
import sys

import bpy
import numpy as np

from blender_scene import add_sun, cycles_exr, flat_world, render_pixels

addon, source, out = sys.argv[1:4]
cx, cz, half, resolution = float(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6]), int(sys.argv[7])
bpy.ops.wm.read_factory_settings(use_empty=True)
if addon != "-":
    sys.path.insert(0, addon)
    import baker_blender  # noqa: E402

    baker_blender.enable()
bpy.ops.import_scene.gltf(filepath=source)
scene = bpy.context.scene
meshes = [o for o in scene.objects if o.type == "MESH"]
obj = meshes[0]
material = obj.data.materials[0]
tree = material.node_tree
principled = next(n for n in tree.nodes if n.type == "BSDF_PRINCIPLED")
report = {
    "meshes": len(meshes), "vertices": len(obj.data.vertices), "polygons": len(obj.data.polygons),
    "alpha_linked": principled.inputs["Alpha"].is_linked, "tangent_linked": principled.inputs["Tangent"].is_linked,
    "images": sorted(i.name for i in bpy.data.images),
    "uv_maps": [uv.name for uv in obj.data.uv_layers],
}
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.data.type = "ORTHO"
camera.data.ortho_scale = 2.0 * half
camera.location = (cx, -10.0, cz)  # glTF (x, y, z) is Blender (x, -z, y): the camera sits on glTF +Z
camera.rotation_euler = (np.pi / 2, 0.0, 0.0)  # looks along +Y, image up = +Z
camera.data.clip_end = 100.0
scene.camera = camera
add_sun(scene, (0.6, 0.0, 0.3)).data.energy = 3.0
flat_world(scene, "grey", (0.2, 0.2, 0.2))
cycles_exr(scene, samples=4, resolution=resolution)
scene.render.film_transparent = True
scene.cycles.filter_width = 0.01
pixels = render_pixels(scene, out + ".exr")
np.savez(out, pixels=pixels, report=np.array(repr(report)))
