"""Preview panel of BAKER_caustics: the material's caustic frames projected in world space along the refracted sun
direction and added to a Lambert shade (``runtime-shaders/baker_caustics.glsl``), at a fixed time of the loop.

The depth fade is left out (fade 1): a preview shows the pattern on any asset, whatever its height below
``waterLevel``."""
from __future__ import annotations

from baker.preview.core import DrawItem, Panel
from baker.techniques.caustics.extension import read

LOOP_FRACTION = 0.37  # the still's time, as a fraction of the period: between two frames, so the blend shows too


class CausticsPanel(Panel):
    """Frames of the material's BAKER_caustics at t = 0.37 period, blended and added to the lit colour."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["caustics"] = caustics = read(doc, item.material_index)
            if caustics is not None:  # PNG colour type (IHDR byte 25): 2 and 6 carry RGB, 0 and 4 gray
                source = doc.json["textures"][caustics.frame_textures[0]]["source"]
                item.data["caustics_rgb"] = float(doc.image_bytes(source)[25:26] in (b"\x02", b"\x06"))

    def applies(self, item):
        return super().applies(item) and item.data.get("caustics") is not None

    def frames(self, caustics):
        count = len(caustics.frame_textures)
        position = LOOP_FRACTION * count
        first = int(position) % count
        return first, (first + 1) % count, position - int(position)

    def uniforms(self, item):
        c = item.data["caustics"]
        _, _, blend = self.frames(c)
        return {"u_projection": c.projection_direction, "u_waterLevel": c.water_level, "u_depth": c.depth,
                "u_tileSize": c.tile_size, "u_scale": c.intensity_scale, "u_strength": c.strength,
                "u_blend": blend, "u_rgb": item.data["caustics_rgb"]}

    def textures(self, scene, ctx, item):
        c = item.data["caustics"]
        first, following, _ = self.frames(c)
        return {"u_first": scene.texture(ctx, c.frame_textures[first], repeat=True),
                "u_next": scene.texture(ctx, c.frame_textures[following], repeat=True)}


PANELS = [
    CausticsPanel("caustics", "caustics", ("baker_caustics.glsl",),
                  "uniform sampler2D u_first;\nuniform sampler2D u_next;\nuniform vec3 u_projection;\n"
                  "uniform float u_waterLevel;\nuniform float u_depth;\nuniform float u_tileSize;\n"
                  "uniform float u_scale;\nuniform float u_strength;\nuniform float u_blend;\nuniform float u_rgb;",
                  "vec2 uv = baker_caustics_uv(P, u_projection, u_waterLevel, u_depth, u_tileSize);\n"
                  "    vec3 irradiance = baker_caustics_irradiance(u_first, u_next, uv, u_blend, u_scale, u_rgb);\n"
                  "    float lambert = max(dot(N, u_light), 0.0);\n"
                  "    color = baker_caustics_apply(vec3(0.1 + 0.3 * lambert + 0.3), vec3(0.3), irradiance,\n"
                  "                                 u_strength, 1.0);",
                  order=45),
]
