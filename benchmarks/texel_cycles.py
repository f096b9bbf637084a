"""Run by Blender's Python (bpy 4.5): the texture-bake peer of benchmarks/texel.py. Imports an OBJ, bakes Cycles'
inside ambient occlusion (Ambient Occlusion node, `inside` and `only_local` on, `samples` rays per shading point,
through an Emission shader) into a float image of the mesh's own UV layout with `bpy.ops.object.bake(type="EMIT")`
on the CPU, and saves the image as .npy, rows top-down (glTF's UV origin). The work per texel is the same as
baker's thickness texture: `samples` rays into the inside of the surface; Cycles keeps the fraction that miss within
`distance`, baker the mean chord.

Usage: python texel_cycles.py MESH.obj SIZE SAMPLES RENDER_SAMPLES DISTANCE OUT.npy"""
import sys

import bpy
import numpy as np

mesh_path, size, samples, render_samples, distance, out = sys.argv[1:7]
size, samples, render_samples, distance = int(size), int(samples), int(render_samples), float(distance)

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=mesh_path)
scene = bpy.context.scene
obj = next(o for o in scene.objects if o.type == "MESH")
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = render_samples
scene.cycles.use_denoising = False
scene.render.threads_mode = "AUTO"

material = bpy.data.materials.new("inside_ao")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
nodes.clear()
ao = nodes.new("ShaderNodeAmbientOcclusion")
ao.inside = True
ao.only_local = True
ao.samples = samples
ao.inputs["Distance"].default_value = distance
emission = nodes.new("ShaderNodeEmission")
links.new(ao.outputs["AO"], emission.inputs["Strength"])
output = nodes.new("ShaderNodeOutputMaterial")
links.new(emission.outputs["Emission"], output.inputs["Surface"])
image = bpy.data.images.new("bake", size, size, alpha=False, float_buffer=True)
target = nodes.new("ShaderNodeTexImage")
target.image = image
nodes.active = target
obj.data.materials.clear()
obj.data.materials.append(material)
bpy.context.view_layer.objects.active = obj
obj.select_set(True)
bpy.ops.object.bake(type="EMIT", margin=0, use_clear=True)

pixels = np.empty(size * size * 4, np.float32)
image.pixels.foreach_get(pixels)
# Blender's image rows run bottom-up (v = 0 first); glTF's UV origin is the top-left corner
np.save(out, np.flipud(pixels.reshape(size, size, 4)[..., 0]))
