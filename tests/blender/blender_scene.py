"""Scene setup the Blender render helpers share (render_look.py, render_translucency.py; run inside Blender's Python,
imported from the helper's own folder): a camera framing an object from -Y, a sun, a flat world, a small Cycles CPU
frame rendered to 32-bit EXR and read back as pixels."""
import math

import bpy
import numpy as np
from mathutils import Vector


def camera_in_front(scene, obj):
    """A scene camera two bounding-box sizes in front (-Y) of `obj`'s centre, looking along +Y."""
    corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    center = sum(corners, Vector()) / 8
    size = max((max(c[i] for c in corners) - min(c[i] for c in corners)) for i in range(3))
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.location = center - Vector((0.0, 2.0 * size, 0.0))
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)  # looks along +Y
    scene.camera = camera
    return camera


def add_sun(scene, rotation_euler):
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.rotation_euler = rotation_euler
    return sun


def flat_world(scene, name, color):
    world = bpy.data.worlds.new(name)
    world.color = color
    scene.world = world
    return world


def cycles_exr(scene, samples, resolution):
    """Cycles on the CPU, `samples` per pixel, no denoising, a square frame of `resolution`, written as 32-bit EXR."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"


def render_pixels(scene, path):
    """Render the scene to the EXR `path` and read it back: float32 RGBA, rows bottom-up as Blender stores them."""
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], np.float32).reshape(image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels
