"""Run inside Blender's Python (the bpy venv): Suzanne as a Blender user exports her, with Blender's own glTF exporter:
the default monkey (2 m), a subdivision modifier (level 2) applied, smooth shading, and a Principled BSDF at its
defaults but for the base colour. The asset of tests/test_preview_runtime_agreement.py's Blender export.

Usage: python principled_suzanne.py OUT.glb"""
import sys

import bpy


def main(out: str) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
    monkey = bpy.context.active_object
    modifier = monkey.modifiers.new("subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 2
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    bpy.ops.object.shade_smooth()
    material = bpy.data.materials.new("principled")
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)  # Blender's default base colour
    bsdf.inputs["Roughness"].default_value = 0.5
    monkey.data.materials.append(material)
    bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_normals=True, export_texcoords=True,
                              export_materials="EXPORT", export_yup=True)


if __name__ == "__main__":
    main(sys.argv[1])
