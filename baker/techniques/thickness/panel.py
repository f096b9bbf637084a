"""Preview panels of BAKER_thickness: the baked thickness as a false-colour map, and translucency lit from behind
(``runtime-shaders/baker_translucency.glsl``, RTR4 eq. 14.30 / GDC 2011)."""
from __future__ import annotations

import numpy as np

from baker.gltf.vertex_attributes import unpadded
from baker.preview.core import DrawItem, Panel, Scene
from baker.techniques.thickness.extension import ATTRIBUTE, ThicknessMaterial, read


class ScalarMapPanel(Panel):
    """False colour of a scalar attribute normalized by its range over the asset."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.range = (0.0, 1.0)

    def prepare(self, items) -> None:
        items = items.items if isinstance(items, Scene) else items
        # the scalar only (x): the padding of the blender attribute layout would pull the range down to 0
        values = np.concatenate([unpadded(i.attributes[self.attribute], 1) for i in items
                                 if self.attribute in i.attributes])
        self.range = (float(values.min()), float(max(values.max(), values.min() + 1e-12)))

    def uniforms(self, item: DrawItem) -> dict:
        return {"u_range": self.range}


class TranslucencyPanel(Panel):
    """Translucency with the material's eq. 14.30 parameters (defaults where the material has none)."""

    def read_item(self, doc, item: DrawItem) -> None:
        if item.material_index is not None:
            item.data["thickness"] = read(doc, item.material_index)

    def uniforms(self, item: DrawItem) -> dict:
        p = item.data.get("thickness") or ThicknessMaterial()
        return {
            "u_thickness.attenuationDistance": p.attenuation_distance,
            "u_thickness.distortion": p.distortion,
            "u_thickness.power": p.power,
            "u_thickness.scale": p.scale,
            "u_thickness.ambient": p.ambient,
            "u_thickness.subsurfaceColor": tuple(p.subsurface_color),
        }


PANELS = [
    ScalarMapPanel("thickness", f"thickness ({ATTRIBUTE})", (), "uniform vec2 u_range;",
                   "float t = clamp((scalar - u_range.x) / (u_range.y - u_range.x), 0.0, 1.0);\n"
                   "    color = mix(vec3(0.95, 0.35, 0.1), vec3(0.1, 0.3, 0.9), t);",
                   attribute=ATTRIBUTE, needs=(ATTRIBUTE,), order=10),
    TranslucencyPanel("translucency", "translucency, lit from behind", ("baker_translucency.glsl",),
                      "uniform BakerThickness u_thickness;",
                      "color = 0.05 * albedo * max(dot(N, u_light), 0.0)\n"
                      "          + baker_translucency(u_thickness, N, V, u_light, scalar);",
                      attribute=ATTRIBUTE, light="back", needs=(ATTRIBUTE,), order=20),
]
