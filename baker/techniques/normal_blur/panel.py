"""Preview panel of BAKER_normal_blur (``runtime-shaders/baker_normal_blur.glsl``): per-channel Lambert with the
three diffuse normal maps, in a tangent frame from screen-space derivatives (the preview passes no TANGENT)."""
from __future__ import annotations

import numpy as np

from baker.preview.core import DrawItem, Panel
from baker.techniques.normal_blur.extension import read


FLAT = 0.02  # largest deviation of a decoded diffuse normal from +Z that counts as a flat map


class NormalBlurPanel(Panel):
    """The diffuse term with the blurred normals: red softest, as skin shades."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["normal_blur"] = read(doc, item.material_index)

    def applies(self, item):
        blur = item.data.get("normal_blur")
        return super().applies(item) and blur is not None and blur.texcoord in item.texcoords

    def describe(self, scene) -> str:
        """The label, saying so when the diffuse normal maps are flat (no normal map detail to blur: the panel is
        the reference's Lambert)."""
        textures = {t for i in scene.items if self.applies(i) for t in i.data["normal_blur"].diffuse_textures}
        flat = all(float(np.abs(scene.image(t)[..., :3] * 2.0 - 1.0 - np.array([0.0, 0.0, 1.0])).max()) < FLAT
                   for t in textures) if textures else False
        return f"{self.label} - flat normals: no normal map detail to blur" if flat else self.label

    def texcoord(self, item):
        return item.data["normal_blur"].texcoord

    def textures(self, scene, ctx, item):
        red, green, blue = item.data["normal_blur"].diffuse_textures
        return {"u_normalBlurRed": scene.texture(ctx, red, repeat=True),
                "u_normalBlurGreen": scene.texture(ctx, green, repeat=True),
                "u_normalBlurBlue": scene.texture(ctx, blue, repeat=True)}


PANELS = [
    NormalBlurPanel("normal-blur", "diffuse normals blurred on the surface (R, G, B)", ("baker_normal_blur.glsl",),
                    "uniform sampler2D u_normalBlurRed;\nuniform sampler2D u_normalBlurGreen;\n"
                    "uniform sampler2D u_normalBlurBlue;",
                    "mat3 tbn = baker_normal_blur_derivative_frame(Ng, dFdx(P), dFdy(P), dFdx(v_uv), dFdy(v_uv));\n"
                    "    vec3 lambert = baker_normal_blur_lambert(tbn, texture(u_normalBlurRed, v_uv).rgb,\n"
                    "        texture(u_normalBlurGreen, v_uv).rgb, texture(u_normalBlurBlue, v_uv).rgb, u_light, 1.0);\n"
                    "    color = albedo * (0.15 + 0.85 * lambert);",
                    inputs="in vec2 v_uv;", order=32),
]
