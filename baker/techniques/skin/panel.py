"""Preview panel of BAKER_skin_lut: Penner's pre-integrated skin (``runtime-shaders/baker_skin.glsl``), the LUT by
N.L and the baked curvature (or the curvature estimated from screen-space derivatives when there is none)."""
from __future__ import annotations

from baker.preview.core import DrawItem, Panel
from baker.techniques.skin.extension import read


class SkinPanel(Panel):
    """Penner's pre-integrated skin: the LUT texture by N.L and the curvature attribute the material names."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["skin"] = read(doc, item.material_index)

    def applies(self, item):
        return super().applies(item) and item.data.get("skin") is not None

    def attribute_of(self, item):
        return item.data["skin"].curvature_attribute

    def uniforms(self, item):
        skin = item.data["skin"]
        return {
            "u_skin.curvatureRange": skin.curvature_range,
            "u_skin.curvatureScale": skin.curvature_scale,
            "u_skin.penumbraWidthRange": skin.penumbra_width_range,
            "u_skin.normalBlend": skin.normal_blend,
            "u_skin.wrap": skin.wrap,
            "u_skin.scatterWidth": skin.scatter_width,
            "u_skin.scatterColor": skin.scatter_color,
            "u_hasCurvature": int(self.attribute_of(item) in item.attributes),
        }

    def textures(self, scene, ctx, item):
        skin = item.data["skin"]
        return {"u_lut": scene.texture(ctx, skin.lut_texture, srgb=skin.encoding == "srgb")}


PANELS = [
    SkinPanel("skin", "pre-integrated skin (LUT x curvature)", ("baker_skin.glsl",),
              "uniform BakerSkin u_skin;\nuniform sampler2D u_lut;\nuniform int u_hasCurvature;",
              "float k = u_hasCurvature != 0 ? scalar : baker_skin_curvature_from_derivatives(fwidth(N), fwidth(P));\n"
              "    color = vec3(0.8) * (0.15 + 0.85 * baker_skin_diffuse(u_skin, u_lut, N, N, u_light, k));",
              attribute="_CURVATURE", order=30),
]
