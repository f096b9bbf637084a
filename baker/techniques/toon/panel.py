"""Preview panel of BAKER_toon_ramp: the toon ramp (or X-Toon map) indexed by N.L and the detail function
(``runtime-shaders/baker_toon.glsl``)."""
from __future__ import annotations

from baker.preview.core import DrawItem, Panel
from baker.techniques.toon.extension import read

XTOON_MODES = {"none": 0, "depth": 1, "orientation": 2}


class ToonPanel(Panel):
    """The ramp of the material's BAKER_toon_ramp by N.L, or the X-Toon map by N.L and depth / orientation."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["toon"] = read(doc, item.material_index)

    def applies(self, item):
        return super().applies(item) and item.data.get("toon") is not None

    def uniforms(self, item):
        ramp = item.data["toon"]
        return {"u_xtoon": XTOON_MODES.get(ramp.xtoon, 0), "u_depthRange": ramp.depth_range,
                "u_orientationPower": ramp.orientation_power}

    def textures(self, scene, ctx, item):
        return {"u_ramp": scene.texture(ctx, item.data["toon"].ramp_texture)}


PANELS = [
    ToonPanel("toon", "toon ramp", ("baker_toon.glsl",),
              "uniform sampler2D u_ramp;\nuniform int u_xtoon;\nuniform vec2 u_depthRange;\n"
              "uniform float u_orientationPower;",
              "float NdotL = dot(N, u_light);\n"
              "    float shade = u_xtoon == 0 ? baker_toon_ramp(u_ramp, NdotL)\n"
              "        : baker_xtoon(u_ramp, NdotL, u_xtoon == 1\n"
              "            ? baker_xtoon_detail_depth(length(u_eye - P), u_depthRange.x, u_depthRange.y)\n"
              "            : baker_xtoon_detail_orientation(N, V, u_orientationPower));\n"
              "    color = albedo * shade;",
              order=40),
]
