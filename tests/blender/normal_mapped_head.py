"""Run inside Blender's Python (the bpy venv): make a normal-mapped head and export it with Blender's own glTF
exporter, TANGENT included: Suzanne, subdivided twice, smooth, 0.27 m wide (head-sized, in metres), with a
procedural tangent-space normal map (crossing ridges a few millimetres apart, like skin creases) on a Principled
BSDF through a Normal Map node.

Usage: python normal_mapped_head.py OUT.glb [SIZE]"""
import sys

import bpy
import numpy as np


def main(out: str, size: int) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(size=0.2, calc_uvs=True)
    head = bpy.context.active_object
    modifier = head.modifiers.new("subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 2
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    bpy.ops.object.shade_smooth()

    # a height field h(u, v) of two crossing ridge sets; the normal map holds (-dh/du, -dh/dv, 1) normalized, in
    # Blender's image convention (row 0 at the bottom, +Y along +v)
    u, v = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size)
    du = 0.35 * np.cos(2 * np.pi * 48 * (u + 0.3 * v)) + 0.2 * np.cos(2 * np.pi * 90 * v)
    dv = 0.35 * 0.3 * np.cos(2 * np.pi * 48 * (u + 0.3 * v)) + 0.2 * np.cos(2 * np.pi * 90 * v)
    normal = np.stack([-du, -dv, np.ones_like(du)], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    rgba = np.concatenate([(normal + 1) / 2, np.ones((size, size, 1))], -1).astype(np.float32)
    image = bpy.data.images.new("skin_normal", size, size, alpha=False)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(rgba.reshape(-1))
    image.file_format = "PNG"
    image.pack()

    material = bpy.data.materials.new("skin")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.55, 0.45, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.5
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    normal_map = nodes.new("ShaderNodeNormalMap")
    links.new(texture.outputs["Color"], normal_map.inputs["Color"])
    links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    head.data.materials.append(material)

    bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_tangents=True, export_normals=True,
                              export_texcoords=True, export_materials="EXPORT", export_yup=True)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 512)
