"""Preview panel of BAKER_caustics: what a runtime draws (``runtime-shaders/baker_caustics.glsl``, as the three.js
and Babylon.js hosts call it), at a fixed time of the loop.

The panel is the Lambert reference with the caustics applied by the runtime's own calls, with the material's
values as written: the frames projected along ``projectionDirection`` from the world position with the baked tile
size (``baker_caustics_uv``), faded by the point's depth below ``waterLevel`` (``baker_caustics_fade``: nothing
above the water), and the key light's Lambert part of the reference redistributed by the irradiance
(``baker_caustics_apply``), as the hosts redistribute their directional lights' Lambert light, under the key light
from the front (the viewer's key light; the sheet's grazing side light would leave the side of an asset standing on
the ground dark, where the caustics barely show). What the panel shows
on an asset is what a runtime shows on it: a water level that leaves the asset dry shows no caustics here either
(baker's default puts the water over the asset, :func:`baker.techniques.caustics.options.water_over`)."""
from __future__ import annotations

import numpy as np

from baker.preview.core import DrawItem, Panel, Scene, host_text
from baker.techniques.caustics.extension import read

LOOP_FRACTION = 0.37  # the still's time, as a fraction of the period: between two frames, so the blend shows too
# the Lambert reference (baker.preview.core.LAMBERT): ambient + key light, the key light being the sun the caustics
# redistribute
AMBIENT, KEY = 0.15, 0.85


class CausticsPanel(Panel):
    """Frames of the material's BAKER_caustics at t = 0.37 period, blended and applied to the reference shade."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.extent = 0.0

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["caustics"] = caustics = read(doc, item.material_index)
            if caustics is not None:  # PNG colour type (IHDR byte 25): 2 and 6 carry RGB, 0 and 4 gray
                source = doc.json["textures"][caustics.frame_textures[0]]["source"]
                item.data["caustics_rgb"] = float(doc.image_bytes(source)[25:26] in (b"\x02", b"\x06"))

    def applies(self, item):
        return super().applies(item) and item.data.get("caustics") is not None

    def prepare(self, scene: Scene) -> None:
        points = scene.points()
        self.extent = float(np.linalg.norm(points.max(0) - points.min(0))) if len(points) else 0.0

    def describe(self, scene: Scene) -> str:
        self.prepare(scene)
        baked = sorted({(i.data["caustics"].tile_size, i.data["caustics"].water_level) for i in scene.items
                        if self.applies(i)})
        if not baked:
            return self.label
        tile, level = baked[0]
        return f"{self.label} (tile {tile:.3g}, asset {self.extent:.3g}, water at y {level:.3g})"

    def frames(self, caustics):
        count = len(caustics.frame_textures)
        position = LOOP_FRACTION * count
        first = int(position) % count
        return first, (first + 1) % count, position - int(position)

    def uniforms(self, item):
        c = item.data["caustics"]
        _, _, blend = self.frames(c)
        return {"u_baker_caustics_on": 1.0, "u_bakerCausticsProjection": c.projection_direction,
                "u_bakerCausticsWaterLevel": c.water_level, "u_bakerCausticsDepth": c.depth,
                "u_bakerCausticsTileSize": c.tile_size, "u_bakerCausticsScale": c.intensity_scale,
                "u_bakerCausticsStrength": c.strength, "u_bakerCausticsFadeDistance": c.fade_distance,
                "u_bakerCausticsBlend": blend}

    def textures(self, scene, ctx, item):
        c = item.data["caustics"]
        first, following, _ = self.frames(c)
        return {"u_bakerCausticsFirst": rgb_texture(scene, ctx, c.frame_textures[first]),
                "u_bakerCausticsNext": rgb_texture(scene, ctx, c.frame_textures[following])}


def rgb_texture(scene: Scene, ctx, texture_index: int):
    """A frame as an RGB texture (REPEAT, LINEAR), a gray frame's value in all three channels: the hosts' stage
    reads .rgb, as browsers decode a gray PNG."""
    import moderngl

    key = ("gl-rgb", id(ctx), texture_index)
    if key not in scene.cache:
        pixels = scene.image(texture_index)
        pixels = np.ascontiguousarray(np.repeat(pixels[..., :1], 3, axis=2) if pixels.shape[2] < 3 else pixels[..., :3])
        h, w, _ = pixels.shape
        tex = ctx.texture((w, h), 3, pixels.tobytes(), dtype="f4")
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
        tex.repeat_x = tex.repeat_y = True
        scene.cache[key] = tex
    return scene.cache[key]


# the web hosts' stage itself (runtime-shaders/hosts/web/surface_caustics.glsl), on the Lambert reference: its key
# light is the sunlit part the stage redistributes; the reference is the whole pixel (no other light), so the stage's
# baker_caustics_headroom compresses the light the caustic adds into the headroom above the reference's shade, as a
# highlight instead of a flat white (the sheet is 8 bits, no tone mapping)
STAGE = host_text("web/surface_caustics.glsl")

PANELS = [
    CausticsPanel("caustics", "caustics", ("baker_caustics.glsl",),
                  "uniform float u_baker_caustics_on;\nuniform sampler2D u_bakerCausticsFirst;\n"
                  "uniform sampler2D u_bakerCausticsNext;\nuniform vec3 u_bakerCausticsProjection;\n"
                  "uniform float u_bakerCausticsWaterLevel;\nuniform float u_bakerCausticsDepth;\n"
                  "uniform float u_bakerCausticsTileSize;\nuniform float u_bakerCausticsScale;\n"
                  "uniform float u_bakerCausticsStrength;\nuniform float u_bakerCausticsFadeDistance;\n"
                  "uniform float u_bakerCausticsBlend;\n",
                  "float lambert = max(dot(N, u_light), 0.0);\n"
                  "    vec3 bakerWorldPosition = P;\n"
                  f"    vec3 bakerSunLight = albedo * {KEY} * lambert;\n"
                  f"    vec3 reference = albedo * ({AMBIENT} + {KEY} * lambert);\n"
                  "    vec3 bakerDiffuse = reference;\n"
                  "    vec3 bakerOtherLight = vec3(0.0);\n"
                  f"    {STAGE}\n"
                  "    color = bakerDiffuse;",
                  light="front", order=45),
]
